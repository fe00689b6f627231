#!/bin/sh
# Runs the libFuzzer targets of a fuzz build (make fuzz) for a bounded time,
# all at once (one core each), on copies of their committed seed corpora
# and of the distilled archives of longer runs (scripts/fuzz-distill.sh).
# Fails on any crash, leak, timeout, out-of-memory or sanitizer report; the
# input that did it is left in BUILD/fuzz-artifacts/.
#   usage: fuzz.sh BUILD_DIR [SECONDS]
set -u
build=${1:-build-fuzz}
seconds=${2:-60}
src=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$build/fuzz-artifacts"
# leaks and UBSan reports are failures; a huge allocation must be refused by
# the library (ND_ERR_SIZE/NOMEM), so any single malloc over 512 MB is a bug
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
pids=""
for t in fuzz_gmsh fuzz_api fuzz_checkpoint fuzz_scene; do
  # a checkpoint of fuzz_checkpoint's problem has about 7 KB (the tangent's
  # history has its full room): room for it and for longer inputs
  max_len=4096
  [ "$t" = fuzz_checkpoint ] && max_len=16384
  corpus="$build/fuzz-corpus/$t"
  mkdir -p "$corpus"
  # the inputs long runs reached (scripts/fuzz-distill.sh), replayed first
  # with the seeds: fuzz_api's take about 25 of the 60 s in CI
  distilled="$build/fuzz-distilled"
  mkdir -p "$distilled/$t"
  archive="$src/tests/fuzz/corpus/$t-distilled.tar.gz"
  [ -f "$archive" ] && tar xzf "$archive" -C "$distilled"
  "$build/tests/fuzz/$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=512 \
    -max_len=$max_len -print_final_stats=1 -artifact_prefix="$build/fuzz-artifacts/$t-" \
    "$corpus" "$src/tests/fuzz/corpus/$t" "$distilled/$t" > "$build/$t.log" 2>&1 &
  pids="$pids $!:$t"
done
status=0
for pt in $pids; do
  pid=${pt%%:*} t=${pt#*:}
  if wait "$pid"; then
    echo "fuzz ok:     $t ($(grep -o 'stat::number_of_executed_units: *[0-9]*' "$build/$t.log" | grep -o '[0-9]*$') executions in ${seconds} s)"
  else
    echo "fuzz FAILED: $t (log: $build/$t.log, input in $build/fuzz-artifacts/)"; tail -60 "$build/$t.log"; status=1
  fi
done
exit $status
