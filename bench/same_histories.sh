#!/bin/sh
# Are the serial histories of this build bitwise those of the committed
# bench (bench/results/history/ours_*.csv)? Not a test: a check after a
# change meant to keep the numerics (a memory or speed change). It runs
# disk_bench on three short scenes of `make bench` (disk_h4 P1, disk_h1 P2,
# ball_h4 P1; Newmark, tau = 0.05, T = 32 as there) and compares t, E, the
# contact force and the Newton iterations (not the step times). The bits
# depend on the CPU (OpenBLAS picks its kernels by CPU): on another CPU than
# the one bench/results/machine.txt names, it says so and compares nothing.
# usage: sh bench/same_histories.sh [BUILD_DIR]   (exit 1: a history differs)
set -eu
build=${1:-build}
here=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
there=$(sed -n 's/^cpu=//p' bench/results/machine.txt)
if [ "$here" != "$there" ]; then
  echo "not compared: this CPU ($here) is not the committed bench's ($there)"
  exit 0
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
for c in disk_h4:2:1 disk_h1:2:2 ball_h4:3:1; do
  IFS=: read -r mesh dim degree <<END
$c
END
  tag=${mesh}_P$degree
  OPENBLAS_NUM_THREADS=1 "$build/disk_bench" "$dim" "examples/meshes/$mesh.msh" "$degree" 0.05 32 0 newmark \
    "$tmp/$tag.csv" > /dev/null
  cut -d, -f1-4 "$tmp/$tag.csv" > "$tmp/ours"
  cut -d, -f1-4 "bench/results/history/ours_$tag.csv" > "$tmp/committed"
  if cmp -s "$tmp/ours" "$tmp/committed"; then
    echo "$tag: bitwise ($(wc -l < "$tmp/$tag.csv") rows)"
  else
    echo "$tag: DIFFERS from bench/results/history/ours_$tag.csv"
    status=1
  fi
done
exit $status
