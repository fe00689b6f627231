#!/bin/sh
# The curved-obstacle scenes run through their impact (t = 10): a ball
# dropped into a spherical bowl, a coin dropped on a cylinder
# (examples/scenes/ball_bowl.toml, disk_cylinder.toml). Each must finish,
# touch (a positive contact force) and stay out of the obstacle (the
# penetration below the library's guard, half a cell: checked by the run).
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
[ $fails -eq 0 ] || exit 1
