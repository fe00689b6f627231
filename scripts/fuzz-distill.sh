#!/bin/sh
# Distils what long fuzz runs found into the committed seed archives
# tests/fuzz/corpus/<target>-distilled.tar.gz: libFuzzer's -merge=1 keeps,
# of the committed seeds, the archive's inputs and the corpus a fuzz build
# has grown (BUILD/fuzz-corpus/<target>, e.g. after
# `sh scripts/fuzz.sh build-fuzz 2700`), the fewest inputs that cover every
# feature any of them covers. scripts/fuzz.sh replays them before it mutates,
# so that a short run (the CI's 60 s) starts from what hours reached.
#   usage: fuzz-distill.sh BUILD_DIR   (a `make fuzz` build)
set -eu
build=${1:-build-fuzz}
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export ASAN_OPTIONS="detect_leaks=0:allocator_may_return_null=1"
for t in fuzz_gmsh fuzz_api fuzz_checkpoint fuzz_scene; do
  archive="$src/tests/fuzz/corpus/$t-distilled.tar.gz"
  mkdir -p "$tmp/old" "$tmp/$t"
  [ -f "$archive" ] && tar xzf "$archive" -C "$tmp/old"
  mkdir -p "$tmp/old/$t" "$build/fuzz-corpus/$t"
  "$build/tests/fuzz/$t" -merge=1 -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=512 "$tmp/$t" \
    "$src/tests/fuzz/corpus/$t" "$tmp/old/$t" "$build/fuzz-corpus/$t" > "$build/$t-distill.log" 2>&1
  # sorted names and fixed metadata: the same inputs make the same archive
  (cd "$tmp" && find "$t" -type f | LC_ALL=C sort |
     tar -c --owner=0 --group=0 --numeric-owner --mtime=@0 -T - | gzip -n -9 > "$archive")
  echo "$t: $(ls "$tmp/$t" | wc -l) inputs, $(wc -c < "$archive") bytes: $archive"
  rm -rf "$tmp/old"
done
