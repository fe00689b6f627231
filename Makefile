# A thin driver over CMake (the one build description).
#   make            build the library and examples in $(BUILD)
#   make check      build and run the whole test suite (CTest)
#   make demo       build the library, the CLI and two examples, and run the demonstration scenes
#   make install    install into $(PREFIX)
#   make check-sanitize / check-valgrind   the tests under ASan+UBSan / memcheck (a subset;
#                   check-valgrind-all: every test program)
#   make fuzz       the libFuzzer targets (clang), $(FUZZ_TIME) s each on their seed corpora
#   make check-petsc  a build with the PETSc solvers in $(PETSC_BUILD) (-DND_WITH_PETSC=ON,
#                   warnings as errors) and its tests labelled petsc (mpi: under mpiexec)
#   make check-valgrind-mpi  its MPI tests on 2 ranks under valgrind memcheck
#   CMAKE_FLAGS=... (re)configures $(BUILD) with these flags, e.g. CI's
#                   make check CMAKE_FLAGS=-DND_WERROR=ON
#   make bench      the benchmarks against GetFEM (bench/run.sh, about 15 min on
#                   2 cores): bench/results/*.csv and report/PERFORMANCE.md
#   make bench-quick  the same, small (< 3 min, CI): $(BUILD)/bench-quick/
#   make bench-tangent  the Newton tangent paths (bench/tangent.sh): bench/results/tangent_*.csv
#   make bench-same  are the serial histories bitwise the committed bench's (bench/same_histories.sh,
#                   ~10 s; only on the CPU bench/results/machine.txt names)
#   make bench-heap  the whole-length arrays a rank holds, on 1, 2, 4 MPI ranks in $(PETSC_BUILD)
#                   (bench/heap_count.sh, ~1 min): bench/results/scaling_heap.csv
#   make bench-scaling  strong and weak scaling on 1 and 2 MPI ranks in $(PETSC_BUILD)
#                   (bench/scaling.sh, ~3 min on a quiet machine): bench/results/scaling.csv
#                   and the tables of report/SCALING.md on stdout
#   make report     the work-precision study (about 15 min): report/REPORT.md, plots, data
#   make report-quick  the same, small (about 2 min, in CI): $(BUILD)/report-quick/
#   make stability  the stability suite: report/STABILITY.md and report/data/stability.csv;
#                   its fixed plan and STABILITY_RANDOM (200) cases drawn at random with a
#                   fresh seed (from the time), printed; replay: make stability STABILITY_SEED=...
#   make stability-quick  its small plan (a test of make check too): $(BUILD)/stability-quick/
#   make stability-random  40 of its random cases with a fresh seed (CI), printed
#   make meshes     regenerate examples/meshes/*.msh (and the gmsh-written fixtures of
#                   tests/fixtures) from the .geo sources (gmsh)
# no "Entering/Leaving directory" lines from the makes that CMake runs
MAKEFLAGS += --no-print-directory
export MAKEFLAGS

BUILD    ?= build
PREFIX   ?= /usr/local
JOBS     ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=
FUZZ_BUILD ?= build-fuzz
FUZZ_TIME  ?= 60
PETSC_BUILD ?= build-petsc


.PHONY: check-valgrind-all check-valgrind-mpi-all
.PHONY: all deps configure check demo install check-sanitize check-valgrind fuzz fuzz-deps petsc-deps petsc-configure petsc-build check-petsc check-valgrind-mpi meshes bench bench-quick bench-tangent bench-same bench-heap bench-scaling bench-deps report report-quick report-deps stability stability-quick stability-random abi-update clean

all: configure
	cmake --build $(BUILD) -j $(JOBS)

deps:
	@sh scripts/install-deps.sh

# configured once; again whenever CMAKE_FLAGS is given (so that CI's flags apply)
configure: deps
	@if [ ! -f $(BUILD)/CMakeCache.txt ] || [ -n "$(CMAKE_FLAGS)" ]; then \
	  cmake -S . -B $(BUILD) -DCMAKE_INSTALL_PREFIX=$(PREFIX) $(CMAKE_FLAGS); fi

check: all
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# only the library, the CLI and the two example programs the demo runs
DEMO_TARGETS = nitschedyn nitschedyn_cli bar1d disk2d
demo: configure
	cmake --build $(BUILD) -j $(JOBS) --target $(DEMO_TARGETS)
	@sh scripts/demo.sh $(BUILD)

install: all
	cmake --install $(BUILD) --prefix $(PREFIX)

check-sanitize: deps
	@if [ ! -f build-sanitize/CMakeCache.txt ] || [ -n "$(CMAKE_FLAGS)" ]; then \
	  cmake -S . -B build-sanitize -DND_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug $(CMAKE_FLAGS); fi
	cmake --build build-sanitize -j $(JOBS)
	cd build-sanitize && CK_FORK=no ctest --output-on-failure -j $(JOBS)

# a representative subset (scripts/check-valgrind.sh says which programs it
# leaves out and why); check-valgrind-all runs every test program
check-valgrind: all
	sh scripts/check-valgrind.sh $(BUILD) $(JOBS)

check-valgrind-all: all
	sh scripts/check-valgrind.sh $(BUILD) $(JOBS) all

# libFuzzer (tests/fuzz): clang with ASan+UBSan; fails on any crash, leak,
# timeout or sanitizer report (scripts/fuzz.sh)
fuzz-deps:
	@sh scripts/install-deps.sh fuzz

fuzz: fuzz-deps
	@test -f $(FUZZ_BUILD)/CMakeCache.txt || CC=clang CXX=clang++ cmake -S . -B $(FUZZ_BUILD) -DND_FUZZ=ON \
	  -DND_TESTS=OFF -DND_FORTRAN=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS)
	cmake --build $(FUZZ_BUILD) -j $(JOBS) --target fuzz_gmsh fuzz_api fuzz_checkpoint fuzz_scene
	sh scripts/fuzz.sh $(FUZZ_BUILD) $(FUZZ_TIME)

# The PETSc linear solvers (ND_SOLVER_PETSC_*): Debian's petsc-dev (MPI, MUMPS)
petsc-deps:
	@sh scripts/install-deps.sh petsc

# configured once (again when CMAKE_FLAGS are given)
petsc-configure: petsc-deps
	@if [ ! -f $(PETSC_BUILD)/CMakeCache.txt ] || [ -n "$(CMAKE_FLAGS)" ]; then \
	  cmake -S . -B $(PETSC_BUILD) -DND_WITH_PETSC=ON -DND_WERROR=ON $(CMAKE_FLAGS); fi

petsc-build: petsc-configure
	cmake --build $(PETSC_BUILD) -j $(JOBS)

check-petsc: petsc-build
	cd $(PETSC_BUILD) && ctest --output-on-failure -L petsc -j $(JOBS)

# The MPI tests of the PETSc build on 2 ranks under valgrind (memory errors):
# the distributed linear algebra, the contact columns and the ranks' agreement
# on a small matrix (mpi_contact_columns), and the collective calls the
# ranks do not match (mpi_mismatch, about 2 minutes); check-valgrind-mpi-all
# adds the disk and ball runs of mpi_distributed (about 5 more minutes),
# which run without valgrind in check-petsc
check-valgrind-mpi: petsc-build
	cd $(PETSC_BUILD) && ctest --output-on-failure -L valgrind-ranks -R "mpi_contact_columns|mpi_mismatch"

check-valgrind-mpi-all: petsc-build
	cd $(PETSC_BUILD) && ctest --output-on-failure -L valgrind-ranks

# Record the public ABI (abi/nitschedyn.abi) after a deliberate change of the API.
abi-update: all
	cmake --build $(BUILD) --target abi-update

# Benchmarks (not tests): ours and GetFEM's (Debian's python3-getfem, gmsh)
bench-deps:
	@sh scripts/install-deps.sh bench

bench: all bench-deps
	sh bench/run.sh $(BUILD)

bench-quick: all bench-deps
	sh bench/run.sh $(BUILD) quick

bench-tangent: all
	sh bench/tangent.sh $(BUILD)

bench-same: all
	sh bench/same_histories.sh $(BUILD)

bench-heap: petsc-configure
	cmake --build $(PETSC_BUILD) -j $(JOBS) --target scaling_bench
	sh bench/heap_count.sh $(PETSC_BUILD)

bench-scaling: petsc-configure
	cmake --build $(PETSC_BUILD) -j $(JOBS) --target scaling_bench
	sh bench/scaling.sh $(PETSC_BUILD)

# The work-precision report (tools/report): runs, then plots and REPORT.md.
# Debian's python3 (/usr/bin/python3) with matplotlib and GetFEM.
REPORT_PY = /usr/bin/python3
report-deps:
	@sh scripts/install-deps.sh report

report: all report-deps
	$(REPORT_PY) tools/report/run.py --full --build $(BUILD) --out report
	$(REPORT_PY) tools/report/make_report.py --data report/data --out report

report-quick: all report-deps
	$(REPORT_PY) tools/report/run.py --quick --build $(BUILD) --out $(BUILD)/report-quick
	$(REPORT_PY) tools/report/make_report.py --data $(BUILD)/report-quick/data --out $(BUILD)/report-quick

# The stability suite (tools/stability): stiff and extreme cases, no silent failure.
# A fresh seed for the random cases unless STABILITY_SEED is given (:= once).
STABILITY_RANDOM ?= 200
ifeq ($(STABILITY_SEED),)
STABILITY_SEED := $(shell date -u +%Y%m%d%H%M%S)
endif
stability: all
	@echo "stability: seed $(STABILITY_SEED) (replay: make stability STABILITY_SEED=$(STABILITY_SEED))"
	$(REPORT_PY) tools/stability/run.py --build $(BUILD) --out report --random $(STABILITY_RANDOM) --seed $(STABILITY_SEED)

stability-quick: all
	$(REPORT_PY) tools/stability/run.py --quick --build $(BUILD) --out $(BUILD)/stability-quick

# STABILITY_RANDOM_CI cases drawn with a fresh seed (CI: the suite is not a
# fixed list to tune against); fails on a silent failure or a false alarm
STABILITY_RANDOM_CI ?= 40
stability-random: all
	@echo "stability-random: seed $(STABILITY_SEED) (replay: make stability-random STABILITY_SEED=$(STABILITY_SEED))"
	$(REPORT_PY) tools/stability/run.py --build $(BUILD) --out $(BUILD)/stability-random --only-random \
	  --random $(STABILITY_RANDOM_CI) --seed $(STABILITY_SEED)

# Regenerate the committed reference meshes (needs Debian's gmsh).
MESHES = examples/meshes
meshes:
	@sh scripts/install-deps.sh meshes
	for h in 4 2 1; do \
	  gmsh -2 -setnumber h $$h -format msh41 $(MESHES)/disk.geo -o $(MESHES)/disk_h$$h.msh || exit 1; \
	  gmsh -3 -setnumber h $$h -format msh41 $(MESHES)/ball.geo -o $(MESHES)/ball_h$$h.msh || exit 1; \
	done
	gmsh -2 -setnumber h 0.5 -format msh41 $(MESHES)/disk.geo -o $(MESHES)/disk_h0.5.msh
	for h in 4 2 1; do \
	  gmsh -2 -setnumber h $$h -format msh41 $(MESHES)/disk_quad.geo -o $(MESHES)/disk_quad_h$$h.msh || exit 1; \
	done
	for h in 4 2; do \
	  gmsh -3 -setnumber h $$h -format msh41 $(MESHES)/ball_hex.geo -o $(MESHES)/ball_hex_h$$h.msh || exit 1; \
	done
	gmsh -2 -order 2 -setnumber dim 2 -format msh41 tests/fixtures/q2_cell.geo -o tests/fixtures/q2_quad.msh
	gmsh -3 -order 2 -setnumber dim 3 -format msh41 tests/fixtures/q2_cell.geo -o tests/fixtures/q2_hex.msh

clean:
	rm -rf $(BUILD) build-sanitize $(FUZZ_BUILD) $(PETSC_BUILD)
