#!/bin/sh
# The curved-obstacle scenes run through their impact (t = 10): a ball
# dropped into a spherical bowl, a coin dropped on a cylinder
# (examples/scenes/ball_bowl.toml, disk_cylinder.toml), and a ball dropped on
# another (two_balls.toml: a contact pair, §10.3). Each must finish,
# touch (a positive contact force) and stay out of the obstacle (the
# penetration below the library's guard, half a cell: checked by the run),
# and its history's ledger (hybrid scheme, Theta = 1: docs/design.md
# §10.1) E_Theta + D_f + D - W - W_obstacle - W_prescribed - W_geometry
# must not rise from row to row by more than round-off (1e-12 of the
# largest energy in the run).
# And the sliding blocks with Coulomb friction (sliding_block.toml, and
# sliding_block_hex.toml in hexahedra, its ledger too; sliding_blocks.toml,
# a block over another with friction on the contact pair) dissipate.
# usage: obstacle_scenes.sh DRIVER SCENES_DIR WORK_DIR
set -u
driver=$1 scenes=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fails=0
# check_ledger NAME CSV: the ledger, read by column name from the history
check_ledger() {
  verdict=$(grep -v '^#' "$2" | awk -F, '
    NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
    { e = $c["E_Theta"] + $c["dissipation_friction"] + $c["dissipation_damping"] - $c["W"] - $c["W_obstacle"] \
          - $c["W_prescribed"] - $c["W_geometry"]
      s = ($c["E_Theta"] < 0 ? -$c["E_Theta"] : $c["E_Theta"]) + ($c["W"] < 0 ? -$c["W"] : $c["W"])
      if (s > scale) scale = s
      if (NR > 2 && e - prev > rise) rise = e - prev
      prev = e; wg = $c["W_geometry"] }
    END { printf "%s %.3g %.3g %.3g\n", (rise <= 1e-12 * scale ? "ok" : "FAIL"), rise, scale, wg }')
  case "$verdict" in
    ok*) echo "ok: $1: ledger (largest rise, scale, W_geometry) $verdict" ;;
    *) echo "FAIL: $1: ledger rose: (largest rise, scale, W_geometry) $verdict"; fails=$((fails + 1)) ;;
  esac
}
for s in ball_bowl disk_cylinder two_balls; do
  if ! "$driver" "$scenes/$s.toml" --quiet --T 14 --out "$work/$s" > "$work/$s.out" 2> "$work/$s.err"; then
    echo "FAIL: $s: $(cat "$work/$s.err")"
    fails=$((fails + 1))
    continue
  fi
  line=$(tail -1 "$work/$s.out")
  force=$(echo "$line" | sed -n 's/.*max contact force \([0-9.eE+-]*\).*/\1/p')
  if [ -z "$force" ] || ! awk -v f="$force" 'BEGIN { exit !(f > 0) }'; then
    echo "FAIL: $s: no contact force in: $line"
    fails=$((fails + 1))
  else
    echo "ok: $s: $line"
  fi
  csv="$work/$s/${s}_history.csv"
  check_ledger "$s" "$csv"
done
# the sliding blocks (examples/scenes/sliding_block.toml; sliding_block_hex.toml, a
# box of hexahedra, mesh.cell_type; sliding_blocks.toml, friction between two
# bodies, contact_pair.friction): friction dissipates (the history's column
# dissipation_friction, D_f, grows from 0 to a positive value); the hexahedra's
# run, the hybrid scheme with Theta = 1, also keeps the ledger
for s in sliding_block sliding_block_hex sliding_blocks; do
  if ! "$driver" "$scenes/$s.toml" --quiet --T 0.5 --out "$work/$s" > "$work/$s.out" 2> "$work/$s.err"; then
    echo "FAIL: $s: $(cat "$work/$s.err")"
    fails=$((fails + 1))
    continue
  fi
  csv="$work/$s/${s}_history.csv"
  col=$(grep -v '^#' "$csv" | head -1 | tr , '\n' | grep -n '^dissipation_friction$' | cut -d: -f1)
  last=$(grep -v '^#' "$csv" | tail -1 | cut -d, -f"${col:-1}")
  if [ -z "$col" ] || ! awk -v d="$last" 'BEGIN { exit !(d > 0) }'; then
    echo "FAIL: $s: no frictional dissipation in $csv (last column dissipation_friction = $last)"
    fails=$((fails + 1))
  else
    echo "ok: $s: D_f = $last at t = 0.5"
  fi
  [ $s = sliding_block_hex ] && check_ledger "$s" "$csv"
  # the one pair's columns (its slave region's, nd_get_region_scalar) are the
  # whole problem's: it holds every contact point
  if [ $s = sliding_blocks ]; then
    verdict=$(grep -v '^#' "$csv" | awk -F, '
      NR == 1 { for (i = 1; i <= NF; ++i) { c[$i] = i; if ($i ~ /^pair[0-9]+_contact_force$/) p = $i }
                sub(/_contact_force$/, "", p); next }
      { n++; if ($c[p "_contact_force"] != $c["contact_force"] || $c[p "_active_points"] != $c["active_points"] ||
                 $c[p "_dissipation_friction"] != $c["dissipation_friction"]) bad++ }
      END { print (p != "" && n > 0 && bad == 0) ? "ok " p : "FAIL " p " " bad+0 " of " n+0 }')
    case "$verdict" in
      ok*) echo "ok: $s: the pair's columns ($verdict) are the problem's at every step" ;;
      *) echo "FAIL: $s: the pair's columns differ from the problem's ($verdict)"; fails=$((fails + 1)) ;;
    esac
  fi
done
[ $fails -eq 0 ] || exit 1
