#!/bin/sh
# Two builds of the library side by side (not a test): scaling_bench of
# each, interleaved, on 1 and 2 ranks with MUMPS (SOLVER=gamg in the
# environment: GAMG; MESHES="ball" or "disk": that scene only), for the before/after tables
# of report/SCALING.md. Scenes: disk_h0.5 P2 (hybrid, tau = 0.25 to T = 12,
# as bench/scaling.sh) and ball_h2 P1 (the same, 3D). One BLAS/OpenMP thread
# per rank. Every run is a row of OUT (CSV), with its version's label.
# usage: sh bench/scaling_ab.sh BUILD_A LABEL_A BUILD_B LABEL_B [OUT [REPEAT]]
#        (each BUILD a -DND_WITH_PETSC=ON build directory with scaling_bench;
#        ENV_A, ENV_B in the environment: a variable=value given to that
#        side's runs, e.g. ENV_B=ND_BENCH_DISTRIBUTED_STATE=1 with one build twice)
set -eu
a=$1 la=$2 b=$3 lb=$4
out=${5:-bench/results/scaling_ab.csv}
repeat=${6:-3}
solver=${SOLVER:-mumps}
scenes=${MESHES:-disk ball}
meshes=examples/meshes
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
export SCOTCH_PTHREAD_NUMBER=1  # (Open MPI's default polling, as bench/scaling.sh)
printf 'version,%s\n' "$("$b/scaling_bench" --header)" > "$out"
run() {  # build label env ranks mesh degree [dim]
  env ${3:-ND_BENCH_NOTHING=} mpiexec -n "$4" "$1/scaling_bench" "$5" "$6" "$solver" 0.25 12 ${7:-} |
    sed "s/^/$2,/" >> "$out"
}
i=0
while [ $i -lt "$repeat" ]; do
  for ranks in 1 2; do
    for scene in $scenes; do
      if [ "$scene" = disk ]; then set -- "$meshes/disk_h0.5.msh" 2; else set -- "$meshes/ball_h2.msh" 1 3; fi
      run "$a" "$la" "${ENV_A:-}" $ranks "$@"
      run "$b" "$lb" "${ENV_B:-}" $ranks "$@"
    done
  done
  i=$((i + 1))
done
# the medians of each configuration
python3 - "$out" <<'EOF'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
keys = sorted({(r['mesh'], r['ranks'], r['version']) for r in rows})
print('| mesh | ranks | version | set-up s | free flight ms | contact step ms | peak RSS/rank MB |')
print('|---|---|---|---|---|---|---|')
for mesh, ranks, version in keys:
    sel = [r for r in rows if (r['mesh'], r['ranks'], r['version']) == (mesh, ranks, version)]
    med = lambda k: statistics.median(float(r[k]) for r in sel)
    print(f"| {mesh.split('/')[-1]} | {ranks} | {version} | {med('setup_s'):.3f} | {med('free_median_ms'):.2f} | "
          f"{med('contact_median_ms'):.1f} | {med('peak_rss_mb_max'):.1f} |")
EOF
