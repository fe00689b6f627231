#!/bin/sh
# Quadrilaterals and hexahedra (issue 60): the disk and ball of docs/design.md
# §7 meshed as transfinite O-grids (examples/meshes/disk_quad.geo,
# ball_hex.geo), Q1 and Q2, the scene of bench/run.sh (Newmark(1/4, 1/2),
# Theta = 1, gamma0 = 1e-3, tau = 0.05), ours (bench/disk_bench, one BLAS
# thread) and GetFEM's (bench/getfem_drop.py: GT_QK, FEM_QK,
# IM_GAUSS_PARALLELEPIPED) one after the other on each mesh; GetFEM only where
# its run takes minutes (the fifth field "ours": ours alone).
# Writes RESULTS/quads_ours.csv, quads_getfem.csv, history/{ours,getfem}_MESH_QP.csv
# and RESULTS/quads_check_brick.txt (GetFEM's brick on Q cells against
# docs/design.md §1's terms). Called by bench/run.sh (make bench, full plan).
#   sh bench/quads.sh BUILD_DIR [RESULTS]      (about 5 minutes on 2 cores)
set -eu
build=${1:-build}
out=${2:-bench/results}
meshes=examples/meshes
py=/usr/bin/python3
# mesh dim degree T [ours]
plan="disk_quad_h2:2:1:32 disk_quad_h2:2:2:32 ball_hex_h4:3:1:12 ball_hex_h4:3:2:11:ours ball_hex_h2:3:1:11:ours"
mkdir -p "$out/history"
ours=$out/quads_ours.csv getfem=$out/quads_getfem.csv
"$build/disk_bench" --header > "$ours"
$py bench/getfem_drop.py --header > "$getfem"
. bench/pair.sh
check_bricks "$out/quads_check_brick.txt" disk_quad_h4:2:1 disk_quad_h4:2:2 ball_hex_h4:3:1 ball_hex_h4:3:2
for entry in $plan; do
  run_pair "$ours" "$getfem" "$out/history" Q "$entry"
  echo "$tag: ours $(tail -1 "$ours" | cut -d, -f5,10,11,12,26) | getfem $([ -n "$only" ] && echo not run ||
    tail -1 "$getfem" | cut -d, -f4,7,8,13)"
done
