#!/bin/sh
# The contact step of two bodies against one body on a plane, same mesh
# (docs/performance.md, "Two bodies"): the upper ball of
# examples/meshes/two_balls_hH.msh dropped on the lower one (a contact pair)
# and on the plane z = 0, P1, hybrid, tau = 0.05, to t = 12, on the meshes
# h = 4 and h = 2, with the share of a contact step the pairing takes.
# Prints bench/pair_search.cpp's lines.
# usage: sh bench/pairs.sh [BUILD_DIR]
set -eu
build=${1:-build}
cmake --build "$build" --target pair_search >/dev/null
export OPENBLAS_NUM_THREADS=1
for h in 4 2; do
  "$build/pair_search" examples/meshes "$h" 12
done
