#!/bin/sh
# usage: check_exports.sh LIBRARY HEADER SOVERSION
# Fails if the library exports a symbol that is not nd_*, if a function of the
# header is not exported, or if the SONAME is not libnitschedyn.so.SOVERSION.
lib=$1 header=$2 major=$3
status=0
stray=$(nm -D --defined-only "$lib" | awk '{print $NF}' | grep -v '^nd_')
if [ -n "$stray" ]; then echo "exported symbols that are not nd_*:"; echo "$stray"; status=1; fi
exported=$(nm -D --defined-only "$lib" | awk '{print $NF}' | sort -u)
declared=$(grep -oE '\bnd_[a-z0-9_]+[[:space:]]*\(' "$header" | tr -d '( ' | sort -u)
missing=$(printf '%s\n' "$declared" | while read -r f; do
  printf '%s\n' "$exported" | grep -qx "$f" || echo "$f"; done)
if [ -n "$missing" ]; then echo "declared but not exported:"; echo "$missing"; status=1; fi
soname=$(objdump -p "$lib" | awk '/SONAME/{print $2}')
if [ "$soname" != "libnitschedyn.so.$major" ]; then echo "SONAME is '$soname'"; status=1; fi
n=$(printf '%s\n' "$exported" | wc -l)
[ $status -eq 0 ] && echo "ok: $n nd_* symbols exported, SONAME $soname"
exit $status
