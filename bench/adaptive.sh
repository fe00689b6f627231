#!/bin/sh
# Adaptive time steps against fixed ones (bench/adaptive_run.c): the disk P1
# and P2 and the ball P1 of docs/design.md §7, fixed steps tau, tau/2, tau/4
# and adaptive steps of tau_max = tau at three tolerances, each run's error at
# T against a fixed-step reference on the same mesh. Part of make bench.
# usage: bench/adaptive.sh BUILD_DIR [OUT_FILE]
set -eu
build=$1 out=${2:-bench/results/adaptive.txt}
meshes=$(dirname "$0")/../examples/meshes
{
  echo "# bench/adaptive.sh, $(date -u +%Y-%m-%d), $(uname -m), $(nproc) cores, one BLAS thread"
  OPENBLAS_NUM_THREADS=1 "$build/adaptive_run" 2 "$meshes/disk_h4.msh" 1 14 0.003125 0.4 1e-2 1e-3 1e-4
  OPENBLAS_NUM_THREADS=1 "$build/adaptive_run" 2 "$meshes/disk_h4.msh" 2 14 0.003125 0.1 1e-2 1e-3 1e-4
  OPENBLAS_NUM_THREADS=1 "$build/adaptive_run" 3 "$meshes/ball_h4.msh" 1 12 0.0125 0.1 1e-2 1e-3 1e-4
} > "$out"
cat "$out"
