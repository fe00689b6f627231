#!/bin/sh
# Runs every test program of a build under valgrind memcheck (no forking in
# Check, so that valgrind sees the test bodies). Fails on any memory error or
# definite leak. usage: check-valgrind.sh BUILD_DIR
set -u
build=${1:-build}
status=0 count=0
for t in "$build"/tests/test_* "$build"/tests/unit_*; do
  [ -f "$t" ] && [ -x "$t" ] || continue
  count=$((count + 1))
  if CK_FORK=no valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
       "$t" > "$t.valgrind.log" 2>&1; then
    echo "valgrind ok:     $(basename "$t")"
  else
    echo "valgrind FAILED: $(basename "$t")"; cat "$t.valgrind.log"; status=1
  fi
done
[ "$count" -gt 0 ] || { echo "no test programs in $build/tests"; exit 1; }
exit $status
