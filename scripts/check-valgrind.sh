#!/bin/sh
# Runs every test program of a build under valgrind memcheck (no forking in
# Check, so that valgrind sees the test bodies), JOBS programs at a time.
# Fails on any memory error or definite leak; prints each program's time so
# that CI shows where its minutes go.
# usage: check-valgrind.sh BUILD_DIR [JOBS]   (JOBS default 2)
#        check-valgrind.sh --one PROGRAM      (one program; used by the above)
set -u
if [ "${1:-}" = "--one" ]; then
  start=$(date +%s)
  # one BLAS thread: valgrind runs threads one at a time, and spinning BLAS
  # workers (OpenBLAS yields in a loop) would multiply the run time
  if CK_FORK=no OPENBLAS_NUM_THREADS=1 valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
       "$2" > "$2.valgrind.log" 2>&1; then
    echo "valgrind ok:     $(basename "$2") ($(( $(date +%s) - start )) s)"
  else
    echo "valgrind FAILED: $(basename "$2") ($(( $(date +%s) - start )) s)"; cat "$2.valgrind.log"
    exit 1
  fi
  exit 0
fi
build=${1:-build}
jobs=${2:-2}
count=0
for t in "$build"/tests/test_* "$build"/tests/unit_*; do
  [ -f "$t" ] && [ -x "$t" ] && count=$((count + 1))
done
[ "$count" -gt 0 ] || { echo "no test programs in $build/tests"; exit 1; }
for t in "$build"/tests/test_* "$build"/tests/unit_*; do
  [ -f "$t" ] && [ -x "$t" ] && echo "$t"
done | xargs -P "$jobs" -n 1 sh "$0" --one
