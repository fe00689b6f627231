#!/bin/sh
# The driver against the example program of the same scene: both make the
# same library calls, so every energy the example prints (8 significant
# digits, once per time unit) must be the driver's CSV value at that time.
# Also checks the ParaView series (the .pvd and every .vtu it names).
#
# usage: compare_disk2d.sh DRIVER EXAMPLE SCENE WORK_DIR [T]
#   EXAMPLE  examples/disk2d or examples/ball3d (its defaults are the scene's:
#            P1, hybrid, Theta = 1, automatic gamma0, tau = 0.05)
set -eu
driver=$1 example=$2 scene=$3 work=$4 T=${5:-16}
rm -rf "$work"
mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

"$driver" "$scene" --T "$T" --out "$work" > "$work/driver.log" 2> "$work/driver.err" ||
  fail "the driver failed: $(cat "$work/driver.err")"
cat "$work/driver.log"
[ -s "$work/driver.err" ] && fail "the driver wrote to stderr (not a terminal: no progress bar): $(cat "$work/driver.err")"
mesh=$(sed -n 's/^gmsh *= *"\([^"]*\)".*/\1/p' "$scene")
case $mesh in /*) ;; *) mesh="$(dirname "$scene")/$mesh" ;; esac
"$example" --mesh "$mesh" --degree 1 --scheme hybrid --Theta 1 --gamma0 0 --tau 0.05 --T "$T" \
  > "$work/example.log" || fail "$example failed"
cat "$work/example.log"

# the same automatic gamma0
g_driver=$(sed -n 's/.*gamma0 = \([^ ]*\) (automatic.*/\1/p' "$work/driver.log")
g_example=$(sed -n 's/.*gamma0 = \([^ ]*\) (automatic.*/\1/p' "$work/example.log")
[ -n "$g_driver" ] && [ "$g_driver" = "$g_example" ] || fail "gamma0: driver '$g_driver', example '$g_example'"

csv=$(ls "$work"/*_history.csv)
# the comments first (the scene's title: "# title: ..."), then the header
header=$(grep -v '^#' "$csv" | head -1)
[ "$header" = "step,t,E,E_Theta,W,contact_force,active_points,max_penetration,newton_iterations,contact_force_applied,W_obstacle,W_prescribed,dissipation_friction,dissipation_damping,W_geometry" ] ||
  fail "$csv: unexpected header $header"
title=$(sed -n 's/^title *= *"\(.*\)".*$/\1/p' "$scene")
[ -z "$title" ] || [ "$(head -1 "$csv")" = "# title: $title" ] || fail "$csv: line 1 is not '# title: $title'"
rows=$(($(grep -vc '^#' "$csv") - 1))
[ "$rows" -eq $((T * 20 + 1)) ] || fail "$csv has $rows rows, not $((T * 20 + 1))"

# example rows: t E E_Theta E_Theta-W force penetration Newton
awk -v csv="$csv" '
  BEGIN {
    FS = ","
    while ((getline line < csv) > 0) {
      n = split(line, f, ",")
      if (f[1] == "step" || line ~ /^#/) continue
      key = sprintf("%.3f", f[2])
      E[key] = f[3]; ET[key] = f[4]; W[key] = f[5]; F[key] = f[6]; P[key] = f[8]; N[key] = f[9]
    }
    FS = " "
  }
  function abs(x) { return x < 0 ? -x : x }
  function close_to(a, b, rel, floor) { return abs(a - b) <= rel * (abs(b) > floor ? abs(b) : floor) }
  NF == 7 && $1 ~ /^[0-9]+\.[0-9]+$/ {
    key = $1
    if (!(key in E)) { print "FAIL: t = " key " is not in the history"; bad++; next }
    scale = abs(E[key]) > 1 ? abs(E[key]) : 1
    ok = close_to(E[key], $2, 1e-7, 1) && close_to(ET[key], $3, 1e-7, 1) &&
         abs((ET[key] - W[key]) - $4) <= 1e-7 * scale && close_to(F[key], $5, 1e-5, 1e-6) &&
         close_to(P[key], $6, 1e-3, 1e-12) && N[key] == $7
    if (!ok) {
      printf "FAIL: t = %s: example %s %s %s %s %s %s, driver %s %s %s %s %s %s\n", key, $2, $3, $4, $5, $6, $7,
             E[key], ET[key], ET[key] - W[key], F[key], P[key], N[key]
      bad++
    }
    if (F[key] > 0) contact++
    compared++
  }
  END {
    if (compared < 5) { print "FAIL: only " compared " rows compared"; exit 1 }
    if (contact == 0) { print "FAIL: no compared time in contact"; exit 1 }
    printf "compared %d times (%d in contact): the same E, E_Theta, E_Theta - W, force, penetration, Newton\n",
           compared, contact
    exit bad > 0
  }' "$work/example.log" || fail "the driver and $(basename "$example") differ"

# the ParaView series: T + 1 frames (interval 1), each file present
pvd=$(ls "$work"/*.pvd)
frames=$(grep -c '<DataSet ' "$pvd")
[ "$frames" -eq $((T + 1)) ] || fail "$pvd names $frames frames, not $((T + 1))"
for f in $(sed -n 's/.*file="\([^"]*\)".*/\1/p' "$pvd"); do
  [ -s "$work/$f" ] || fail "$pvd names $f, which is not beside it"
  grep -q '<VTKFile' "$work/$f" || fail "$f is not a VTK file"
done
echo "ok: $pvd, $frames frames"
