#!/bin/sh
# The scenes with values in time (examples/scenes/bar_pushed.toml: a
# prescribed motion given as an expression in t; pulse.toml: a traction
# given as a table of (t, value) rows and a support swaying as an
# expression) run to their end, touch the plane, and keep the hybrid
# scheme's ledger (docs/design.md §3, §10.5): with Theta = 1 the history's
# E_Theta - W - W_obstacle - W_prescribed never rises from one row to the
# next, to round-off (1e-12 of the largest energy or work in the run; the
# CSV has 17 digits).
# usage: time_scenes.sh DRIVER SCENES_DIR WORK_DIR
set -u
driver=$1 scenes=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
for s in bar_pushed pulse; do
  if ! "$driver" "$scenes/$s.toml" --quiet --out "$work/$s" > "$work/$s.out" 2> "$work/$s.err"; then
    fail "$s: $(cat "$work/$s.err")"
    continue
  fi
  csv="$work/$s/${s}_history.csv"
  # columns: 4 E_Theta, 5 W, 6 contact_force, 11 W_obstacle, 12 W_prescribed
  report=$(grep -v '^#' "$csv" | awk -F, -v s="$s" '
    NR == 1 { if ($11 != "W_obstacle" || $12 != "W_prescribed") { print "header " $0; bad = 1 } next }
    {
      L[NR] = $4 - $5 - $11 - $12
      for (k = 4; k <= 12; k++) if (k != 6 && k != 7 && k != 8 && k != 9 && k != 10) {
        a = $k < 0 ? -$k : $k
        if (a > scale) scale = a
      }
      if ($6 > force) force = $6
      wp = $12; w = $5; n = NR
    }
    END {
      if (bad) exit 1
      rise = 0
      for (k = 3; k <= n; k++) if (L[k] - L[k - 1] > rise) rise = L[k] - L[k - 1]
      if (rise > 1e-12 * scale) { print "the ledger rose by " rise " (scale " scale ")"; exit 1 }
      if (!(force > 0)) { print "no contact force"; exit 1 }
      if (!(wp != 0)) { print "no work of the prescribed motion"; exit 1 }
      if (s == "pulse" && !(w > 0)) { print "the pulse did no work"; exit 1 }
      print "rows " n - 1 ", max contact force " force ", W " w ", W_prescribed " wp ", largest rise " rise
    }') || { fail "$s: $report"; continue; }
  echo "ok: $s: $report"
done
# Adaptive steps (bar_bounce_adaptive.toml, time.tolerance): the run ends at
# T = 3 exactly, a row lands at the first touch t = 0.1037 (a rigid flight:
# to round-off), the rows are not the 75 fixed steps of T/tau, and the
# ledger E_Theta - W - W_obstacle never rises past round-off.
s=bar_bounce_adaptive
if "$driver" "$scenes/$s.toml" --quiet --out "$work/$s" > "$work/$s.out" 2> "$work/$s.err"; then
  report=$(grep -v '^#' "$work/$s/${s}_history.csv" | awk -F, '
    NR == 1 { next }
    {
      L = $4 - $5 - $11
      if (NR > 2 && L - last > rise) rise = L - last
      last = L
      d = $2 - 0.1037; if (d < 0) d = -d
      if (NR == 2 || d < touch) touch = d
      t = $2; n = NR - 2
    }
    END {
      if (t != 3) { print "the run ended at t = " t ", not 3"; exit 1 }
      if (touch > 1e-12) { print "no row within 1e-12 of the touch (" touch ")"; exit 1 }
      if (n == 75) { print "75 steps: the fixed ones"; exit 1 }
      if (rise > 1e-13) { print "the ledger rose by " rise; exit 1 }
      print "steps " n ", touch to " touch ", largest rise " rise
    }') && echo "ok: $s: $report" || fail "$s: $report"
else
  fail "$s: $(cat "$work/$s.err")"
fi
[ $fails -eq 0 ] || exit 1
