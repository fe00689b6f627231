#!/bin/sh
# The contact step on a curved obstacle against the plane, same mesh
# (docs/performance.md, "Curved obstacles"): the ball P1 dropped on the plane
# z = 0, on a sphere of radius 100 tangent to it (outside) and into a bowl of
# radius 100 (inside), hybrid, tau = 0.05, to t = 16 (the bounce), on the
# meshes h = 4 and h = 2. Prints bench/obstacle_step.c's lines.
# usage: sh bench/obstacles.sh [BUILD_DIR]
set -eu
build=${1:-build}
cmake --build "$build" --target obstacle_step >/dev/null
export OPENBLAS_NUM_THREADS=1
for h in 4 2; do
  "$build/obstacle_step" examples/meshes "$h" 16 100
done
