#!/bin/sh
# Issue 54, finding 3: under an address-space limit (ulimit -v) a step of
# every linear solver returns ND_ERR_NOMEM within seconds (or ND_OK where
# it fits), never hangs in OpenBLAS's endless retry of its work buffer.
#   memory_limit.sh PROGRAM SOLVER...
# One BLAS and one OpenMP thread: the worker threads OpenBLAS and libgomp
# start by themselves (when loaded, outside any call of the library) take
# their buffers and stacks there, which no library can check (man
# libnitschedyn, BUGS).
prog=$1
shift
OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
export OPENBLAS_NUM_THREADS OMP_NUM_THREADS
base=$("$prog" vmsize) || exit 1
status=0
# 64 MiB above the program's size at start: the problem's first allocations
# fit, OpenBLAS's 128 MiB buffer does not (this hung before the fix); 200 MiB:
# the buffer fits, the dense factor of 10,302 unknowns (850 MB) does not
for extra in 65536 204800; do
  limit=$((base + extra))
  for solver in "$@"; do
    start=$(date +%s)
    out=$( (ulimit -v $limit && exec timeout 30 "$prog" step "$solver") 2>&1)
    rc=$?
    took=$(($(date +%s) - start))
    case $rc in
      3) verdict=ok ;;                                   # ND_ERR_NOMEM
      0) [ $extra -gt 65536 ] && verdict=ok || verdict="ND_OK where ND_ERR_NOMEM was expected" ;;
      124) verdict="no answer after 30 s: a hang" ;;
      *) verdict="exit $rc: neither ND_OK nor ND_ERR_NOMEM" ;;
    esac
    [ "$verdict" = ok ] && [ $took -gt 10 ] && verdict="took $took s"
    echo "ulimit -v $limit (start + $((extra / 1024)) MiB), solver $solver: $out ($took s) $verdict"
    [ "$verdict" = ok ] || status=1
  done
done
# Two BLAS threads (as OPENBLAS_NUM_THREADS unset on two cores): OpenBLAS's
# worker thread, started when the library is loaded, takes its buffer as it
# starts and, under start + 64 MiB, retries forever (one core busy) before
# any function of the library runs; the library's call still answers
# ND_ERR_NOMEM at once (it runs the BLAS on one thread), and the process
# then hangs at exit, where OpenBLAS joins that thread (man libnitschedyn,
# BUGS): the answer must come within 5 s, the hang at exit is reported.
OPENBLAS_NUM_THREADS=2
unset OMP_NUM_THREADS
base=$("$prog" vmsize) || exit 1
limit=$((base + 65536))
for solver in "$@"; do
  start=$(date +%s)
  out=$( (ulimit -v $limit && exec timeout 5 "$prog" step "$solver") 2>&1)
  rc=$?
  took=$(($(date +%s) - start))
  case "$rc:$out" in
    "3:solver $solver: -20"*) verdict=ok ;;
    "124:solver $solver: -20"*) verdict="ok (ND_ERR_NOMEM at once; the exit hung in OpenBLAS's worker thread)" ;;
    *) verdict="no ND_ERR_NOMEM within 5 s (exit $rc)"; status=1 ;;
  esac
  echo "2 BLAS threads, ulimit -v $limit (start + 64 MiB), solver $solver: $out: $verdict"
done
exit $status
