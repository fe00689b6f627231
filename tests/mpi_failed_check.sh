#!/bin/sh
# mpi_failed_check.sh MPIEXEC N PROGRAM: the program's check fails on the last
# of N ranks only; the job must end (within 60 s, not at ctest's timeout),
# non-zero, with the failed check's message naming that rank.
set -u
out=$(timeout 60 "$1" -n "$2" --oversubscribe "$3" 2>&1)
status=$?
last=$(($2 - 1))
if [ "$status" -eq 124 ]; then
  echo "the job hung: a failed check left the other ranks waiting"; exit 1
fi
if [ "$status" -eq 0 ]; then
  echo "the job succeeded although a check failed"; exit 1
fi
if ! printf '%s\n' "$out" | grep -q "rank $last: a check failed on rank $last alone"; then
  printf '%s\n' "$out"; echo "the failed check's message is missing"; exit 1
fi
echo "the job ended with status $status and the message of rank $last"
