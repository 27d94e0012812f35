#!/usr/bin/env bash
# Builds the libFuzzer target for snert's header handling and raw reader with clang (outside the
# g++ CMake build: ITK is not needed, and Debian's ITK headers do not compile with clang), then
# runs it for a bounded time. Usage: tests/fuzz/run.sh [SECONDS] (default 60).
# Crashes are written to build/fuzz/ as crash-* files; rerun one with
#   build/fuzz/fuzz_volume_headers build/fuzz/crash-<hash>
set -euo pipefail
seconds=${1:-60}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
out="$root/build/fuzz"
mkdir -p "$out/corpus" "$out/seeds"
cxx=${FUZZ_CXX:-clang++}

# Every source of snert_io but those that include ITK (itk_support, itk_image_io, dicom_series,
# isotropic; src/io/CMakeLists.txt names the same ones), those that call them (open_volume, the input
# model) and the writers; and the core sources they call.
sources=("$root/tests/fuzz/fuzz_volume_headers.cpp" "$root/src/core/volume_stats.cpp"
    "$root/src/core/volume.cpp")
for file in "$root"/src/io/*.cpp; do
    case "$file" in
    */itk_support.cpp | */itk_image_io.cpp | */dicom_series.cpp | */isotropic.cpp) ;;
    */load_volume.cpp) ;;
    */source.cpp) ;;
    */mesh_io.cpp | */atomic_file.cpp) ;;
    *) sources+=("$file") ;;
    esac
done
echo "fuzz: building $out/fuzz_volume_headers with $cxx"
"$cxx" -std=c++20 -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
    -I"$root/src" "${sources[@]}" -lz -o "$out/fuzz_volume_headers"

# Seeds: the first byte picks the target (see fuzz_volume_headers.cpp), the rest is its input.
printf '\001NDims = 3\nDimSize = 4 5 6\nElementType = MET_SHORT\nElementDataFile = LOCAL\n' \
    > "$out/seeds/metaimage"
printf '\002# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 8\nSCALARS s short 1\nLOOKUP_TABLE default\n' \
    > "$out/seeds/vtk"
printf '\003NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n0123456789abcdef' \
    > "$out/seeds/nrrd"
printf '\015NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: gzip\n\n' \
    > "$out/seeds/nrrd_file"
printf '\007dir9/IM-0009.raw' > "$out/seeds/numbered"
printf '\010MemTotal: 100 kB\nMemAvailable: 50 kB\n' > "$out/seeds/meminfo"
printf '\013\001\001\002\003\000abcdefgh' > "$out/seeds/raw"

echo "fuzz: running for $seconds s"
cd "$out"
./fuzz_volume_headers -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 corpus seeds
