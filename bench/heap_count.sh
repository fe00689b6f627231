#!/bin/sh
# The whole-length arrays a rank holds (not a test): scaling_bench's heap
# columns (bench/heap_track.cpp, units of 8 n bytes) on the scenes of
# report/SCALING.md's count, one run each, into OUT (CSV):
#   ball_h2 P1 GAMG on 1, 2, 4 ranks with a distributed state, and on 1, 2
#   ranks with the state whole; disk_h1 P2 MUMPS on 1, 2 ranks and ball_h4
#   P2 GAMG on 2 ranks, distributed state. The hybrid scheme, tau = 0.25 to
#   T = 12 (the impact at t = 10). One BLAS/OpenMP thread per rank.
# The counts are exact (not timings): one run is enough. ~1 min.
# usage: sh bench/heap_count.sh [BUILD_DIR [OUT]]   (a -DND_WITH_PETSC=ON build)
set -eu
build=${1:-build-petsc}
out=${2:-bench/results/scaling_heap.csv}
meshes=examples/meshes
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_mpi_yield_when_idle=1 SCOTCH_PTHREAD_NUMBER=1
printf 'state,%s\n' "$("$build/scaling_bench" --header)" > "$out"
row() {  # state ranks mesh degree solver [dim]
  state=$1 ranks=$2 mesh=$3 degree=$4 solver=$5 dim=${6:-}
  if [ "$state" = distributed ]; then
    ND_BENCH_DISTRIBUTED_STATE=1 mpiexec -n "$ranks" "$build/scaling_bench" "$meshes/$mesh" "$degree" "$solver" 0.25 12 $dim
  else
    mpiexec -n "$ranks" "$build/scaling_bench" "$meshes/$mesh" "$degree" "$solver" 0.25 12 $dim
  fi | sed "s/^/$state,/" >> "$out"
}
for ranks in 1 2 4; do row distributed $ranks ball_h2.msh 1 gamg 3; done
for ranks in 1 2; do row whole $ranks ball_h2.msh 1 gamg 3; done
for ranks in 1 2; do row distributed $ranks disk_h1.msh 2 mumps; done
row distributed 2 ball_h4.msh 2 gamg 3
echo "written: $out" >&2
