#!/usr/bin/env bash
# An independent check of FE-readiness on the real scans: TetGen (`tetgen -d`, exact
# predicates of its own) must find no intersecting facets in the MC and SNERT meshes of every
# volume of the shared data folder, and on the smaller volumes must find as many intersecting
# pairs as snert's own `self_intersections` says, whatever that number is (the large ones skip
# that cross-check: it costs a second run of the pipeline). Usage: tetgen_test.sh NAME (one of
# the volumes below: one test each, so that ctest -j spreads them). $SNERT is the binary,
# $SNERT_DATA_DIR the data folder. Exit 77 (skipped) without TetGen or without the data, and
# where SNERT_LARGE_VOLUMES=0 (the sanitizer build): TetGen's time is the same in every build,
# so only the optimized one pays it (`make test` runs it there).
set -u
only=${1:?usage: tetgen_test.sh NAME}
data=${SNERT_DATA_DIR:-}
if ! command -v tetgen >/dev/null; then
    echo "tetgen: TetGen is not installed (Debian package tetgen), skipped"
    exit 77
fi
if [ -z "$data" ] || [ ! -d "$data" ]; then
    echo "tetgen: shared data folder absent, skipped"
    exit 77
fi
if [ "${SNERT_LARGE_VOLUMES:-1}" = 0 ]; then
    echo "tetgen: $only: skipped in the sanitizer build (make test runs it optimized)"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passes=0

# One line per volume: a name, whether to cross-check the counts, then the input arguments
# (iso values from SOURCES.md).
volumes=(
    "headsq|count|$data/headsq/quarter.1 --raw 64,64,93 --raw-type uint16 --raw-spacing 3.2,3.2,1.5 --iso 500"
    "head_mr|count|$data/HeadMRVolume.mhd --iso 40"
    "carotid|count|$data/carotid.vtk --iso 190"
    "flair|large|$data/FLAIR.nrrd --iso 40"
    "ct_abdomen|count|$data/totalseg_ct_abdomen/example_ct_sm.nii.gz --iso -500"
    "liver|count|$data/totalseg_ct_abdomen/example_ct_sm.nii.gz --labels $data/totalseg_ct_abdomen/example_seg.nii.gz --label 5"
    "dicom_head|large|$data/dicom_mr_head_t1_sag --iso 200"
)

# TetGen lists a pair once per triangle pair it examines, so a pair can appear several times:
# count distinct unordered pairs.
tetgen_pairs() {
    grep -oE 'Facet #[0-9]+ intersects facet #[0-9]+' "$1" |
        awk '{a = substr($2, 2); b = substr($5, 2); if (a + 0 > b + 0) { t = a; a = b; b = t }; print a, b}' |
        sort -u | wc -l
}

known=0
for entry in "${volumes[@]}"; do
    IFS='|' read -r name count arguments <<<"$entry"
    [ "$name" = "$only" ] || continue
    known=1
    read -r -a input <<<"$arguments"
    if [ ! -e "${input[0]}" ]; then
        echo "tetgen: $name: ${input[0]} absent, skipped"
        continue
    fi
    if [ "$count" = count ] &&
        ! "$SNERT" compare "${input[@]}" --mode snert --no-compactness --json "$tmp/$name.json" >/dev/null 2>"$tmp/err"; then
        echo "FAIL: $name: snert compare failed:"; cat "$tmp/err"; failures=$((failures + 1)); continue
    fi
    for method in mc snert; do
        off="$tmp/${name}_$method.off"
        if ! "$SNERT" export "${input[@]}" --method "$method" --out "$off" >/dev/null 2>"$tmp/err"; then
            echo "FAIL: $name $method: snert export failed:"; cat "$tmp/err"; failures=$((failures + 1)); continue
        fi
        tetgen -d "$off" >"$tmp/tetgen.txt" 2>&1
        if grep -q "No faces are intersecting" "$tmp/tetgen.txt"; then
            theirs=0
        elif grep -q "intersects facet" "$tmp/tetgen.txt"; then
            theirs=$(tetgen_pairs "$tmp/tetgen.txt")
        else
            echo "FAIL: $name $method: TetGen gave no verdict:"; tail -n 5 "$tmp/tetgen.txt"
            failures=$((failures + 1)); continue
        fi
        triangles=$(head -n 2 "$off" | tail -n 1 | cut -d' ' -f2)
        ours=$theirs
        if [ "$count" = count ]; then
            ours=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]]['self_intersections'])" "$tmp/$name.json" "$method")
        fi
        if [ "$theirs" -ne "$ours" ]; then
            echo "FAIL: $name $method: TetGen finds $theirs intersecting pairs, snert counts $ours"
            failures=$((failures + 1))
        elif [ "$theirs" -ne 0 ]; then
            echo "FAIL: $name $method: $theirs intersecting facet pairs ($triangles triangles)"
            failures=$((failures + 1))
        else
            echo "ok: $name $method: no intersecting facets ($triangles triangles)"
            passes=$((passes + 1))
        fi
    done
done

if [ "$known" = 0 ]; then
    echo "tetgen: unknown volume '$only'"
    exit 1
fi
echo "tetgen: $only: $passes passed, $failures failed"
[ "$failures" -eq 0 ]
