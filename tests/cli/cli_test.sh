#!/usr/bin/env bash
# The command-line contract: outputs, exit codes and one-line errors. $SNERT is the binary.
set -u
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passes=0

pass() { passes=$((passes + 1)); }
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect_exit CODE PATTERN -- command...: exit code and a stderr line matching PATTERN.
expect_exit() {
    local code=$1 pattern=$2
    shift 3
    "$@" >"$tmp/out" 2>"$tmp/err"
    local rc=$?
    if [ "$rc" -ne "$code" ]; then fail "exit $rc (want $code): $*"; cat "$tmp/err"; return; fi
    if [ -n "$pattern" ] && ! grep -qE -- "$pattern" "$tmp/err"; then
        fail "stderr of '$*' lacks /$pattern/:"; cat "$tmp/err"; return
    fi
    # The error is one line, "snert COMMAND: ...", and the last one (informational lines such
    # as the description of a loaded volume may come before it).
    if [ "$code" -ne 0 ] && { [ "$(grep -cE '^snert [a-z0-9]+: ' "$tmp/err")" -ne 1 ] ||
        ! tail -n 1 "$tmp/err" | grep -qE '^snert [a-z0-9]+: '; }; then
        fail "error of '$*' is not one line:"; cat "$tmp/err"; return
    fi
    pass
}

# Usage errors: exit 2, one line.
expect_exit 2 "unknown command" -- "$SNERT" frobnicate
expect_exit 2 "unknown option --bogus" -- "$SNERT" compare phantom:sphere --bogus 1
expect_exit 2 "unknown phantom 'cube'" -- "$SNERT" compare phantom:cube
expect_exit 2 "--size must be an integer in 8..1024" -- "$SNERT" compare phantom:sphere --size 4
expect_exit 2 "--iterations must be an integer" -- "$SNERT" compare phantom:sphere --iterations x
expect_exit 2 "--mode must be one of" -- "$SNERT" compare phantom:sphere --mode fast
expect_exit 2 "missing input" -- "$SNERT" compare
expect_exit 2 "needs a value" -- "$SNERT" compare phantom:sphere --iso
expect_exit 2 "missing --out" -- "$SNERT" export phantom:sphere
expect_exit 2 "no-such-volume.nrrd" -- "$SNERT" compare "$tmp/no-such-volume.nrrd"
expect_exit 2 "mesh.xyz" -- "$SNERT" export phantom:sphere --size 16 --out "$tmp/mesh.xyz"
expect_exit 2 "empty" -- "$SNERT" export phantom:sphere --size 16 --iso 1000 --out "$tmp/e.stl"
[ -e "$tmp/e.stl" ] && fail "empty surface left a file"
expect_exit 2 "all inside or all outside" -- "$SNERT" compare phantom:sphere --size 16 --iso -1000 --json "$tmp/e.json"
[ -e "$tmp/e.json" ] && fail "empty surface left a JSON file"

# compare: the table and the JSON schema.
expect_exit 0 "" -- "$SNERT" compare phantom:sphere --size 24 --json "$tmp/c.json"
grep -q "snert" "$tmp/out" || fail "compare table lacks the snert row"
grep -q "fe_ready" "$tmp/out" || fail "compare table lacks the FE-readiness columns"
grep -q "accS over the whole surface" "$tmp/out" || fail "compare table does not say which accuracy is which"
python3 - "$tmp/c.json" <<'PY' || fail "compare JSON schema"
import json, sys
j = json.load(open(sys.argv[1]))
assert set(j) == {"mc", "sna", "snert"}, j.keys()
keys = ["vertices", "triangles", "quality_mean", "quality_min", "quality_hist", "quality60_mean",
        "radius_ratio_mean", "degenerate", "smoothness", "accuracy_vertices", "accuracy_faces",
        "accuracy_surface", "accuracy_against", "watertight", "manifold", "nonmanifold_edges",
        "nonmanifold_vertices", "self_intersections", "slivers", "min_angle_deg", "fe_ready",
        "iterations", "converged", "final_max_move", "ms"]
for name, m in j.items():
    for k in keys: assert k in m, k
    assert m["triangles"] > 0 and m["watertight"] is True and m["manifold"] is True
    assert len(m["quality_hist"]) == 20 and sum(m["quality_hist"]) == m["triangles"]
    assert 0 < m["quality_mean"] <= 1
    assert 0 <= m["slivers"] <= 1 and 0 < m["min_angle_deg"] <= 60
    assert m["accuracy_surface"] > 0 and m["accuracy_against"] == "the exact surface of the phantom"
    # The relaxation's numbers belong to the nets only.
    assert (m["iterations"] is None) == (name == "mc"), name
assert j["mc"]["self_intersections"] == 0 and j["mc"]["fe_ready"] is True
assert j["snert"]["quality_mean"] > j["mc"]["quality_mean"]
PY
expect_exit 0 "" -- "$SNERT" compare phantom:torus --size 20 --mode gradient --iterations 3
grep -q "gradient" "$tmp/out" || fail "--mode gradient row missing"

# export: every format, written whole; an unwritable folder fails cleanly.
for ext in stl obj ply off vtk; do
    expect_exit 0 "wrote" -- "$SNERT" export phantom:sphere --size 16 --method snert --out "$tmp/m.$ext"
    [ -s "$tmp/m.$ext" ] || fail "export .$ext is empty"
done
expect_exit 2 "no-dir" -- "$SNERT" export phantom:sphere --size 16 --method mc --out "$tmp/no-dir/m.stl"
ls "$tmp" | grep -q tmp && fail "a temporary file was left behind"

# table1 writes one object per phantom.
expect_exit 0 "" -- "$SNERT" table1 --size 16 --iterations 5 --json "$tmp/t.json"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert set(j)=={'plane','sphere','two_spheres'}; assert set(j['sphere'])=={'mc','sna','snert'}" "$tmp/t.json" || fail "table1 JSON"


# Real volumes, when the shared data folder is there.
data=${SNERT_DATA_DIR:-}
if [ -n "$data" ] && [ -d "$data" ]; then
    expect_exit 0 "" -- "$SNERT" compare "$data/HeadMRVolume.mhd" --iso 40 --iterations 5 --json "$tmp/mr.json"
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['snert']['accuracy_reference']=='first-order'; assert j['mc']['triangles']>1000; assert 'iso-surface I = 40' in j['mc']['accuracy_against']" "$tmp/mr.json" || fail "MR compare JSON"
    ct="$data/totalseg_ct_abdomen/example_ct_sm.nii.gz"
    expect_exit 0 "" -- "$SNERT" compare "$ct" --labels "$data/totalseg_ct_abdomen/example_seg.nii.gz" --label 5 --iterations 5
    grep -q "snert" "$tmp/out" || fail "label compare lacks the snert row"
    grep -q "not the label mask's boundary" "$tmp/out" || fail "label compare does not say what accuracy is measured against"
    expect_exit 2 "HeadMRVolume" -- "$SNERT" compare "$ct" --labels "$data/HeadMRVolume.mhd" --label 5
    expect_exit 0 "wrote" -- "$SNERT" export "$data/headsq/quarter.1" --raw 64,64,93 --raw-type uint16 --raw-spacing 3.2,3.2,1.5 --iso 500 --iterations 5 --method snert --out "$tmp/head.ply"
else
    echo "cli: shared data folder absent, real-volume checks skipped"
fi

echo "cli: $passes passed, $failures failed"
[ "$failures" -eq 0 ]
