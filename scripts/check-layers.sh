#!/bin/sh
# No folder of src/ includes a folder that stands above it in the data flow
# (docs/architecture.md §1): the order below, lowest first. A folder may
# include itself and any folder before it. src/fast, the step driver's fast
# paths, is included by src/problem alone (and itself): the method's folders
# (solve, monitor, ...) never see it.
# Usage: scripts/check-layers.sh [SRC_DIR]   (exit 1 and the offending lines)
src=${1:-$(dirname "$0")/../src}
order="common mesh fem parallel linalg assembly contact time solve fast monitor problem io capi"
rank() { i=0; for f in $order; do [ "$f" = "$1" ] && { echo $i; return; }; i=$((i + 1)); done; echo -1; }
bad=0
for dir in "$src"/*/; do
  folder=$(basename "$dir")
  r=$(rank "$folder")
  if [ "$r" -lt 0 ]; then echo "check-layers: src/$folder is not in the order; add it"; bad=1; continue; fi
  # every '#include "X/..."' of the folder's files
  for line in $(grep -n '#include "[a-z_]*/' "$dir"* | sed 's/[[:space:]]//g'); do
    target=$(echo "$line" | sed 's/.*#include"\([a-z_]*\)\/.*/\1/')
    t=$(rank "$target")
    if [ "$t" -gt "$r" ]; then
      echo "check-layers: $(echo "$line" | sed "s|^$src/||; s|^.*/src/||") : src/$folder includes src/$target, which stands above it"
      bad=1
    fi
    if [ "$target" = fast ] && [ "$folder" != fast ] && [ "$folder" != problem ]; then
      echo "check-layers: $(echo "$line" | sed "s|^$src/||; s|^.*/src/||") : src/$folder includes src/fast, the step driver's alone"
      bad=1
    fi
  done
done
[ $bad = 0 ] && echo "check-layers: no folder includes one above it ($order)"
exit $bad
