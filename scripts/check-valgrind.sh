#!/bin/sh
# Runs test programs of a build under valgrind memcheck (no forking in
# Check, so that valgrind sees the test bodies), JOBS programs at a time.
# Fails on any memory error or definite leak; prints each program's time so
# that CI shows where its minutes go.
# usage: check-valgrind.sh BUILD_DIR [JOBS [all]]  (JOBS default 2)
#        check-valgrind.sh --one PROGRAM           (one program; used by the above)
# Without `all`, the programs below are left out: they are the slowest under
# valgrind (70 % of its time) and repeat paths that the others take through
# every layer at smaller sizes (the Newton tangent paths, the forces on 3D
# meshes, file output, the contact bounds, the critical-step estimate, the
# convergence study, friction's schemes, laws and impacts on 2D and 3D
# meshes: test_friction, more than 10 minutes alone; the contact pairs'
# schemes, friction and restarts: test_pairs, 6 minutes, and a body touching
# itself: test_self_contact, about 20 runs of up to 300 steps, a minute each; the
# pairing and its rows, of two regions and of a region its own master, are
# the Fortran pairs twin's under valgrind), and the
# allocation-failure sweep (thousands of steps)
# and METIS under a memory budget (unit_metis_memory), which interpose
# malloc themselves; all of them run under ASan and UBSan (make
# check-sanitize; unit_metis_memory's budget only without ASan, whose
# allocator it would bypass), and `make check-valgrind-all` runs every
# program.
set -u
if [ "${1:-}" = "--one" ]; then
  start=$(date +%s)
  # one BLAS thread: valgrind runs threads one at a time, and spinning BLAS
  # workers (OpenBLAS yields in a loop) would multiply the run time
  if CK_FORK=no OPENBLAS_NUM_THREADS=1 valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite \
       "$2" > "$2.valgrind.log" 2>&1; then
    echo "valgrind ok:     $(basename "$2") ($(( $(date +%s) - start )) s)"
  else
    echo "valgrind FAILED: $(basename "$2") ($(( $(date +%s) - start )) s)"; cat "$2.valgrind.log"
    exit 1
  fi
  exit 0
fi
build=${1:-build}
jobs=${2:-2}
slow="unit_tangent unit_forces test_io unit_contact_bounds unit_critical_step test_convergence test_friction test_pairs test_self_contact unit_alloc_failure unit_metis_memory"
[ "${3:-}" = all ] && slow=""
programs() {
  for t in "$build"/tests/test_* "$build"/tests/unit_*; do
    [ -f "$t" ] && [ -x "$t" ] || continue
    case " $slow " in *" $(basename "$t") "*) continue ;; esac
    echo "$t"
  done
}
[ -n "$(programs)" ] || { echo "no test programs in $build/tests"; exit 1; }
programs | xargs -P "$jobs" -n 1 sh "$0" --one
