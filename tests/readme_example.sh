#!/bin/sh
# Every C program of README.md compiles (warnings are errors) and runs, each
# from its own ```c block; with a Fortran compiler, so does the ```fortran one.
# usage: readme_example.sh README CC INCLUDE_DIR LIBRARY_DIR WORK_DIR [FC MODULE_DIR FORTRAN_LIBRARY_DIR]
set -eu
readme=$1 cc=$2 inc=$3 lib=$4 work=$5
# for users, not a notebook: at most 12000 bytes
size=$(wc -c < "$readme")
[ "$size" -le 12000 ] || { echo "README.md has $size bytes; at most 12000 (measurements belong in docs/ and bench/results)"; exit 1; }
mkdir -p "$work"
cd "$work"
# the k-th block into readme_c_k.c or readme_fortran_k.f90
awk 'BEGIN{k=0} $0 == "```c" {f=1; k++; next} $0 == "```fortran" {g=1; k++; next}
     /^```$/ {f=0; g=0} f {print > ("readme_c_" k ".c")} g {print > ("readme_fortran_" k ".f90")}' "$readme"
count=0
for src in readme_c_*.c; do
  [ -f "$src" ] || continue
  count=$((count + 1))
  "$cc" -std=c11 -Wall -Wextra -Werror "$src" -I"$inc" -L"$lib" -lnitschedyn -lm -Wl,-rpath,"$lib" -o "${src%.c}"
  echo "== $src"
  "./${src%.c}" | tee "${src%.c}.out"
done
[ "$count" -ge 2 ] || { echo "README.md has $count C programs; expected the complete program and the coupling loop"; exit 1; }
if [ $# -ge 8 ]; then
  fc=$6 mod=$7 flib=$8
  for src in readme_fortran_*.f90; do
    [ -f "$src" ] || { echo "no Fortran block in $readme"; exit 1; }
    "$fc" -std=f2018 -Wall -Wextra -Werror -I"$mod" "$src" -L"$flib" -lnitschedyn_fortran -L"$lib" -lnitschedyn \
      -Wl,-rpath,"$flib" -Wl,-rpath,"$lib" -o "${src%.f90}"
    echo "== $src"
    "./${src%.f90}" | tee "${src%.f90}.out"
  done
  # the twins agree: the same E_Theta(3) to the 6 digits both print
  e() { awk -F'=' '/E_Theta\(3\)/ {split($2, a, " "); print a[1]}' "$1"; }
  ec=$(e readme_c_1.out) ef=$(e readme_fortran_2.out)
  [ -n "$ec" ] && [ "$ec" = "$ef" ] || { echo "the C program printed E_Theta(3) = '$ec', its Fortran twin '$ef'"; exit 1; }
fi
