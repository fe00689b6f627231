#!/bin/sh
# Demonstration scenes, run by `make demo` after the build:
#   sh scripts/demo.sh BUILD_DIR
# The 1D bar of docs/design.md §7 against its exact solution, with the hybrid scheme
# and with Newmark (beta = 1/4, gamma = 1/2): P1, Theta = 1, gamma0 = 0.2,
# NX = 80, T = 3 (one period); then the 2D disk of docs/design.md §7 through the
# command-line driver (P1, h = 4) and examples/disk2d (P2, h = 2), hybrid,
# Theta = 1, automatic gamma0. Exits non-zero as soon as a run fails.
set -e
# small systems: a multithreaded BLAS only spins (measured 7.5 vs 5.0 ms/step on the disk)
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"

if [ $# -ne 1 ]; then
  echo "usage: sh scripts/demo.sh BUILD_DIR" >&2
  exit 2
fi
bar1d="$1/bar1d"
if [ ! -x "$bar1d" ]; then
  echo "demo: $bar1d not found; build first (make)" >&2
  exit 1
fi

# the common scene; the scheme and its parameters come first
bar() { "$bar1d" "$@" --degree 1 --Theta 1 --gamma0 0.2 --nx 80 --T 3 --quiet; }

echo "== 1D bar, hybrid scheme (P1, Theta=1, gamma0=0.2, NX=80, T=3)"
bar hybrid
echo
echo "== 1D bar, Newmark beta=1/4 gamma=1/2 (P1, Theta=1, gamma0=0.2, NX=80, T=3)"
bar newmark --beta 0.25 --gamma 0.5
echo
echo "== 2D disk dropped on a plane, with the command-line driver (examples/scenes/disk.toml:"
echo "   P1, h = 4, hybrid, Theta=1, gamma0 automatic, tau=0.05, T=32)"
mkdir -p "$1/demo"
"$1/tools/cli/nitschedyn" examples/scenes/disk.toml --out "$1/demo"
echo "history (every 4 time units):"
grep -v '^#' "$1/demo/disk_history.csv" | awk -F, 'NR == 1 || (NR - 2) % 80 == 0' | cut -d, -f1-6
echo
echo "== the same disk, P2 on the finer mesh h = 2, with examples/disk2d"
"$1/disk2d" --degree 2 --mesh examples/meshes/disk_h2.msh --scheme hybrid --Theta 1 --tau 0.05 --T 32 --every 4
