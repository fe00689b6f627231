# Sourced by bench/run.sh and bench/quads.sh (after build, meshes, py are set).
# check_bricks FILE MESH:DIM:DEGREE...: GetFEM's Nitsche brick, as configured,
# against docs/design.md §1's terms, one line a mesh into FILE
check_bricks() {
  file=$1
  shift
  : > "$file"
  for c in "$@"; do
    IFS=: read -r mesh dim degree <<EOF
$c
EOF
    $py bench/getfem_drop.py --check-brick "$meshes/$mesh.msh" "$dim" "$degree" >> "$file"
  done
}
# run_pair OURS GETFEM HISTORY_DIR P|Q MESH:DIM:DEGREE:T[:ours]: sets mesh,
# dim, degree, T, only and tag (MESH_PDEGREE or _QDEGREE); our run (one BLAS
# thread) appended to OURS, then GetFEM's to GETFEM unless only is "ours";
# their histories HISTORY_DIR/{ours,getfem}_TAG.csv
run_pair() {
  IFS=: read -r mesh dim degree T only <<EOF
$5
EOF
  tag=${mesh}_$4$degree
  OPENBLAS_NUM_THREADS=1 "$build/disk_bench" "$dim" "$meshes/$mesh.msh" "$degree" 0.05 "$T" 0 newmark \
    "$3/ours_$tag.csv" >> "$1"
  [ "$only" = ours ] || OPENBLAS_NUM_THREADS=1 $py bench/getfem_drop.py "$meshes/$mesh.msh" "$dim" "$degree" 0.05 \
    "$T" "$3/getfem_$tag.csv" >> "$2"
}
