#!/bin/sh
# The Fortran example examples/disk2d_mpi.f90 on 2 ranks (MUMPS over
# MPI_COMM_WORLD) prints the same history as its serial reference (CHOLMOD,
# 1 rank): the same times, and E_Theta and the contact force within 1e-8 of
# the largest value of each column (the direct solvers differ by round-off);
# and the final displacement, gathered on rank 0 from the ranks that own
# the nodes (nd_get_field_gathered), within 1e-8 of its largest component.
# With LAYOUT distributed the MPI run keeps a distributed state
# (nd_problem_set_distributed_state), and the program checks its ranks'
# owned parts against the gathered field itself.
# usage: disk_mpi_agrees.sh MPIEXEC PROGRAM MESH WORK_DIR [LAYOUT]
set -eu
mpiexec=$1 prog=$2 mesh=$3 work=$4 layout=${5:-whole}
mkdir -p "$work"
rm -f "$work/serial_u.txt" "$work/mpi2_u.txt"
"$mpiexec" -n 1 --oversubscribe "$prog" "$mesh" serial 11 0.25 "$work/serial_u.txt" > "$work/serial.txt"
"$mpiexec" -n 2 --oversubscribe "$prog" "$mesh" mumps 11 0.25 "$work/mpi2_u.txt" "$layout" > "$work/mpi2.txt"
paste "$work/serial_u.txt" "$work/mpi2_u.txt" | awk '
  function abs(x) { return x < 0 ? -x : x }
  NF != 4 { print "malformed displacement line " NR ": " $0; bad = 1; exit }
  { for (j = 1; j <= 2; j++) { a[NR, j] = $j; b[NR, j] = $(j + 2); if (abs($j) > m) m = abs($j) } }
  END {
    if (bad) exit 1
    if (NR == 0 || m == 0) { print "no final displacement"; exit 1 }
    for (i = 1; i <= NR; i++) for (j = 1; j <= 2; j++) { d = abs(a[i, j] - b[i, j]) / m; if (d > md) md = d }
    printf "%d nodes: the gathered final displacement %.2e relative to the serial run\n", NR, md
    exit md <= 1e-8 ? 0 : 1
  }'
paste "$work/serial.txt" "$work/mpi2.txt" | awk '
  function abs(x) { return x < 0 ? -x : x }
  NF != 6 { print "malformed line " NR ": " $0; bad = 1; exit }
  { t[NR] = $1; t2[NR] = $4; e[NR] = $2; e2[NR] = $5; f[NR] = $3; f2[NR] = $6
    if (abs($2) > me) me = abs($2); if (abs($3) > mf) mf = abs($3) }
  END {
    if (bad) exit 1
    if (NR == 0 || mf == 0) { print "no history, or no impact in it"; exit 1 }
    for (i = 1; i <= NR; i++) {
      if (t[i] != t2[i]) { print "line " i ": t " t[i] " vs " t2[i]; exit 1 }
      de = abs(e[i] - e2[i]) / me; df = abs(f[i] - f2[i]) / mf
      if (de > mde) mde = de; if (df > mdf) mdf = df
    }
    printf "%d steps: energy %.2e, contact force %.2e relative to the serial run\n", NR, mde, mdf
    exit (mde <= 1e-8 && mdf <= 1e-8) ? 0 : 1
  }'
