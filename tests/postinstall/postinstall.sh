#!/bin/sh
# Post-install tests: install the build tree into a fresh prefix (what
# `make install PREFIX=...` does: cmake --install BUILD --prefix PREFIX), check
# the installed files, then use the installation the way a user would.
#
# usage: postinstall.sh MODE BUILD_DIR SOURCE_DIR WORK_DIR CC LIBDIR INCLUDEDIR MANDIR VERSION
#   MODE  pkgconfig  build and run tests/postinstall/consumer.c with
#                    `pkg-config --cflags --libs nitschedyn`
#         cmake      the same through find_package(nitschedyn) in
#                    tests/postinstall/cmake_consumer
#         man        `man -M PREFIX/MANDIR` finds a page for every function,
#                    and nitschedyn(1)
#         driver     the installed bin/nitschedyn runs the disk scene with the
#                    installed library (its rpath), without LD_LIBRARY_PATH
#   LIBDIR, INCLUDEDIR, MANDIR are CMAKE_INSTALL_LIBDIR, ..._INCLUDEDIR,
#   ..._MANDIR (relative to the prefix); VERSION is major.minor.patch.
# Exit status 0: passed, 1: failed, 77: skipped (a tool is missing).
set -eu
mode=$1 build=$2 src=$3 work=$4 cc=$5 libdir=$6 includedir=$7 mandir=$8 version=$9
major=${version%%.*}
prefix="$work/prefix"
fail() { echo "FAIL: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$prefix" > "$work/install.log" 2>&1 ||
  { cat "$work/install.log"; fail "cmake --install $build --prefix $prefix"; }

# ---- the installed files ---------------------------------------------------
lib="$prefix/$libdir"
[ -f "$lib/libnitschedyn.so.$version" ] || fail "no $libdir/libnitschedyn.so.$version"
[ "$(readlink "$lib/libnitschedyn.so.$major")" = "libnitschedyn.so.$version" ] ||
  fail "$libdir/libnitschedyn.so.$major is not a link to libnitschedyn.so.$version"
[ "$(readlink "$lib/libnitschedyn.so")" = "libnitschedyn.so.$major" ] ||
  fail "$libdir/libnitschedyn.so is not a link to libnitschedyn.so.$major"
cmp -s "$src/include/nitschedyn.h" "$prefix/$includedir/nitschedyn.h" ||
  fail "$includedir/nitschedyn.h is not include/nitschedyn.h"
for page in "$src"/man/*.3; do
  cmp -s "$page" "$prefix/$mandir/man3/$(basename "$page")" || fail "$mandir/man3/$(basename "$page") is missing or differs"
done
for page in "$src"/man/*.1; do
  cmp -s "$page" "$prefix/$mandir/man1/$(basename "$page")" || fail "$mandir/man1/$(basename "$page") is missing or differs"
done
[ -x "$prefix/bin/nitschedyn" ] || fail "no bin/nitschedyn"
[ -f "$lib/pkgconfig/nitschedyn.pc" ] || fail "no $libdir/pkgconfig/nitschedyn.pc"
for f in nitschedynConfig.cmake nitschedynConfigVersion.cmake nitschedynTargets.cmake; do
  [ -f "$lib/cmake/nitschedyn/$f" ] || fail "no $libdir/cmake/nitschedyn/$f"
done

# the program must use the installed library, not the build tree's
uses_installed() { # program
  resolved=$(ldd "$1" | awk '/libnitschedyn\.so/ { print $3; exit }')
  [ -n "$resolved" ] || fail "$1 does not load libnitschedyn.so: $(ldd "$1")"
  [ "$(readlink -f "$resolved")" = "$(readlink -f "$lib/libnitschedyn.so.$version")" ] ||
    fail "$1 loads $resolved, not the installed $lib/libnitschedyn.so.$version"
}

case $mode in
pkgconfig)
  command -v pkg-config >/dev/null 2>&1 || { echo "skipped: pkg-config not found"; exit 77; }
  PKG_CONFIG_PATH="$lib/pkgconfig"
  export PKG_CONFIG_PATH
  pkg-config --exists --print-errors nitschedyn || fail "pkg-config does not find nitschedyn in $PKG_CONFIG_PATH"
  [ "$(pkg-config --modversion nitschedyn)" = "$version" ] ||
    fail "pkg-config --modversion nitschedyn is $(pkg-config --modversion nitschedyn), expected $version"
  cflags=$(pkg-config --cflags nitschedyn)
  libs=$(pkg-config --libs nitschedyn)
  static_libs=$(pkg-config --libs --static nitschedyn)
  echo "pkg-config --cflags: $cflags"
  echo "pkg-config --libs: $libs"
  echo "pkg-config --libs --static: $static_libs"
  pc_libdir=$(pkg-config --variable=libdir nitschedyn)
  [ "$(readlink -f "$pc_libdir")" = "$(readlink -f "$lib")" ] || fail "libdir=$pc_libdir is not $lib"
  case " $libs " in *" -lnitschedyn "*) ;; *) fail "--libs lacks -lnitschedyn" ;; esac
  case " $libs " in *" -llapack"*|*" -lstdc++ "*) fail "--libs has private libraries: $libs" ;; esac
  case " $static_libs " in *" -lstdc++ "*) ;; *) fail "--libs --static lacks -lstdc++: $static_libs" ;; esac
  # shellcheck disable=SC2086
  "$cc" -std=c11 -Wall -Wextra -Werror "$src/tests/postinstall/consumer.c" $cflags $libs -lm \
    -o "$work/consumer" || fail "the consumer does not build with pkg-config's flags"
  # every library of Libs.private exists (a static link would need them all)
  # shellcheck disable=SC2086
  "$cc" -std=c11 "$src/tests/postinstall/consumer.c" $cflags $static_libs \
    -o "$work/consumer_private" || fail "the libraries of Libs.private do not all link"
  LD_LIBRARY_PATH="$lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  export LD_LIBRARY_PATH
  uses_installed "$work/consumer"
  "$work/consumer" || fail "the pkg-config consumer failed"
  ;;
cmake)
  cmake -S "$src/tests/postinstall/cmake_consumer" -B "$work/consumer-build" \
    -DCMAKE_C_COMPILER="$cc" -DCMAKE_PREFIX_PATH="$prefix" -DND_VERSION="$version" \
    -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON > "$work/configure.log" 2>&1 ||
    { cat "$work/configure.log"; fail "the CMake consumer does not configure"; }
  grep 'nitschedyn .* from' "$work/configure.log" || true
  found=$(sed -n 's/^nitschedyn_DIR:PATH=//p' "$work/consumer-build/CMakeCache.txt")
  [ "$(readlink -f "$found")" = "$(readlink -f "$lib/cmake/nitschedyn")" ] ||
    fail "find_package found nitschedyn in $found, not in $lib/cmake/nitschedyn"
  cmake --build "$work/consumer-build" > "$work/build.log" 2>&1 ||
    { cat "$work/build.log"; fail "the CMake consumer does not build"; }
  uses_installed "$work/consumer-build/consumer"
  "$work/consumer-build/consumer" || fail "the CMake consumer failed"
  ;;
man)
  command -v man >/dev/null 2>&1 || { echo "skipped: man not found (apt-get install man-db)"; exit 77; }
  mp="$prefix/$mandir"
  show() { MANPAGER=cat PAGER=cat MANWIDTH=80 man -M "$mp" "$@" 2>/dev/null; }   # not a tty: plain text
  out=$(show nd_step)
  printf '%s\n' "$out" | sed -n '1,12p'
  printf '%s\n' "$out" | grep -q 'nd_step.*advance a problem by one time step' || fail "man nd_step does not show nd_step(3)"
  printf '%s\n' "$out" | grep -q 'SYNOPSIS' || fail "man nd_step has no SYNOPSIS"
  out=$(show nd_mesh_destroy)
  printf '%s\n' "$out" | grep -q '^ND_MESH_CREATE(3)' || fail "man nd_mesh_destroy does not show nd_mesh_create(3)"
  printf '%s\n' "$out" | grep -q 'nd_mesh_destroy(nd_mesh \*m)' || fail "man nd_mesh_destroy lacks its synopsis"
  echo "man nd_mesh_destroy: $(printf '%s\n' "$out" | sed -n 1p)"
  show 3 libnitschedyn | grep -q 'The life of a simulation' || fail "man 3 libnitschedyn does not show the overview"
  n=0
  for f in $(grep -oE '\bnd_[a-z0-9_]+[[:space:]]*\(' "$src/include/nitschedyn.h" | tr -d '( ' | sort -u); do
    man -M "$mp" -w "$f" > /dev/null 2>&1 || fail "man -M $mp $f finds no page"
    show "$f" | grep -q "$f" || fail "man -M $mp $f shows a page that does not name $f"
    n=$((n + 1))
  done
  echo "man: all $n functions of the header have a page"
  show 1 nitschedyn | grep -q 'run a dynamic contact scene' || fail "man 1 nitschedyn does not show nitschedyn(1)"
  echo "man: nitschedyn(1)"
  ;;
driver)
  uses_installed "$prefix/bin/nitschedyn"
  (unset LD_LIBRARY_PATH; "$prefix/bin/nitschedyn" --version) || fail "bin/nitschedyn --version"
  (unset LD_LIBRARY_PATH; "$prefix/bin/nitschedyn" "$src/examples/scenes/disk.toml" --T 2 --out "$work/run" --quiet) ||
    fail "bin/nitschedyn on examples/scenes/disk.toml"
  [ "$(grep -vc "^#" "$work/run/disk_history.csv")" -eq 42 ] || fail "the history has not 41 rows"
  ;;
*)
  fail "unknown mode $mode"
  ;;
esac
echo "ok: postinstall $mode"
