#!/bin/sh
# Benchmark of the 2D disk (not a test): P1 and P2 on the committed meshes
# h = 4, 2, 1 (and 0.5 when gmsh is there to make it), hybrid scheme,
# Theta = 1, gamma0 = 1e-3, tau = 0.05, T = 32 (the whole bounce).
# usage: sh bench/run.sh BUILD_DIR [OUT.csv]   (make bench)
set -eu
build=${1:-build}
out=${2:-bench/results/disk.csv}
meshes=examples/meshes
export OPENBLAS_NUM_THREADS="${OPENBLAS_NUM_THREADS:-1}"
list="$meshes/disk_h4.msh:4 $meshes/disk_h2.msh:2 $meshes/disk_h1.msh:1"
if command -v gmsh >/dev/null 2>&1; then
  gmsh -2 -setnumber h 0.5 -format msh41 "$meshes/disk.geo" -o "$build/disk_h0.5.msh" >/dev/null
  list="$list $build/disk_h0.5.msh:0.5"
fi
mkdir -p "$(dirname "$out")"
echo "dim,mesh,h,degree,unknowns,steps,solver,setup_s,first_step_s,median_step_ms,mean_step_ms,newton_per_step,floor_solve_ms,median_over_floor,peak_rss_mb" > "$out"
for entry in $list; do
  mesh=${entry%%:*} h=${entry##*:}
  for degree in 1 2; do
    row=$("$build/disk_bench" 2 "$mesh" "$degree" 0.05 32 0)
    echo "$row" | awk -F, -v h="$h" 'BEGIN{OFS=","} {n=split($2,a,"/"); $2=a[n]; print $1,$2,h,$3,$4,$5,$6,$7,$8,$9,$10,$11,$12,$13,$14}' >> "$out"
    tail -1 "$out"
  done
done
echo "written: $out"
# what the guards cost a free-flight step (DESIGN §3b: at most 5 %)
guards=$(dirname "$out")/guard_cost.csv
echo "degree,unknowns,median_step_ms_guarded,median_step_ms_unguarded,relative_cost,energy_evaluation_over_step" > "$guards"
for degree in 1 2; do
  "$build/guard_cost" "$meshes/disk_h1.msh" "$degree" >> "$guards"
done
cat "$guards"
# the Newton tangent solvers: the low-rank update against the refactorization
sh bench/tangent.sh "$build" "$(dirname "$out")"
