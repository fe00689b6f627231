#!/bin/sh
# Are the serial histories of this build bitwise those of the committed
# bench (bench/results/history/ours_*.csv)? Not a test: a check after a
# change meant to keep the numerics (a memory or speed change). It runs
# disk_bench on three short scenes of `make bench` (disk_h4 P1, disk_h1 P2,
# ball_h4 P1; Newmark, tau = 0.05, T = 32 as there) and compares t, E, the
# contact force and the Newton iterations (not the step times). The bits
# depend on the kernels OpenBLAS picks by CPU (two "AMD EPYC" differed at
# round-off: Zen's kernels on one, Cooperlake's AVX-512 ones on the other),
# so it asks for the committed bench's (bench/results/machine.txt,
# blas_core) with OPENBLAS_CORETYPE; on a CPU without the instructions they
# need, or results that do not name them and another CPU model than theirs,
# it says so and compares nothing.
# usage: sh bench/same_histories.sh [BUILD_DIR]   (exit 1: a history differs)
set -eu
build=${1:-build}
machine=bench/results/machine.txt
core=$(sed -n 's/^blas_core=//p' "$machine")
flags=" $(grep -m1 '^flags' /proc/cpuinfo | cut -d: -f2) "
# the instructions of each kernel set (ours need AVX2 and FMA in any case)
case $core in
  Haswell | Zen) need="avx2 fma" ;;
  SkylakeX) need="avx2 fma avx512f avx512cd avx512bw avx512dq avx512vl" ;;
  Cooperlake) need="avx2 fma avx512f avx512cd avx512bw avx512dq avx512vl avx512_bf16" ;;
  *) need="" ;;
esac
if [ -n "$need" ]; then
  for f in $need; do
    case $flags in
      *" $f "*) ;;
      *) echo "not compared: this CPU lacks $f, which the committed bench's BLAS kernels ($core) use"; exit 0 ;;
    esac
  done
  export OPENBLAS_CORETYPE="$core"
  echo "with OpenBLAS's $core kernels, as the committed bench"
else
  here=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
  there=$(sed -n 's/^cpu=//p' "$machine")
  if [ "$here" != "$there" ]; then
    echo "not compared: this CPU ($here) is not the committed bench's ($there)"
    exit 0
  fi
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
