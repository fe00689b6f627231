#!/bin/sh
# The C program of README.md compiles (warnings are errors) and runs.
# usage: readme_example.sh README CC INCLUDE_DIR LIBRARY_DIR WORK_DIR
set -eu
readme=$1 cc=$2 inc=$3 lib=$4 work=$5
mkdir -p "$work"
awk '/^```c$/{f=1;next} /^```$/{f=0} f' "$readme" > "$work/readme_example.c"
[ -s "$work/readme_example.c" ] || { echo "no C block in $readme"; exit 1; }
"$cc" -std=c11 -Wall -Wextra -Werror "$work/readme_example.c" -I"$inc" -L"$lib" -lnitschedyn \
  -Wl,-rpath,"$lib" -o "$work/readme_example"
"$work/readme_example"
