#!/bin/sh
# Every key of the scene file (nitschedyn --list-keys: "table.key") is in
# nitschedyn(1): each table as a subsection .Ss "[table]", each key as Cm key.
# usage: man_keys.sh DRIVER PAGE
set -u
driver=$1 page=$2
fails=0
keys=$("$driver" --list-keys) || { echo "FAIL: --list-keys"; exit 1; }
[ -n "$keys" ] || { echo "FAIL: --list-keys lists nothing"; exit 1; }
has_table() { grep -qxF ".Ss [$1]" "$page"; }
has_key() { grep -E '^\.(It|Cm)' "$page" | grep -qE "(^\\.| )Cm $1( |$)"; }
for k in $keys; do
  case $k in
    *.*) table=${k%%.*} key=${k##*.}
         has_table "$table" || { echo "FAIL: $page has no subsection [$table] (for $k)"; fails=$((fails + 1)); }
         has_key "$key" || { echo "FAIL: $page does not document $k (Cm $key)"; fails=$((fails + 1)); } ;;
    *)   has_table "$k" || has_key "$k" || { echo "FAIL: $page documents neither [$k] nor $k"; fails=$((fails + 1)); } ;;
  esac
done
[ $fails -eq 0 ] || exit 1
echo "ok: $(echo "$keys" | wc -l) keys documented in $(basename "$page")"
