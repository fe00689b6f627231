#!/bin/sh
# The curved-obstacle scenes run through their impact (t = 10): a ball
# dropped into a spherical bowl, a coin dropped on a cylinder
# (examples/scenes/ball_bowl.toml, disk_cylinder.toml). Each must finish,
# touch (a positive contact force) and stay out of the obstacle (the
# penetration below the library's guard, half a cell: checked by the run).
# And the sliding block with Coulomb friction (sliding_block.toml) dissipates.
# usage: obstacle_scenes.sh DRIVER SCENES_DIR WORK_DIR
set -u
driver=$1 scenes=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
fails=0
for s in ball_bowl disk_cylinder; do
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
done
# the sliding block (examples/scenes/sliding_block.toml): friction dissipates
# (the history's last column, D_f, grows from 0 to a positive value)
if ! "$driver" "$scenes/sliding_block.toml" --quiet --T 0.5 --out "$work/sliding_block" > "$work/sliding_block.out" \
     2> "$work/sliding_block.err"; then
  echo "FAIL: sliding_block: $(cat "$work/sliding_block.err")"
  fails=$((fails + 1))
else
  csv="$work/sliding_block/sliding_block_history.csv"
  last=$(grep -v '^#' "$csv" | tail -1 | awk -F, '{ print $NF }')
  header=$(grep -v '^#' "$csv" | head -1 | awk -F, '{ print $NF }')
  if [ "$header" != dissipation_friction ] || ! awk -v d="$last" 'BEGIN { exit !(d > 0) }'; then
    echo "FAIL: sliding_block: no frictional dissipation in $csv (last column $header = $last)"
    fails=$((fails + 1))
  else
    echo "ok: sliding_block: D_f = $last at t = 0.5"
  fi
fi
[ $fails -eq 0 ] || exit 1
