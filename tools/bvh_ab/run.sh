#!/bin/sh
# The BVH (render/accel/bvh*) at revision OLD against the working tree's, interleaved in one
# process, on the trace bench's ray sets, then both builds of the 1M-triangle sphere:
#   tools/bvh_ab/run.sh OLD [REPEAT]          e.g. tools/bvh_ab/run.sh 9b132f2 11
# Builds in $TMPDIR (or /tmp)/bvh_ab; the rays come from patina (the venv's python), written
# once (delete the directory to write them again).
set -e
repo=$(cd "$(dirname "$0")/../.." && pwd)
old=${1:?usage: run.sh OLD_REVISION [REPEAT]}
repeat=${2:-5}
work=${TMPDIR:-/tmp}/bvh_ab
python=${PYTHON:-$repo/.venv/bin/python}
mkdir -p "$work/render/accel" "$work/data"
[ -f "$work/data/sphere1m.mesh" ] || (cd "$repo" && "$python" tools/bvh_ab/dump_rays.py "$work/data")
# the old revision's BVH, every name renamed (Bvh -> OldBvh, bvh_ -> old_bvh_, ...)
for f in bvh.h bvh_traverse.h bvh_build.cpp; do
    git -C "$repo" show "$old:render/accel/$f" |
        sed -e 's#render/accel/bvh\.h#render/accel/old_bvh.h#' \
            -e 's/\bBvh/OldBvh/g; s/\bbvh_/old_bvh_/g; s/\bkBvh/kOldBvh/g; s/\bbuild_bvh\b/old_build_bvh/g' \
            >"$work/render/accel/old_$f"
done
flags="-O3 -DNDEBUG -std=c++20 -ffp-contract=off -I$work -I$repo"
c++ $flags -c "$work/render/accel/old_bvh_build.cpp" -o "$work/old_bvh_build.o"
c++ $flags -c "$repo/render/accel/bvh_build.cpp" -o "$work/bvh_build.o"
c++ $flags -c "$repo/render/accel/kdtree_build.cpp" -o "$work/kdtree_build.o"
c++ $flags -mavx2 -mfma "$repo/tools/bvh_ab/driver.cpp" "$work/old_bvh_build.o" "$work/bvh_build.o" \
    "$work/kdtree_build.o" -o "$work/driver"
d=$work/data
uptime
"$work/driver" "$repeat" "$d/icosphere.mesh" "$d/random.icosphere.rays" "$d/boxes.mesh" "$d/random.boxes.rays" \
    "$d/boxes.mesh" "$d/shadow.boxes.rays" "$d/preview.mesh" "$d/replay.path.rays" \
    "$d/preview.mesh" "$d/replay.shadow.rays" "$d/icosphere.mesh" "$d/primary.icosphere.rays" \
    "$d/sphere1m.mesh" - "$d/boxes.mesh" - "$d/icosphere.mesh" -
uptime
