#!/usr/bin/env bash
# An FE mesher fills the closed surfaces: with --close-border, the Marching Cubes and SNERT
# meshes of one volume of the shared data folder are closed, manifold and fe_ready by snert's
# own measures (watertight, no boundary edge, none off the border), and TetGen's `tetgen -pq`
# (a constrained Delaunay tetrahedralisation with quality refinement) on the exported OFF file
# ends with a tetrahedral mesh. The output files are not written (-NEF): TetGen's statistics
# say how many tetrahedra it made. Usage: tetgen_fill_test.sh NAME METHOD (one of the volumes
# below; mc or snert: one test each, so that ctest -j spreads TetGen's minutes over the cores);
# $SNERT is the binary, $SNERT_DATA_DIR the data folder. Exit 77 (skipped) without TetGen,
# without the data, or where SNERT_LARGE_VOLUMES=0 (the sanitizer build; `make test` runs
# them in an optimized build). On the two large volumes `tetgen -pq` spends minutes to half an
# hour of CPU splitting the surface's facets (FLAIR's MC mesh: 34.5 min; the DICOM head's
# stretched 1 x 1 x 4.8 mm SNERT mesh: 203 s), so there both meshes get `tetgen -pqY`: the same
# quality refinement inside, the surface kept exactly as snert wrote it (11-21 s), which is
# what an FE model built on the surface needs; SNERT_TETGEN_FULL=1 gives them -pq.
set -u
name=${1:?usage: tetgen_fill_test.sh NAME METHOD}
method=${2:?usage: tetgen_fill_test.sh NAME METHOD}
case "$method" in mc | snert) ;; *) echo "tetgen_fill: unknown method '$method'"; exit 1 ;; esac
data=${SNERT_DATA_DIR:-}
if ! command -v tetgen >/dev/null; then
    echo "tetgen_fill: TetGen is not installed (Debian package tetgen), skipped"
    exit 77
fi
if [ -z "$data" ] || [ ! -d "$data" ]; then
    echo "tetgen_fill: shared data folder absent, skipped"
    exit 77
fi

# One line per volume: a name, its size class, then the input arguments (iso values as in
# tetgen_test.sh). TetGen's time on 2 cores is in tests/README.md.
volumes=(
    "headsq|small|$data/headsq/quarter.1 --raw 64,64,93 --raw-type uint16 --raw-spacing 3.2,3.2,1.5 --iso 500"
    "head_mr|small|$data/HeadMRVolume.mhd --iso 40"
    "carotid|small|$data/carotid.vtk --iso 190"
    "flair|large|$data/FLAIR.nrrd --iso 40"
    "ct_abdomen|small|$data/totalseg_ct_abdomen/example_ct_sm.nii.gz --iso -500"
    "liver|small|$data/totalseg_ct_abdomen/example_ct_sm.nii.gz --labels $data/totalseg_ct_abdomen/example_seg.nii.gz --label 5"
    "dicom_head|large|$data/dicom_mr_head_t1_sag --iso 200"
)
entry=""
for e in "${volumes[@]}"; do
    [ "${e%%|*}" = "$name" ] && entry=$e
done
if [ -z "$entry" ]; then
    echo "tetgen_fill: unknown volume '$name'"
    exit 1
fi
IFS='|' read -r name size arguments <<<"$entry"
read -r -a input <<<"$arguments"
# TetGen's minutes are the same in every build, so only the optimized one pays them: the
# sanitizer build (SNERT_LARGE_VOLUMES=0) checks --close-border through the cli test instead.
if [ "${SNERT_LARGE_VOLUMES:-1}" = 0 ]; then
    echo "tetgen_fill: $name: skipped in the sanitizer build (make test runs it optimized)"
    exit 77
fi
if [ ! -e "${input[0]}" ]; then
    echo "tetgen_fill: $name: ${input[0]} absent, skipped"
    exit 77
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passes=0
fail() { echo "FAIL: $name $method: $*"; failures=$((failures + 1)); }

if "$SNERT" compare "${input[@]}" --close-border --mode snert --json "$tmp/c.json" >/dev/null 2>"$tmp/err"; then
    if python3 - "$tmp/c.json" "$method" <<'PY'; then passes=$((passes + 1)); else fail "snert's measures"; fi
import json, sys
j = json.load(open(sys.argv[1]))
assert j["provenance"]["input"]["close_border"] is True
for m in (sys.argv[2],):
    f = j[m]
    facts = {k: f[k] for k in ("watertight", "manifold", "boundary_edges", "boundary_edges_off_border",
                               "self_intersections", "degenerate", "fe_ready")}
    ok = (f["watertight"] and f["manifold"] and f["boundary_edges"] == 0 and
          f["boundary_edges_off_border"] == 0 and f["fe_ready"])
    print(("ok" if ok else "FAIL") + ": %s: closed at the border: %s" % (m, facts))
    assert ok
PY
else
    fail "snert compare failed:"; cat "$tmp/err"
fi

TIMEFORMAT=%U
off="$tmp/$method.off"
if ! "$SNERT" export "${input[@]}" --close-border --method "$method" --out "$off" >/dev/null 2>"$tmp/err"; then
    fail "snert export failed:"; cat "$tmp/err"
else
    triangles=$(sed -n 2p "$off" | cut -d' ' -f2)
    # User CPU seconds of TetGen on stderr (bash's time), its report on stdout.
    switches=-pqNEF
    if [ "$size" = large ] && [ "${SNERT_TETGEN_FULL:-0}" != 1 ]; then
        switches=-pqYNEF
        echo "tetgen_fill: $name $method: large, tetgen -pqY, the surface kept (SNERT_TETGEN_FULL=1 for -pq)"
    fi
    { time tetgen $switches "$off" >"$tmp/tetgen.txt" 2>&1; } 2>"$tmp/time"
    rc=$?
    tets=$(sed -n 's/^ *Mesh tetrahedra: *\([0-9]*\).*/\1/p' "$tmp/tetgen.txt")
    if [ "$rc" -ne 0 ] || [ -z "$tets" ] || [ "$tets" -eq 0 ]; then
        fail "tetgen $switches made no tetrahedral mesh of $triangles triangles (exit $rc):"
        tail -n 8 "$tmp/tetgen.txt"
    else
        echo "ok: $name $method: tetgen ${switches%NEF} filled $triangles triangles with $tets tetrahedra ($(cat "$tmp/time") s of CPU)"
        passes=$((passes + 1))
    fi
fi

echo "tetgen_fill: $name $method: $passes passed, $failures failed"
[ "$failures" -eq 0 ]
