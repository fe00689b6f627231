#!/bin/sh
# Installs the Debian packages that the build and the tests need, when one is
# missing and we are root; otherwise says what to install. Safe to run twice.
#   install-deps.sh          the build and the tests
#   install-deps.sh report   also the work-precision report (matplotlib, GetFEM)
#   install-deps.sh meshes   also gmsh (make meshes)
#   install-deps.sh bench    also gmsh and GetFEM (make bench, make bench-quick)
#   install-deps.sh fuzz     also clang and libFuzzer (make fuzz; libclang-rt-dev is
#                            Debian's libclang-rt-N-dev of the default clang, -14- on bookworm)
#   install-deps.sh petsc    also PETSc with MPI, MUMPS and hypre (make check-petsc,
#                            -DND_WITH_PETSC=ON; bookworm: PETSc 3.18, OpenMPI)
# Several groups install in one apt-get run: install-deps.sh fuzz petsc report bench
set -e
need=""
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
pkgs="cmake g++ make pkg-config liblapack-dev liblapacke-dev libopenblas0-pthread libsuitesparse-dev libmetis-dev check binutils valgrind mandoc man-db gfortran python3-numpy libtomlplusplus-dev libcli11-dev"
for group in "$@"; do
  case $group in
    report) pkgs="$pkgs python3 python3-matplotlib python3-getfem" ;;
    meshes) pkgs="$pkgs gmsh" ;;
    bench) pkgs="$pkgs python3 python3-numpy python3-getfem gmsh" ;;
    fuzz) pkgs="$pkgs clang libclang-rt-dev" ;;
    petsc) pkgs="$pkgs petsc-dev" ;;
    *) echo "install-deps: unknown group '$group' (report, meshes, bench, fuzz, petsc)" >&2; exit 2 ;;
  esac
done
for pkg in $pkgs; do
  have_pkg "$pkg" || case " $need " in *" $pkg "*) ;; *) need="$need $pkg" ;; esac
done
[ -z "$need" ] && exit 0
if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  echo "install-deps: installing$need"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends $need >/dev/null
else
  echo "install-deps: missing Debian packages:$need" >&2
  echo "install-deps: run as root: apt-get install$need" >&2
  exit 1
fi
