#!/bin/sh
# python3 -m nitschedyn.plot: a history of the driver (the disk, to t = 14,
# through the impact) gives a PNG; a file that is not a history is refused
# with exit status 2. Exit 77 (skipped) when matplotlib is not installed.
# usage: test_plot.sh PYTHON DRIVER SCENE WORK_DIR   (PYTHONPATH: the package)
set -u
py=$1 driver=$2 scene=$3 work=$4
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"
mkdir -p "$work"
"$py" -c 'import matplotlib' 2> /dev/null ||
  { echo "skipped: matplotlib is not installed (apt-get install python3-matplotlib)"; exit 77; }
"$driver" "$scene" --T 14 --out "$work" --quiet || fail "the driver failed"
csv="$work/disk_history.csv"
"$py" -m nitschedyn.plot "$csv" -o "$work/plot.png" || fail "nitschedyn.plot failed"
[ "$(head -c 8 "$work/plot.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "plot.png is not a PNG"
[ "$(wc -c < "$work/plot.png")" -gt 20000 ] || fail "plot.png is suspiciously small"
# the default output: beside the CSV
"$py" -m nitschedyn.plot "$csv" > "$work/default.log" || fail "nitschedyn.plot without -o failed"
[ -s "$work/disk_history.png" ] || fail "no disk_history.png beside the CSV: $(cat "$work/default.log")"
# not a history
printf 'a,b\n1,2\n' > "$work/bad.csv"
"$py" -m nitschedyn.plot "$work/bad.csv" -o "$work/bad.png" 2> "$work/bad.err"
[ $? -eq 2 ] && grep -q 'not a nitschedyn history' "$work/bad.err" || fail "bad.csv: $(cat "$work/bad.err")"
[ ! -e "$work/bad.png" ] || fail "bad.png written"
echo "ok: $work/plot.png ($(wc -c < "$work/plot.png") bytes), the default output, a bad file refused"
