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
expect_exit 2 "not expected.*--bogus" -- "$SNERT" compare phantom:sphere --bogus 1
expect_exit 2 "unknown phantom 'cube'" -- "$SNERT" compare phantom:cube
expect_exit 2 "--size: Value 4 not in range 8 to 1024" -- "$SNERT" compare phantom:sphere --size 4
expect_exit 2 "--iterations: Value x not in range" -- "$SNERT" compare phantom:sphere --iterations x
expect_exit 2 "--mode: must be one of sna\|gradient\|snert" -- "$SNERT" compare phantom:sphere --mode fast
expect_exit 2 "VOLUME is required" -- "$SNERT" compare
expect_exit 2 "--iso: 1 required" -- "$SNERT" compare phantom:sphere --iso
expect_exit 2 "--out is required" -- "$SNERT" export phantom:sphere
expect_exit 2 "no-such-volume.nrrd" -- "$SNERT" compare "$tmp/no-such-volume.nrrd"
expect_exit 2 "mesh.xyz" -- "$SNERT" export phantom:sphere --size 16 --out "$tmp/mesh.xyz"
expect_exit 2 "empty" -- "$SNERT" export phantom:sphere --size 16 --iso 1000 --out "$tmp/e.stl"
[ -e "$tmp/e.stl" ] && fail "empty surface left a file"
expect_exit 2 "all inside or all outside" -- "$SNERT" compare phantom:sphere --size 16 --iso -1000 --json "$tmp/e.json"
[ -e "$tmp/e.json" ] && fail "empty surface left a JSON file"

# Option rules: what does not apply to the input, or lacks its partner, is a usage error.
expect_exit 2 "--raw: applies to volume files, not to phantom:sphere" -- "$SNERT" compare phantom:sphere --raw 4,4,4 --raw-type uint8
expect_exit 2 "--labels: applies to volume files" -- "$SNERT" compare phantom:sphere --labels "$tmp/l.nii" --label 1
expect_exit 2 "--size: applies to phantoms only" -- "$SNERT" compare "$tmp/v.nrrd" --size 32
expect_exit 2 "--raw requires --raw-type" -- "$SNERT" compare "$tmp/v.raw" --raw 4,4,4
expect_exit 2 "--raw-type requires --raw" -- "$SNERT" compare "$tmp/v.raw" --raw-type uint8
expect_exit 2 "--label requires --labels" -- "$SNERT" compare "$tmp/v.nrrd" --label 3
expect_exit 2 "--(series excludes --raw|raw excludes --series)" -- "$SNERT" compare "$tmp/v.raw" --raw 4,4,4 --raw-type uint8 --series 1.2.3
expect_exit 2 "--raw: takes three" -- "$SNERT" compare "$tmp/v.raw" --raw 4,4 --raw-type uint8
expect_exit 2 "--raw-type: .*float32" -- "$SNERT" compare "$tmp/v.raw" --raw 4,4,4 --raw-type half

# --isotropic: a 1 x 1 x 3 mm ball resampled to cubic voxels of 1 mm; phantoms (cubic already)
# refuse it; a cubic grid that does not fit in memory is refused with its sizes.
python3 -c "
import sys
sys.stdout.buffer.write(bytes(200 if (x-7.5)**2+(y-7.5)**2+(3*z-7.5)**2 < 36 else 0
                              for z in range(6) for y in range(16) for x in range(16)))" >"$tmp/ball.raw"
ball=("$tmp/ball.raw" --raw 16,16,6 --raw-type uint8 --raw-spacing 1,1,3 --iso 100)
expect_exit 0 "resampled to 16x16x16, cubic voxels of 1 mm" -- "$SNERT" compare "${ball[@]}" --isotropic --mode snert --iterations 5 --json "$tmp/ball.json"
python3 -c "import json,sys; p=json.load(open(sys.argv[1]))['provenance']['input']; assert p['dims']==[16,16,16] and p['spacing']==[1,1,1] and p['isotropic']==1, p" "$tmp/ball.json" || fail "--isotropic provenance"
expect_exit 0 "cubic voxels of 0.5 mm" -- "$SNERT" compare "${ball[@]}" --isotropic 0.5 --mode snert --iterations 5
expect_exit 2 "--isotropic: applies to volume files, not to phantom:sphere" -- "$SNERT" compare phantom:sphere --isotropic
expect_exit 2 "--isotropic: 'abc' is not a positive number" -- "$SNERT" compare "${ball[@]}" --isotropic abc
expect_exit 2 "--isotropic requires --volume" -- "$SNERT" bench --isotropic
expect_exit 2 "ball.raw: resampling to cubic voxels of 0.001 mm: 16 x 16 x 6 samples \\(spacing 1 x 1 x 3000 mm\\) would become 15001 x 15001 x [0-9]+, which need .* of memory is available" -- \
    "$SNERT" compare "$tmp/ball.raw" --raw 16,16,6 --raw-type uint8 --raw-spacing 1,1,3000 --iso 100 --isotropic 0.001
expect_exit 2 "--schedule: must be one of simultaneous\|smoothing-first" -- "$SNERT" compare phantom:sphere --schedule later
expect_exit 2 "--method: must be one of mc\|sna\|gradient\|snert" -- "$SNERT" export phantom:sphere --method best --out "$tmp/m.stl"
expect_exit 2 "not expected.*--mode" -- "$SNERT" export phantom:sphere --mode sna --out "$tmp/m.stl"

# --help is generated from the declarations: the input options are listed.
expect_exit 0 "" -- "$SNERT" compare --help
for option in --raw --raw-type --raw-spacing --raw-endian --series --labels --label --isotropic --iso --mode --json; do
    grep -qE -- "^ *$option " "$tmp/out" || fail "compare --help lacks $option"
done
expect_exit 0 "" -- "$SNERT" --help
grep -q "compare" "$tmp/out" || fail "snert --help lacks the commands"

# The version, from CMake's project version.
expect_exit 0 "" -- "$SNERT" --version
grep -qxE "snert [0-9]+\.[0-9]+\.[0-9]+" "$tmp/out" || fail "--version prints '$(cat "$tmp/out")'"
expect_exit 0 "" -- "$SNERT" version
grep -qxE "snert [0-9]+\.[0-9]+\.[0-9]+" "$tmp/out" || fail "version prints '$(cat "$tmp/out")'"

# Output paths are checked before the work: a missing folder fails at once (a 400^3 phantom
# would take far longer than a second to mesh).
for command in "compare phantom:sphere --size 400 --json $tmp/no-dir/c.json" \
               "table1 --size 400 --json $tmp/no-dir/t.json" \
               "export phantom:sphere --size 400 --out $tmp/no-dir/m.stl"; do
    start=$(date +%s%N)
    # shellcheck disable=SC2086
    expect_exit 2 "no-dir.*does not exist" -- "$SNERT" $command
    elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
    [ "$elapsed_ms" -lt 1000 ] || fail "'$command' took $elapsed_ms ms to refuse a missing folder"
done
expect_exit 2 "c.txt: unknown extension" -- "$SNERT" compare phantom:sphere --size 16 --json "$tmp/c.txt"

# --json - : JSON on standard output, the table on standard error.
expect_exit 0 "" -- "$SNERT" compare phantom:sphere --size 16 --iterations 3 --json -
python3 -m json.tool "$tmp/out" >/dev/null || fail "--json - does not print JSON alone"
grep -q "accS over the whole surface" "$tmp/err" || fail "--json - does not move the table to stderr"
python3 - "$tmp/out" <<'PY' || fail "compare provenance"
import json, sys
p = json.load(open(sys.argv[1]))["provenance"]
assert p["command"] == "compare" and p["version"].count(".") == 2, p
assert p["input"] == {"phantom": "sphere", "size": 16, "dims": [16, 16, 16], "spacing": [1, 1, 1], "close_border": False}, p["input"]
assert p["iso"] == 0 and p["inside"] == "above", p
r = p["relaxation"]
assert r["iterations"] == 3 and r["mode"] == "snert" and r["schedule"] == "simultaneous", r
assert r["epsilon"] == 1e-4 and r["guard"] is True and r["triangulation"] == "shorter", r
PY

# Numbers as people write them.
expect_exit 0 "" -- "$SNERT" compare phantom:sphere --size 16 --iso 0.25 --mode sna --iterations 2
grep -q "(iso 0.25)" "$tmp/out" || fail "the table title does not print the iso as given"

# compare: the table and the JSON schema.
expect_exit 0 "" -- "$SNERT" compare phantom:sphere --size 24 --compactness --json "$tmp/c.json"
grep -q "snert" "$tmp/out" || fail "compare table lacks the snert row"
grep -q "fe_ready" "$tmp/out" || fail "compare table lacks the FE-readiness columns"
grep -q "accS over the whole surface" "$tmp/out" || fail "compare table does not say which accuracy is which"
python3 - "$tmp/c.json" <<'PY' || fail "compare JSON schema"
import json, sys
j = json.load(open(sys.argv[1]))
assert set(j) == {"mc", "sna", "snert", "provenance", "compactness"}, j.keys()
prov = j.pop("provenance")
curve = j.pop("compactness")
assert set(curve) == {"mc", "sna", "snert"}, curve.keys()
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
# compare --equal-count: the meshes reduced to one count and measured again; the compactness
# curve of the full meshes in the JSON.
expect_exit 0 "" -- "$SNERT" compare phantom:sphere --size 32 --mode snert --iterations 10 --equal-count --compactness --json "$tmp/eq.json"
grep -q "equal triangle count" "$tmp/out" || fail "compare --equal-count does not say so"
python3 - "$tmp/eq.json" <<'PY' || fail "compare --equal-count JSON"
import json, sys
j = json.load(open(sys.argv[1]))
n = j["equal_count"]["target"]
assert j["equal_count"]["requested"] is None and j["equal_count"]["triangles"] <= n
assert n == min(j[m]["decimation"]["original"] for m in ("mc", "snert")), n
for m in ("mc", "snert"):
    d, r = j[m]["decimation"], j[m]
    assert 0.99 * n <= r["triangles"] <= n, (m, r["triangles"], n)
    assert d["achieved"] == r["triangles"] and d["stalled"] is False
    assert sum(r["quality_hist"]) == r["triangles"]
    assert r["watertight"] and r["manifold"] and r["self_intersections"] == 0 and r["fe_ready"]
    c = j["compactness"][m]
    assert [p["fraction"] for p in c] == [1.0, 0.5, 0.25, 0.1, 0.05], c
    full = c[0]["triangles"]
    assert full == d["original"] and c[0]["accuracy_mean"] == 0 and c[0]["accuracy_max"] == 0
    for p in c[1:]:
        assert abs(p["triangles"] - p["fraction"] * full) <= 0.02 * p["fraction"] * full + 2, p
        assert 0 < p["accuracy_mean"] <= p["accuracy_max"] < 1 and 0 < p["quality_mean"] <= 1, p
    # Coarser meshes are farther from the full one.
    assert c[4]["accuracy_mean"] > c[1]["accuracy_mean"], c
PY
expect_exit 0 "" -- "$SNERT" compare phantom:sphere --size 32 --mode snert --iterations 10 --equal-count=500 --json "$tmp/eq500.json"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert 'compactness' not in j; assert j['equal_count']=={'triangles':500,'target':500,'requested':500}; assert all(490<=j[m]['triangles']<=500 and j[m]['decimation']['requested']==500 for m in ('mc','snert'))" "$tmp/eq500.json" || fail "compare --equal-count=500"
expect_exit 2 "--equal-count: must be a whole number" -- "$SNERT" compare phantom:sphere --equal-count 0
expect_exit 2 "--equal-count: must be a whole number" -- "$SNERT" compare phantom:sphere --equal-count many
# render --equal-count draws the reduced meshes (only where the renderer is built).
if "$SNERT" render --help >/dev/null 2>&1; then
    expect_exit 0 "equal triangle count: 400" -- "$SNERT" render phantom:sphere --size 24 --iterations 5 --equal-count 400 --width 400 --height 300 --gl osmesa --out "$tmp/eq.png"
    [ -s "$tmp/eq.png" ] || fail "render --equal-count wrote no picture"
    # Colouring by a distance: to the iso-surface also for one mesh; to the other mesh needs both.
    expect_exit 0 "wrote" -- "$SNERT" render phantom:sphere --size 24 --iterations 3 --layout mc --shading quality --color-by distance-iso --width 400 --height 300 --gl osmesa --out "$tmp/dist_mc.png"
    expect_exit 2 "distance-other needs both meshes" -- "$SNERT" render phantom:sphere --layout net --color-by distance-other --out "$tmp/dist_net.png"
    [ -e "$tmp/dist_net.png" ] && fail "a refused distance render left a file"
fi
expect_exit 0 "" -- "$SNERT" compare phantom:torus --size 20 --mode gradient --iterations 3
grep -q "gradient" "$tmp/out" || fail "--mode gradient row missing"

# export: every format, written whole; an unwritable folder fails cleanly.
for ext in stl obj ply off vtk msh inp; do
    expect_exit 0 "wrote" -- "$SNERT" export phantom:sphere --size 16 --method snert --out "$tmp/m.$ext"
    [ -s "$tmp/m.$ext" ] || fail "export .$ext is empty"
done
expect_exit 2 "no-dir" -- "$SNERT" export phantom:sphere --size 16 --method mc --out "$tmp/no-dir/m.stl"
ls "$tmp" | grep -q tmp && fail "a temporary file was left behind"

# table1 writes one object per phantom.
expect_exit 0 "" -- "$SNERT" table1 --size 16 --iterations 5 --json "$tmp/t.json"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert set(j)=={'plane','sphere','two_spheres','provenance'}; assert set(j['sphere'])=={'mc','sna','snert'}; assert [p['phantom'] for p in j['provenance']['input']['phantoms']]==['plane','sphere','two-spheres']; assert j['provenance']['relaxation']['iterations']==5" "$tmp/t.json" || fail "table1 JSON"


# OSMesa, and the LLVM it pulls in (about 50 MB resident), is opened only when something is
# drawn (render/context.cpp): the binary does not link it.
if ldd "$SNERT" | grep -q "libOSMesa"; then fail "snert links OSMesa instead of opening it"; fi

# bench: the stages timed, with a thread limit; the JSON `make bench` reads.
expect_exit 0 "" -- "$SNERT" bench --size 32 --threads 1 --repeat 1 --json "$tmp/b.json"
grep -q "SNERT iteration" "$tmp/out" || fail "bench table lacks the iteration row"
grep -q "central differences" "$tmp/out" || fail "bench table lacks the central-difference iteration row"
grep -q "in kept memory" "$tmp/out" || fail "bench table lacks the kept-memory rows"
python3 - "$tmp/b.json" <<'PY' || fail "bench JSON"
import json, sys
j = json.load(open(sys.argv[1]))
for key in ("mc_ms", "mc_kept_ms", "net_ms", "net_kept_ms", "relax_ns_per_node",
            "relax_trilinear_ns_per_node",
            "relax_central_ns_per_node", "metrics_ms", "compare_ms", "nodes", "triangles",
            "threads", "size", "peak_rss_mb"):
    assert key in j, key
assert j["threads"] == 1 and j["size"] == [32, 32, 32] and j["nodes"] > 0, j
assert j["relax_trilinear_ns_per_node"] == j["relax_ns_per_node"] < 1e9, j
assert 0 < j["relax_central_ns_per_node"], j
assert 0 < j["mc_ms"] < j["compare_ms"] and 0 < j["mc_kept_ms"] and 0 < j["net_kept_ms"], j
PY
expect_exit 2 "--volume excludes --size|--size excludes --volume" -- "$SNERT" bench --size 32 --volume "$tmp/v.nrrd"
expect_exit 2 "--iso requires --volume" -- "$SNERT" bench --iso 3

# Progress: one line redrawn on a terminal (script gives the command one), nothing in a log.
expect_exit 0 "" -- "$SNERT" compare phantom:sphere --size 24 --iterations 3
grep -q $'\r' "$tmp/err" && fail "progress written to a stderr that is not a terminal"
if command -v script >/dev/null; then
    script -qec "$SNERT compare phantom:sphere --size 24 --iterations 3 >/dev/null" /dev/null >"$tmp/tty" 2>&1
    grep -q "snert compare: SNERT [0-9]* %" "$tmp/tty" || fail "no progress line on a terminal"
    script -qec "$SNERT compare phantom:sphere --size 24 --iterations 3 --quiet >/dev/null" /dev/null >"$tmp/tty" 2>&1
    grep -q "%" "$tmp/tty" && fail "--quiet still shows progress"
    pass
fi

# --close-border: every surface closed at the volume border (the plane leaves the grid on all
# sides); off by default for grey values; --no-close-border and --close-border=false turn it off.
closed_facts() {
    python3 - "$@" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
want = sys.argv[2] == "closed"
assert j["provenance"]["input"]["close_border"] == want, j["provenance"]["input"]
for m in ("mc", "snert"):
    f = j[m]
    if want:
        assert f["watertight"] and f["manifold"] and f["boundary_edges"] == 0, m
        if len(sys.argv) > 3:
            assert f["euler"] == int(sys.argv[3]), (m, f["euler"])
        assert f["boundary_edges_off_border"] == 0 and f["fe_ready"], m
    else:
        assert not f["watertight"] and f["boundary_edges"] > 0, m
PY
}
expect_exit 0 "" -- "$SNERT" compare phantom:plane --size 16 --iterations 3 --mode snert --close-border --json "$tmp/closed.json"
closed_facts "$tmp/closed.json" closed 2 || fail "--close-border: the plane is not closed"
grep -q "closed at the border" "$tmp/out" || fail "--close-border: the table's title does not say so"
[ "$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['provenance']['input']['dims'])" "$tmp/closed.json")" = "[16, 16, 16]" ] || fail "--close-border: the JSON's dims are not the grid read"
for off in "" --no-close-border --close-border=false; do
    expect_exit 0 "" -- "$SNERT" compare phantom:plane --size 16 --iterations 3 --mode snert $off --json "$tmp/open.json"
    closed_facts "$tmp/open.json" open || fail "'$off': the plane is closed"
done
expect_exit 0 "wrote" -- "$SNERT" export phantom:plane --size 16 --iterations 3 --close-border --out "$tmp/closed.off"
expect_exit 0 "" -- "$SNERT" bench --size 16 --repeat 1 --close-border
grep -q "close the border" "$tmp/out" || fail "bench --close-border: no row for the padding"

# Real volumes, when the shared data folder is there.
data=${SNERT_DATA_DIR:-}
if [ -n "$data" ] && [ -d "$data" ]; then
    expect_exit 0 "" -- "$SNERT" compare "$data/HeadMRVolume.mhd" --iso 40 --iterations 5 --no-compactness --json "$tmp/mr.json"
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['snert']['accuracy_reference']=='first-order'; assert j['mc']['triangles']>1000; assert 'iso-surface I = 40' in j['mc']['accuracy_against']" "$tmp/mr.json" || fail "MR compare JSON"
    ct="$data/totalseg_ct_abdomen/example_ct_sm.nii.gz"
    expect_exit 0 "" -- "$SNERT" compare "$ct" --labels "$data/totalseg_ct_abdomen/example_seg.nii.gz" --label 5 --iterations 5
    grep -q "snert" "$tmp/out" || fail "label compare lacks the snert row"
    grep -q "not the label mask's boundary" "$tmp/out" || fail "label compare does not say what accuracy is measured against"
    expect_exit 2 "HeadMRVolume" -- "$SNERT" compare "$ct" --labels "$data/HeadMRVolume.mhd" --label 5
    # A label that does not occur: the labels present, with the names the file carries.
    expect_exit 2 "example_seg.nii.gz: label 21 does not occur.*5 liver" -- "$SNERT" compare "$ct" --labels "$data/totalseg_ct_abdomen/example_seg.nii.gz" --label 21
    expect_exit 0 "" -- "$SNERT" compare "$ct" --labels "$data/totalseg_ct_abdomen/example_seg.nii.gz" --label 5 --mode snert --iterations 2 --no-compactness --json -
    python3 -c "import json,sys; p=json.load(open(sys.argv[1]))['provenance']['input']; assert p['label']==5 and p['label_name']=='liver' and p['format']=='NIfTI', p" "$tmp/out" || fail "label provenance"
    # A label map closes its surfaces at the border by default (the liver reaches the last
    # slices; closed, it has one handle: Euler characteristic 0); --no-close-border leaves them
    # open there.
    closed_facts "$tmp/out" closed 0 || fail "--labels: the liver is not closed by default"
    expect_exit 0 "" -- "$SNERT" compare "$ct" --labels "$data/totalseg_ct_abdomen/example_seg.nii.gz" --label 5 --mode snert --iterations 2 --no-close-border --json "$tmp/liver_open.json"
    closed_facts "$tmp/liver_open.json" open || fail "--no-close-border: the liver is closed"
    expect_exit 2 "--raw: applies to volume files" -- "$SNERT" compare phantom:sphere --raw 64,64,93 --raw-type uint16
    expect_exit 0 "wrote" -- "$SNERT" export "$data/headsq/quarter.1" --raw 64,64,93 --raw-type uint16 --raw-spacing 3.2,3.2,1.5 --iso 500 --iterations 5 --method snert --out "$tmp/head.ply"
else
    echo "cli: shared data folder absent, real-volume checks skipped"
fi

# The slice view's options (only where snert was built with the renderer and OSMesa runs).
if "$SNERT" render phantom:small-sphere --slice axial:5 --gl osmesa --out "$tmp/slice.png" -q >/dev/null 2>&1; then
    expect_exit 2 "--slice: 'oblique:3' is not AXIS:INDEX" -- "$SNERT" render phantom:small-sphere --slice oblique:3 --out "$tmp/s.png"
    expect_exit 2 "axial slice 12 is outside 0..11" -- "$SNERT" render phantom:small-sphere --slice axial:12 --gl osmesa --out "$tmp/s.png"
    expect_exit 2 "--node: needs --slice" -- "$SNERT" render phantom:small-sphere --node 2,3,5 --out "$tmp/s.png"
    expect_exit 2 "cell \(0,0,0\) holds no node" -- "$SNERT" render phantom:small-sphere --slice axial:5 --node 0,0,0 --gl osmesa --out "$tmp/s.png"
    expect_exit 2 "--zoom: with --slice, '1,2' is not a window X,Y,W,H" -- "$SNERT" render phantom:small-sphere --slice axial:5 --zoom 1,2 --out "$tmp/s.png"
    expect_exit 2 "--zoom: '0,0,1' is not a positive number" -- "$SNERT" render phantom:small-sphere --zoom 0,0,1 --out "$tmp/s.png"
    [ -e "$tmp/s.png" ] && fail "a refused slice render left a file"
    expect_exit 0 "wrote" -- "$SNERT" render phantom:crease --slice coronal:3 --node 6,3,1 --iteration 1 --gl osmesa --out "$tmp/node.png"
fi

echo "cli: $passes passed, $failures failed"
[ "$failures" -eq 0 ]
