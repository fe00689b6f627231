#!/bin/sh
# Benchmark of the Newton tangent solvers (not a test), docs/design.md §4:
#   bench/results/tangent_crossover.csv  one solve with k active points, the
#     refactorization against the low-rank update (the rule of lowrank_rank_limit)
#   bench/results/tangent_steps.csv      the whole bounce of the disk with each
#     path, step costs as ratios to the floor, with one BLAS thread and with
#     the BLAS default; the ball_h4 P1 bounce with one thread
# usage: sh bench/tangent.sh BUILD_DIR [OUT_DIR]
set -eu
build=${1:-build}
out=${2:-bench/results}
meshes=examples/meshes
mkdir -p "$out"
cross=$out/tangent_crossover.csv
echo "dim,mesh,degree,unknowns,contact_points,blas_threads,k,floor_ms,refactor_over_floor,lowrank_warm_over_floor,lowrank_one_point_changed_over_floor,column_cost_per_point_over_floor,lowrank_back_to_back_over_floor,two_solves_back_to_back_over_floor" > "$cross"
for m in disk_h4 disk_h2 disk_h1; do
  for d in 1 2; do OPENBLAS_NUM_THREADS=1 "$build/tangent_bench" crossover 2 "$meshes/$m.msh" $d >> "$cross"; done
done
for d in 1 2; do OPENBLAS_NUM_THREADS=1 "$build/tangent_bench" crossover 3 "$meshes/ball_h4.msh" $d >> "$cross"; done
echo "written: $cross"
steps=$out/tangent_steps.csv
echo "dim,mesh,degree,unknowns,contact_points,tangent,blas_threads,floor_ms,contact_steps,newton_per_contact_step,free_step_over_floor,contact_step_over_floor,per_newton_iteration_over_floor,contact_step_ms,slowest_contact_step_over_floor,columns,max_rank,refactorizations" > "$steps"
for threads in 1 default; do
  for m in disk_h4 disk_h2 disk_h1; do
    for d in 1 2; do
      if [ "$threads" = default ]; then
        env -u OPENBLAS_NUM_THREADS "$build/tangent_bench" run 2 "$meshes/$m.msh" $d >> "$steps"
      else
        OPENBLAS_NUM_THREADS=1 "$build/tangent_bench" run 2 "$meshes/$m.msh" $d >> "$steps"
      fi
    done
  done
done
# the ball (P1): up to ~900 active points, near the rank limit
OPENBLAS_NUM_THREADS=1 "$build/tangent_bench" run 3 "$meshes/ball_h4.msh" 1 >> "$steps"
echo "written: $steps"
