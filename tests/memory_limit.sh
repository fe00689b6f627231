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
    # (the time is printed, not judged: a loaded machine runs it slower; the
    # 30 s timeout tells a hang)
    echo "ulimit -v $limit (start + $((extra / 1024)) MiB), solver $solver: $out ($took s) $verdict"
    [ "$verdict" = ok ] || status=1
  done
done
# Two BLAS threads (as OPENBLAS_NUM_THREADS unset on two cores): OpenBLAS's
# worker thread, started when the library is loaded, takes its buffer as it
# starts and, under start + 64 MiB, may retry forever (one core busy) before
# any function of the library runs; the library's call still answers
# ND_ERR_NOMEM at once (it runs the BLAS on one thread), and the process
# may then hang at exit, where OpenBLAS joins that thread (man
# libnitschedyn, BUGS): the answer must come within 20 s (it takes well
# under one alone; the spinning worker and a loaded machine slow the
# start), a hang at exit is reported and the process killed.
OPENBLAS_NUM_THREADS=2
unset OMP_NUM_THREADS
base=$("$prog" vmsize) || exit 1
limit=$((base + 65536))
answer=$(mktemp) || exit 1
for solver in "$@"; do
  (ulimit -v $limit && exec "$prog" step "$solver") > "$answer" 2>&1 &
  pid=$!
  tenths=0
  while [ $tenths -lt 200 ] && ! grep -q "^solver $solver: " "$answer" && kill -0 $pid 2>/dev/null; do
    sleep 0.1
    tenths=$((tenths + 1))
  done
  sleep 0.2  # (the exit, if it comes)
  if kill -0 $pid 2>/dev/null; then
    kill -9 $pid
    ended="the exit hung in OpenBLAS's worker thread: killed"
  else
    ended="exited"
  fi
  wait $pid 2>/dev/null
  out=$(grep "^solver $solver: " "$answer")
  case "$out" in
    "solver $solver: -20"*) verdict="ok (ND_ERR_NOMEM after about $tenths tenths of a second; $ended)" ;;
    *) verdict="no ND_ERR_NOMEM within 20 s ($ended): $(head -c 300 "$answer")"; status=1 ;;
  esac
  echo "2 BLAS threads, ulimit -v $limit (start + 64 MiB), solver $solver: $out: $verdict"
done
rm -f "$answer"
exit $status
