#!/bin/sh
# The manual pages are complete, correct and clean.
#
# usage: man_pages.sh SOURCE_DIR LIBRARY CC WORK_DIR
#   SOURCE_DIR  the project (man/*.3, include/nitschedyn.h)
#   LIBRARY     the built shared library (for nm -D and to run the example)
#   CC          a C compiler
#   WORK_DIR    scratch directory
#
# Checks, each reported as "FAIL: ..." (exit status 1 if any fails):
#  1. mandoc -Tlint -Wwarning is silent on every page (sections 1 and 3);
#  2. every function declared in the headers (nitschedyn.h, and
#     nitschedyn_mpi.h of the PETSc builds) and every nd_* symbol the library
#     exports has a page or an alias (an .Nm of a NAME section: that is how
#     cmake/install.cmake installs the aliases), and every nd_* name in a NAME
#     section is a function of the header;
#  3. every .Fn of a SYNOPSIS is exactly the header's prototype, and every
#     .Nm of a page has its .Fn in the page's SYNOPSIS;
#  4. every code in an ERRORS section (.It Bq Er CODE) is in ND_STATUS_LIST,
#     every ND_* identifier a page mentions exists in the header, and every C
#     page lists ND_ERR_NOMEM and ND_ERR_INTERNAL (the exception barrier);
#  5. every C page has the sections NAME, LIBRARY, SYNOPSIS, DESCRIPTION,
#     RETURN VALUES, EXAMPLES, ERRORS, THREAD SAFETY, SEE ALSO;
#  6. every .Xr to an nd_*/libnitschedyn/nitschedyn_* page resolves, and the
#     SEE ALSO of libnitschedyn(3) names every page of the C API;
#  7. the status table of nd_last_error(3) is ND_STATUS_LIST, value and text;
#  8. the EXAMPLES program of libnitschedyn(3) compiles with -Wall -Wextra
#     -Werror and runs; every other .Bd -literal block of the EXAMPLES of a C
#     page compiles as pasted (-fsyntax-only, the same warnings): it includes
#     what it uses. A block that is intentionally partial says so on its
#     first line, "/* assumes: DECLARATIONS */", and only DECLARATIONS are
#     put before it (a line "\&..." inside a block stands for elided code:
#     such a block is not compiled, and must say "/* assumes: ... */" too);
#  9. every page (sections 1 and 3) renders with mandoc -Tutf8 -Owidth=80
#     with no line longer than 80 columns;
# 10. neither the pages nor the library's strings (its messages) cite
#     DESIGN.md, which is not installed: they name a manual page instead.
# Examples are extracted from the mdoc source, with \e read as a backslash
# and \& dropped; any other escape in an example is an error.
set -u
src=$1 lib=$2 cc=$3 work=$4
man="$src/man"
header="$src/include/nitschedyn.h"
mpi_header="$src/include/nitschedyn_mpi.h"  # builds with PETSc: the MPI_Comm call
mkdir -p "$work"
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

command -v mandoc >/dev/null 2>&1 || { echo "mandoc not found"; exit 1; }
pages=$(ls "$man"/*.3 2>/dev/null)
[ -n "$pages" ] || { echo "no pages in $man"; exit 1; }

# ---- the header --------------------------------------------------------
# prototypes, one per line: "name<TAB>int nd_x(int a, double *b)"
awk '
  /^ND_EXPORT/ { decl = ""; on = 1 }
  on { decl = decl " " $0 }
  on && /;/ {
    on = 0
    sub(/^ *ND_EXPORT */, "", decl); sub(/;.*$/, "", decl)
    gsub(/[ \t]+/, " ", decl); gsub(/\( /, "(", decl); gsub(/ \)/, ")", decl)
    gsub(/\* /, "*", decl); sub(/^ /, "", decl); sub(/ $/, "", decl)
    name = decl; sub(/\(.*/, "", name); sub(/.*[ *]/, "", name)
    print name "\t" decl
  }' "$header" "$mpi_header" > "$work/header_protos.txt"
cut -f1 "$work/header_protos.txt" | sort -u > "$work/header_functions.txt"
# status codes: "NAME<TAB>VALUE<TAB>TEXT"
sed -n '/^#define ND_STATUS_LIST/,/^$/p' "$header" |
  sed -n 's/.*X(\(ND_[A-Z0-9_]*\), *\(-\{0,1\}[0-9]*\), *"\(.*\)").*/\1	\2	\3/p' > "$work/status.txt"
cut -f1 "$work/status.txt" | sort -u > "$work/status_names.txt"
# every ND_ identifier the header defines
{ grep -oE 'X\(ND_[A-Z0-9_]+' "$header" | sed 's/^X(//'
  grep -oE '^#define ND_[A-Z0-9_]+' "$header" | sed 's/^#define //'; } |
  sort -u > "$work/header_identifiers.txt"
[ -s "$work/header_functions.txt" ] || fail "no function found in $header"
[ -s "$work/status.txt" ] || fail "ND_STATUS_LIST not found in $header"

# ---- 1. lint (also the section 1 pages: nitschedyn(1)) ----------------------
for p in $pages $(ls "$man"/*.1 2>/dev/null); do
  out=$(mandoc -Tlint -Wwarning "$p" 2>&1) || true
  [ -z "$out" ] || fail "mandoc -Tlint -Wwarning $(basename "$p"):
$out"
done

# ---- the names of every page --------------------------------------------
# "page<TAB>name" for the page itself and every .Nm of its NAME section
: > "$work/names.txt"
for p in $pages; do
  page=$(basename "$p" .3)
  printf '%s\t%s\n' "$page" "$page" >> "$work/names.txt"
  awk -v page="$page" '
    /^\.Sh / { sec = $0; sub(/^\.Sh /, "", sec); next }
    sec == "NAME" && /^\.Nm / { print page "\t" $2 }' "$p" >> "$work/names.txt"
done
cut -f2 "$work/names.txt" | sort -u > "$work/resolvable.txt"
# a page of the C API: its SYNOPSIS includes the header (other pages, such as
# the Fortran module's, get the lint, name, error-code and reference checks)
is_c_page() {
  awk '/^\.Sh / { sec = $0; next }
       sec == ".Sh SYNOPSIS" && ($0 == ".In nitschedyn.h" || $0 == ".In nitschedyn_mpi.h") { found = 1 }
       END { exit !found }' "$1"
}

# ---- 2. coverage -----------------------------------------------------------
nm -D --defined-only "$lib" | awk '{print $NF}' | grep '^nd_' | sort -u > "$work/exported.txt"
[ -s "$work/exported.txt" ] || fail "no nd_* symbol exported by $lib"
for f in $(cat "$work/header_functions.txt" "$work/exported.txt" | sort -u); do
  grep -qx "$f" "$work/resolvable.txt" || fail "$f has no manual page or alias"
done
for f in $(cut -f2 "$work/names.txt" | grep '^nd_' | sort -u); do
  grep -qx "$f" "$work/header_functions.txt" || fail "a page names $f, which the header does not declare"
done

# ---- 3. synopses ---------------------------------------------------------
for p in $pages; do
  is_c_page "$p" || continue
  page=$(basename "$p")
  awk '
    /^\.Sh / { sec = $0; sub(/^\.Sh /, "", sec); next }
    sec != "SYNOPSIS" { next }
    /^\.Ft / { ft = $0; sub(/^\.Ft /, "", ft); gsub(/"/, "", ft); next }
    /^\.Fn / {
      n = split($0, q, "\"")
      name = q[1]; sub(/^\.Fn /, "", name); sub(/ +$/, "", name)
      args = ""
      for (i = 2; i <= n; i += 2) args = args (args == "" ? "" : ", ") q[i]
      decl = ft " " name "(" args ")"
      gsub(/[ \t]+/, " ", decl); gsub(/\* /, "*", decl)
      print name "\t" decl
    }' "$p" > "$work/synopsis.txt"
  while IFS='	' read -r name decl; do
    want=$(awk -F'\t' -v n="$name" '$1 == n { print $2 }' "$work/header_protos.txt")
    if [ -z "$want" ]; then fail "$page: SYNOPSIS has $name, which the header does not declare"
    elif [ "$want" != "$decl" ]; then fail "$page: SYNOPSIS '$decl' differs from the header '$want'"; fi
  done < "$work/synopsis.txt"
  for name in $(awk -F'\t' -v pg="$(basename "$p" .3)" '$1 == pg { print $2 }' "$work/names.txt" | grep '^nd_'); do
    cut -f1 "$work/synopsis.txt" | grep -qx "$name" || fail "$page: $name is in NAME but has no .Fn in SYNOPSIS"
  done
done

# ---- 4. error codes and identifiers -----------------------------------------
for p in $pages; do
  page=$(basename "$p")
  awk '/^\.Sh / { sec = $0; sub(/^\.Sh /, "", sec); next }
       sec == "ERRORS" && /^\.It Bq Er / { print $4 }' "$p" | sort -u > "$work/errors.txt"
  while read -r code; do
    grep -qx "$code" "$work/status_names.txt" || fail "$page: ERRORS names $code, which is not in ND_STATUS_LIST"
  done < "$work/errors.txt"
  is_c_page "$p" || continue
  # ND_ERR_* and the like name a family: some identifier must start with it
  for id in $(grep -v '^\.Dt ' "$p" | grep -oE 'ND_[A-Z0-9_]+' | sort -u); do
    case $id in
      *_) grep -q "^$id" "$work/header_identifiers.txt" || fail "$page: no identifier of the header starts with $id" ;;
      *) grep -qx "$id" "$work/header_identifiers.txt" || fail "$page: $id is not defined by the header" ;;
    esac
  done
  if [ "$page" != libnitschedyn.3 ]; then
    for code in ND_ERR_NOMEM ND_ERR_INTERNAL; do
      grep -qx "$code" "$work/errors.txt" || fail "$page: ERRORS does not list $code"
    done
  fi
done

# ---- 5. sections --------------------------------------------------------
for p in $pages; do
  is_c_page "$p" || continue
  page=$(basename "$p")
  if [ "$page" = libnitschedyn.3 ]; then
    need="NAME|LIBRARY|SYNOPSIS|DESCRIPTION|THREAD SAFETY|EXAMPLES|SEE ALSO"
  else
    need="NAME|LIBRARY|SYNOPSIS|DESCRIPTION|RETURN VALUES|EXAMPLES|ERRORS|THREAD SAFETY|SEE ALSO"
  fi
  have=$(sed -n 's/^\.Sh //p' "$p" | tr -d '"')
  old_ifs=$IFS; IFS='|'
  for s in $need; do
    printf '%s\n' "$have" | grep -qx "$s" || fail "$page: no section $s"
  done
  IFS=$old_ifs
done

# ---- 6. cross references ---------------------------------------------------
for p in $pages; do
  page=$(basename "$p")
  for ref in $(sed -n 's/^\.Xr \([A-Za-z0-9_]*\) 3.*/\1/p' "$p" | sort -u); do
    case $ref in nd_*|libnitschedyn|nitschedyn_*) ;; *) continue ;; esac
    grep -qx "$ref" "$work/resolvable.txt" || fail "$page: .Xr $ref 3 does not resolve to a page or alias"
  done
done
if [ -f "$man/libnitschedyn.3" ]; then
  see_also=$(awk '/^\.Sh / { sec = $0; next } sec == ".Sh SEE ALSO" && /^\.Xr / { print $2 }' "$man/libnitschedyn.3")
  for p in $pages; do
    page=$(basename "$p" .3)
    [ "$page" = libnitschedyn ] && continue
    if printf '%s\n' "$see_also" | grep -qx "$page"; then continue; fi
    if is_c_page "$p"; then fail "libnitschedyn.3: SEE ALSO does not name $page(3)"
    else echo "note: libnitschedyn.3: SEE ALSO does not name $page(3)"; fi
  done
else
  fail "no overview page libnitschedyn.3"
fi

# ---- 7. the status table ---------------------------------------------------
if [ -f "$man/nd_last_error.3" ]; then
  sed -n 's/^\.It Dv \(ND_[A-Z0-9_]*\) Ta \(.*\) Ta \(.*\)$/\1	\2	\3/p' "$man/nd_last_error.3" |
    sed 's/\\-/-/g' > "$work/status_table.txt"
  if ! cmp -s "$work/status.txt" "$work/status_table.txt"; then
    fail "nd_last_error.3: the status table differs from ND_STATUS_LIST:
$(diff "$work/status.txt" "$work/status_table.txt")"
  fi
fi

# ---- 8. examples ---------------------------------------------------------
unescape_example() { # raw block on stdin -> C source on stdout; status 2 on a bad escape
  sed -e 's/\\e/\\/g' -e 's/\\&//g' > "$work/unescaped_example"
  # after unescaping, a remaining roff escape (\ followed by one of ( * f s [)
  # would be printed differently from the source
  if grep -n '\\[(*fs[]' "$work/unescaped_example" >&2; then return 2; fi
  cat "$work/unescaped_example"
}
# the literal blocks of a page's EXAMPLES, into $work/block_N.raw; prints N
split_examples() {
  rm -f "$work"/block_*.raw
  awk -v out="$work/block_" '/^\.Sh / { sec = $0; next }
       sec == ".Sh EXAMPLES" && /^\.Bd -literal/ { on = 1; n++; printf "" > (out n ".raw"); next }
       on && /^\.Ed/ { on = 0; close(out n ".raw"); next }
       on { print > (out n ".raw") }
       END { print n + 0 }' "$1"
}
libdir=$(dirname "$lib")
split_examples "$man/libnitschedyn.3" > /dev/null
if [ -s "$work/block_1.raw" ] && unescape_example < "$work/block_1.raw" > "$work/overview_example.c"; then
  if "$cc" -std=c11 -Wall -Wextra -Werror -I"$src/include" "$work/overview_example.c" \
       -L"$libdir" -lnitschedyn -lm -Wl,-rpath,"$libdir" -o "$work/overview_example" 2> "$work/cc.log"; then
    (cd "$work" && ./overview_example) > "$work/run.log" 2>&1 ||
      fail "libnitschedyn.3: the EXAMPLES program fails: $(cat "$work/run.log")"
    cat "$work/run.log"
  else
    fail "libnitschedyn.3: the EXAMPLES program does not compile: $(cat "$work/cc.log")"
  fi
else
  fail "libnitschedyn.3: no EXAMPLES program (or a roff escape in it)"
fi
n_fragments=0
for p in $pages; do
  is_c_page "$p" || continue
  page=$(basename "$p" .3)
  [ "$page" = libnitschedyn ] && continue
  n=$(split_examples "$p")
  [ "$n" -gt 0 ] || fail "$page.3: no EXAMPLES block"
  i=1
  while [ "$i" -le "$n" ]; do
    c="$work/example_${page}_$i.c"
    if ! unescape_example < "$work/block_$i.raw" > "$c.body"; then
      fail "$page.3: EXAMPLES block $i has a roff escape"
    else
      assumes=$(sed -n '1s|^/\* assumes: \(.*\) \*/$|\1|p' "$c.body")
      if grep -q '^ *\.\.\.$' "$c.body"; then # elided code: only checked for its marker
        [ -n "$assumes" ] || fail "$page.3: EXAMPLES block $i elides code without an /* assumes: */ line"
      else
        { [ -z "$assumes" ] || printf '%s\n' "$assumes"; cat "$c.body"; } > "$c"
        # an example of the MPI call needs mpi.h: where MPI is (mpicc --showme)
        mpi_flags=
        if grep -q '<mpi.h>' "$c"; then
          mpi_flags=$(mpicc --showme:compile 2>/dev/null) || {
            echo "note: $page.3: EXAMPLES block $i needs mpi.h, and mpicc is not here: not compiled"
            i=$((i + 1)); continue; }
        fi
        # shellcheck disable=SC2086
        "$cc" -std=c11 -Wall -Wextra -Werror -Wno-unused-function -I"$src/include" $mpi_flags -fsyntax-only \
          "$c" 2> "$work/cc.log" ||
          fail "$page.3: EXAMPLES block $i does not compile as pasted: $(cat "$work/cc.log")"
        n_fragments=$((n_fragments + 1))
      fi
    fi
    i=$((i + 1))
  done
done

# ---- 9. width ------------------------------------------------------------
for p in $pages $(ls "$man"/*.1 2>/dev/null); do
  mandoc -Tutf8 -Owidth=80 "$p" | sed 's/.\x08//g' > "$work/rendered.txt"
  wide=$(LC_ALL=C.UTF-8 grep -nE '^.{81,}' "$work/rendered.txt")
  [ -z "$wide" ] || fail "$(basename "$p"): lines longer than 80 columns (mandoc -Tutf8 -Owidth=80):
$wide"
done

# ---- 10. no citation of DESIGN.md -------------------------------------------
cited=$(grep -n 'DESIGN' $pages $(ls "$man"/*.1 2>/dev/null))
[ -z "$cited" ] || fail "a page cites DESIGN, which is not installed:
$cited"
cited=$(strings "$lib" | grep 'DESIGN')
[ -z "$cited" ] || fail "a string of the library cites DESIGN, which is not installed:
$cited"

n_pages=$(echo "$pages" | wc -w)
n_names=$(wc -l < "$work/resolvable.txt")
if [ $fails -eq 0 ]; then
  echo "ok: $n_pages pages, $n_names names, $n_fragments C fragments compiled as pasted; $(wc -l < "$work/header_functions.txt") functions, $(wc -l < "$work/exported.txt") exported symbols documented"
  exit 0
fi
echo "$fails check(s) failed"
exit 1
