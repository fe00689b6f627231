#!/bin/sh
# The frictional contact step against the frictionless one, same mesh
# (docs/performance.md, "Friction"): the disk and the ball P1 landing with a
# tangential velocity, frictionless and with Coulomb's F = 0.3, hybrid and
# Newmark, tau = 0.05, to t = 16 (the bounce). Prints bench/friction_step.c's lines.
# usage: sh bench/friction.sh [BUILD_DIR]
set -eu
build=${1:-build}
cmake --build "$build" --target friction_step >/dev/null
export OPENBLAS_NUM_THREADS=1
for scheme in hybrid newmark; do
  "$build/friction_step" examples/meshes 4 16 "$scheme"
done
