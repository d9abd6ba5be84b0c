#!/bin/bash
# Build OpenSubdiv 3.6.0 CPU libs (sdc, vtr, far, bfr) + osd_bench harness, sequentially (one core).
# Usage: ./build.sh [OSD_SRC_DIR]   (default: ./src, i.e. `git archive v3_6_0` of PixarAnimationStudios/OpenSubdiv)
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
SRC="$(cd "${1:-$HERE/src}" && pwd)"
OBJ="$HERE/build/obj"
CXX="${CXX:-g++}"
CXXFLAGS="-O3 -march=native -std=c++14 -DNDEBUG"
mkdir -p "$OBJ"
for d in sdc vtr far bfr; do
  for f in "$SRC"/opensubdiv/$d/*.cpp; do
    o="$OBJ/${d}_$(basename "${f%.cpp}").o"
    if [ ! -f "$o" ] || [ "$f" -nt "$o" ]; then
      echo "CXX $d/$(basename "$f")"
      $CXX $CXXFLAGS -I"$SRC" -c "$f" -o "$o"
    fi
  done
done
rm -f "$HERE/build/libosdcpu_min.a"
ar rcs "$HERE/build/libosdcpu_min.a" "$OBJ"/*.o
echo "CXX osd_bench.cpp"
$CXX $CXXFLAGS -I"$SRC" "$HERE/osd_bench.cpp" "$HERE/build/libosdcpu_min.a" -o "$HERE/osd_bench"
echo "built $HERE/osd_bench"
