#!/bin/sh
# The kd-tree build at revision OLD against the working tree's, interleaved in one process:
#   tools/kdtree_build_ab/run.sh OLD [REPEAT]      e.g. tools/kdtree_build_ab/run.sh ed7e803 5
# Builds in $TMPDIR (or /tmp)/kdtree_build_ab; the meshes come from patina (the venv's python).
set -e
repo=$(cd "$(dirname "$0")/../.." && pwd)
old=${1:?usage: run.sh OLD_REVISION [REPEAT]}
repeat=${2:-5}
work=${TMPDIR:-/tmp}/kdtree_build_ab
mkdir -p "$work"
python=${PYTHON:-$repo/.venv/bin/python}
[ -f "$work/sphere1m.bin" ] || "$python" "$repo/tools/kdtree_build_ab/dump_mesh.py" "$work"
# the old revision's build: its entry point renamed, Box3::area left to the new one
git -C "$repo" show "$old:render/accel/kdtree_build.cpp" |
    sed -e 's/^KdTree build_kdtree(/KdTree build_kdtree_old(/' -e '/^float Box3::area() const {/,/^}/d' >"$work/old.cpp"
flags="-O3 -DNDEBUG -std=c++17 -ffp-contract=off -I$repo"
c++ $flags -c "$work/old.cpp" -o "$work/old.o"
c++ $flags -c "$repo/render/accel/kdtree_build.cpp" -o "$work/new.o"
c++ $flags "$repo/tools/kdtree_build_ab/driver.cpp" "$work/new.o" "$work/old.o" -o "$work/driver" -lpthread
uptime
"$work/driver" "$repeat" "$work/sphere1m.bin" "$work/sphere200k.bin" "$work/boxes200k.bin" "$work/icosphere80k.bin"
uptime
