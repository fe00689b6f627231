#!/bin/sh
# python3 -m nitschedyn.plot on a history of the driver (the disk, to t = 14,
# through the impact):
#  - without numpy, and without matplotlib (each hidden by a module of that
#    name on PYTHONPATH that raises ImportError): --help and argument errors
#    work, a plot fails with one line naming the Debian package, status 2;
#  - the driver writes the scene's title as "# title: ..." before the header,
#    and it is the plot's title (the file name without it);
#  - the plot draws contact_force_applied when the history has it (the
#    legend of the figure, as plot() returns it), and not otherwise;
#  - a PNG, beside the CSV by default; a file that is not a history is
#    refused with exit status 2.
# Every check runs and reports "FAIL: ..." (exit 1 if any failed). Exit 77
# (skipped) when matplotlib is not installed, after the checks without it.
# usage: test_plot.sh PYTHON DRIVER SCENE WORK_DIR   (PYTHONPATH: the package)
set -u
py=$1 driver=$2 scene=$3 work=$4
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
rm -rf "$work"
mkdir -p "$work"
"$driver" "$scene" --T 14 --out "$work" --quiet || { echo "FAIL: the driver failed"; exit 1; }
csv="$work/disk_history.csv"
title=$(sed -n 's/^title *= *"\(.*\)".*$/\1/p' "$scene")
[ -n "$title" ] || { echo "FAIL: $scene has no title"; exit 1; }

# ---- the history: the title as a comment, then the header -------------------
[ "$(sed -n 1p "$csv")" = "# title: $title" ] || fail "line 1 of the history is not '# title: $title': $(sed -n 1p "$csv")"
sed -n 2p "$csv" | grep -q '^step,t,E,' || fail "line 2 of the history is not the header: $(sed -n 2p "$csv")"

# ---- without numpy, without matplotlib --------------------------------------
mkdir -p "$work/no_numpy/numpy" "$work/no_matplotlib/matplotlib"
echo 'raise ImportError("numpy hidden by test_plot.sh")' > "$work/no_numpy/numpy/__init__.py"
echo 'raise ImportError("matplotlib hidden by test_plot.sh")' > "$work/no_matplotlib/matplotlib/__init__.py"
without() {  # without MODULE ARGS...: python3 -m nitschedyn.plot ARGS with MODULE hidden
  hide=$1
  shift
  PYTHONPATH="$work/no_$hide${PYTHONPATH:+:$PYTHONPATH}" "$py" -m nitschedyn.plot "$@"
}
for hide in numpy matplotlib; do
  case $hide in numpy) package=python3-numpy ;; *) package=python3-matplotlib ;; esac
  if [ $hide = matplotlib ] && ! "$py" -c 'import numpy' 2> /dev/null; then
    echo "(numpy is not installed: the checks with matplotlib hidden are those with numpy hidden)"
    continue
  fi
  without $hide --help > "$work/help_$hide.out" 2> "$work/help_$hide.err"
  status=$?
  [ $status -eq 0 ] && grep -q '^usage: python3 -m nitschedyn.plot' "$work/help_$hide.out" ||
    fail "--help without $hide: status $status: $(cat "$work/help_$hide.out" "$work/help_$hide.err")"
  without $hide > /dev/null 2> "$work/usage_$hide.err"
  status=$?
  [ $status -eq 2 ] && grep -q 'the following arguments are required' "$work/usage_$hide.err" &&
    ! grep -q Traceback "$work/usage_$hide.err" ||
    fail "no argument without $hide: status $status (not 2): $(cat "$work/usage_$hide.err")"
  without $hide "$csv" -o "$work/no_$hide.png" > /dev/null 2> "$work/plot_$hide.err"
  status=$?
  [ $status -eq 2 ] && [ "$(wc -l < "$work/plot_$hide.err")" -eq 1 ] && grep -q "$package" "$work/plot_$hide.err" ||
    fail "a plot without $hide: status $status (not 2), not one line naming $package: $(cat "$work/plot_$hide.err")"
  [ ! -e "$work/no_$hide.png" ] || fail "a plot without $hide wrote no_$hide.png"
done

if ! "$py" -c 'import matplotlib' 2> /dev/null; then
  [ $fails -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
  echo "skipped: matplotlib is not installed (apt-get install python3-matplotlib); the checks without it passed"
  exit 77
fi

# ---- the plot ---------------------------------------------------------------
"$py" -m nitschedyn.plot "$csv" -o "$work/plot.png" > "$work/plot.out" || fail "nitschedyn.plot failed"
[ "$(head -c 8 "$work/plot.png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || fail "plot.png is not a PNG"
[ "$(wc -c < "$work/plot.png")" -gt 20000 ] || fail "plot.png is suspiciously small"
grep -qF "($title)" "$work/plot.out" || fail "the plot's title is not the scene's '$title': $(cat "$work/plot.out")"
# the default output: beside the CSV
"$py" -m nitschedyn.plot "$csv" > "$work/default.log" || fail "nitschedyn.plot without -o failed"
[ -s "$work/disk_history.png" ] || fail "no disk_history.png beside the CSV: $(cat "$work/default.log")"
# what the figure holds: its title and the force panel's legend
drawn() {  # drawn CSV PNG: "title<TAB>legend of the force panel, |-separated"
  "$py" - "$1" "$2" << 'EOF'
import sys
from nitschedyn import plot
d = plot.plot(plot.read_history(sys.argv[1]), sys.argv[2])
print(d["title"] + "\t" + "|".join(d["legends"]["contact force"]))
EOF
}
out=$(drawn "$csv" "$work/drawn.png") || fail "plot.plot failed: $out"
[ "$(printf '%s\n' "$out" | cut -f1)" = "$title" ] || fail "plot.plot: the title is not '$title': $out"
printf '%s\n' "$out" | cut -f2 | tr '|' '\n' | grep -q '^contact_force_applied' ||
  fail "plot.plot: no contact_force_applied in the force panel's legend: $out"
printf '%s\n' "$out" | cut -f2 | tr '|' '\n' | grep -q '^contact_force ' ||
  fail "plot.plot: no contact_force in the force panel's legend: $out"
# without the title: the file name; without the column (an older driver's): not drawn
grep -v '^#' "$csv" | cut -d, -f1-9 > "$work/old_history.csv"
"$py" -m nitschedyn.plot "$work/old_history.csv" -o "$work/old.png" > "$work/old.out" ||
  fail "nitschedyn.plot on a history without title and contact_force_applied failed"
grep -qF "(old_history.csv)" "$work/old.out" || fail "without a title, not the file name: $(cat "$work/old.out")"
out=$(drawn "$work/old_history.csv" "$work/old_drawn.png") || fail "plot.plot failed without the column: $out"
! printf '%s\n' "$out" | grep -q contact_force_applied || fail "contact_force_applied drawn without the column: $out"
# not a history
printf 'a,b\n1,2\n' > "$work/bad.csv"
"$py" -m nitschedyn.plot "$work/bad.csv" -o "$work/bad.png" 2> "$work/bad.err"
[ $? -eq 2 ] && grep -q 'not a nitschedyn history' "$work/bad.err" || fail "bad.csv: $(cat "$work/bad.err")"
[ ! -e "$work/bad.png" ] || fail "bad.png written"

[ $fails -eq 0 ] || { echo "$fails check(s) failed"; exit 1; }
echo "ok: $work/plot.png ($(wc -c < "$work/plot.png") bytes) titled '$title' with contact_force_applied," \
  "the default output, the file name without a title, --help and a clear failure without numpy or matplotlib," \
  "a bad file refused"
