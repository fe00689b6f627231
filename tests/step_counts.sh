#!/bin/sh
# step_counts.sh DISK2D BAR1D: T / tau beyond what an int64_t holds, or NaN,
# is refused by the example drivers (exit 2, a message naming T / tau) before
# any step, instead of converting it (undefined behaviour; the drivers ran no
# step and exited 0). Issue 54, finding 6 (examples/step_count.h).
set -u
failed=0
expect_refused() {
  out=$(timeout 60 "$@" 2>&1)
  status=$?
  if [ "$status" -ne 2 ] || ! printf '%s\n' "$out" | grep -q "is not a number of steps"; then
    printf '%s\n' "$out" | tail -3
    echo "FAILED (exit $status): $*"
    failed=1
  else
    echo "refused: $*"
  fi
}
for T in 1e300 nan inf; do
  expect_refused "$1" --T "$T" --tau 1e-10 --quiet
done
# (bar1d refuses a value that is not finite when it reads it)
expect_refused "$2" --T 1e300 --tau 1e-10
expect_refused "$2" --T 1e19 --tau 1
expect_refused "$1" --T 1 --tau 0.05 --every nan --quiet
exit $failed
