// The PETSc backends (built with -DND_WITH_PETSC=ON), serial for now: the
// matrix is one MATSEQAIJ on PETSC_COMM_SELF.
//
//   ND_SOLVER_PETSC_MUMPS  MUMPS through PETSc's factor interface: Cholesky
//       (MUMPS's symmetric LDL^T, SYM = 2, so that it also factors what is not
//       positive definite and counts the negative pivots, INFOG(12)) when SPD
//       is requested, LU otherwise. The analysis is redone only when the
//       structure asked for changes.
//   ND_SOLVER_PETSC_GAMG   a Krylov method preconditioned by PETSc's smoothed
//       aggregation multigrid: CG for SPD, right-preconditioned GMRES for the
//       others, both stopping at ||b - A x|| <= rtol ||b|| (the true residual),
//       rtol = kKrylovRtol; GAMG gets the rigid-body modes of the unknowns as
//       its near-null space when a DofGeometry is given. factor() builds the
//       multigrid hierarchy; it cannot certify definiteness (Unknown): an
//       indefinite matrix requested as SPD is reported as ND_ERR_INDEFINITE only
//       when CG meets negative curvature during a solve.
//
// Options: both backends give their objects the options prefix "nd_" and read
// the options database after setting the defaults, so that PETSc's own
// options change them without a new call: PETSC_OPTIONS="-nd_ksp_rtol 1e-10
// -nd_pc_gamg_threshold 0.01 -nd_mat_mumps_icntl_14 50". Nothing unprefixed
// applies to them.
//
// Next (issue 15, distribution): a communicator per problem (nd_problem_set_comm
// taking an MPI_Comm, and nd_problem_set_comm_f for Fortran's integer handle
// via MPI_Comm_f2c; PETSC_COMM_SELF stays the default so that serial callers
// change nothing), the DOFs partitioned by cell ownership, MATMPIAIJ with
// MatMPIAIJSetPreallocationCSR on the owned rows, the near-null space from the
// owned DOFs' coordinates, and MUMPS's INFOG(12) (ICNTL(13) = 1 is already set
// so that the inertia stays exact when MUMPS would use ScaLAPACK). The
// Factorization interface's solve(double *) then takes the owned part.
//
// PETSc is global to the process: every PETSc call of the library runs under
// one mutex (so that handles used from distinct threads stay safe), with an
// error handler that records PETSc's message instead of printing it; every
// PetscErrorCode is checked and becomes an nd::Error. Initialization: see
// petsc_session() below.
#include <petscksp.h>  // first: it keeps the MPI C++ bindings out (OMPI_SKIP_MPICXX)

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/format.hpp"
#include "linalg/backends.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// The Krylov stopping rule of ND_SOLVER_PETSC_GAMG: ||b - A x|| <= kKrylovRtol ||b||.
// Tight on purpose: the low-rank Newton tangent (Woodbury over the active
// contact points) builds T^{-1} from solves with A, and Newton's test of the
// update at round-off expects solves that are exact to about that level.
constexpr double kKrylovRtol = 1e-12;
constexpr PetscInt kKrylovMaxIterations = 10000;

// Defined before g_finalize_at_unload: destroyed after it.
std::recursive_mutex g_petsc_mutex;
std::recursive_mutex &petsc_mutex() { return g_petsc_mutex; }

// ---- errors -------------------------------------------------------------------

// The first (innermost) message of the failing PETSc call; set under the mutex.
std::string g_petsc_message;

PetscErrorCode record_error(MPI_Comm, int line, const char *function, const char *file, PetscErrorCode code,
                            PetscErrorType kind, const char *message, void *) {
  if (kind == PETSC_ERROR_INITIAL)
    g_petsc_message = std::string(function ? function : "?") + "() at " + (file ? file : "?") + ":" +
                      std::to_string(line) + (message && *message ? std::string(": ") + message : std::string());
  return code;
}

[[noreturn]] void fail_petsc(PetscErrorCode code, const char *what) {
  const char *text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  std::string msg = std::string("PETSc ") + what + " failed (PETSc error " + std::to_string(code) +
                    (text ? std::string(", ") + text : std::string()) + ")";
  if (!g_petsc_message.empty()) msg += " in " + g_petsc_message;
  g_petsc_message.clear();
  if (code == PETSC_ERR_MEM) fail(ND_ERR_NOMEM, "out of memory: " + msg);
  if (code == PETSC_ERR_MAT_LU_ZRPVT) fail(ND_ERR_SINGULAR, "the matrix is singular: " + msg);
  fail(ND_ERR_INTERNAL, msg);
}

void check(PetscErrorCode code, const char *what) {
  if (code) fail_petsc(code, what);
}

// A solve in place: b <- x (a copy), and xv wraps x's storage for the solution
// (the caller resets xv after the solve)
void place_rhs(Vec b, Vec xv, double *x, PetscInt n) {
  PetscScalar *a = nullptr;
  check(VecGetArrayWrite(b, &a), "VecGetArrayWrite");
  std::copy(x, x + n, a);
  check(VecRestoreArrayWrite(b, &a), "VecRestoreArrayWrite");
  check(VecPlaceArray(xv, x), "VecPlaceArray");
}

// ---- initialization -----------------------------------------------------------
//
// The library initializes PETSc on first use when the host has not (and PETSc
// initializes MPI when the host has not: MPI_Init_thread, its default), and
// finalizes only what it initialized:
//   - MPI initialized by the host: PETSc is finalized at the start of the
//     host's MPI_Finalize (a delete callback of an attribute on
//     MPI_COMM_SELF, which MPI runs first, MPI still usable);
//   - MPI initialized by PETSc for us: PETSc (and with it MPI) is finalized
//     when the library is unloaded or the process exits;
//   - PETSc initialized by the host: the host finalizes it; it must destroy
//     the problems that use a PETSc solver first (afterwards their PETSc
//     objects are abandoned, not destroyed).
// PETSc is initialized without its signal handler (-no_signal_handler) and
// reads PETSC_OPTIONS as usual.
bool g_we_initialized = false;

void finalize_if_ours() {
  std::lock_guard<std::recursive_mutex> lock(petsc_mutex());
  if (!g_we_initialized) return;
  g_we_initialized = false;
  PetscBool finalized = PETSC_TRUE;
  int mpi_finalized = 1;
  if (PetscFinalized(&finalized) || finalized) return;
  if (MPI_Finalized(&mpi_finalized) != MPI_SUCCESS || mpi_finalized) return;
  PetscFinalize();  // also MPI_Finalize when PETSc began MPI
}

int finalize_at_mpi_finalize(MPI_Comm, int, void *, void *) {
  finalize_if_ours();
  return MPI_SUCCESS;
}

struct FinalizeAtUnload {
  ~FinalizeAtUnload() { finalize_if_ours(); }
} g_finalize_at_unload;

void ensure_initialized() {
  PetscBool initialized = PETSC_FALSE, finalized = PETSC_FALSE;
  check(PetscInitialized(&initialized), "PetscInitialized");
  if (initialized) return;
  check(PetscFinalized(&finalized), "PetscFinalized");
  if (finalized)
    fail(ND_ERR_STATE, "PETSc has been finalized in this process; the ND_SOLVER_PETSC_* solvers cannot run again");
  int mpi_initialized = 0, mpi_finalized = 0;
  MPI_Initialized(&mpi_initialized);
  MPI_Finalized(&mpi_finalized);
  if (mpi_finalized) fail(ND_ERR_STATE, "MPI has been finalized in this process; the ND_SOLVER_PETSC_* solvers need it");
  static char arg0[] = "libnitschedyn", arg1[] = "-no_signal_handler";
  static char *argv[] = {arg0, arg1, nullptr};
  int argc = 2;
  char **args = argv;
  const PetscErrorCode code = PetscInitialize(&argc, &args, nullptr, nullptr);
  if (code) fail(ND_ERR_INTERNAL, "PetscInitialize failed (PETSc error " + std::to_string(code) + ")");
  g_we_initialized = true;
  if (mpi_initialized) {
    int key = MPI_KEYVAL_INVALID;
    if (MPI_Comm_create_keyval(MPI_COMM_NULL_COPY_FN, finalize_at_mpi_finalize, &key, nullptr) != MPI_SUCCESS ||
        MPI_Comm_set_attr(MPI_COMM_SELF, key, nullptr) != MPI_SUCCESS)
      fail(ND_ERR_INTERNAL, "cannot attach PETSc's finalization to MPI_Finalize (MPI_Comm_set_attr)");
  }
}

// Every PETSc call sequence of this file: locked, PETSc initialized, errors
// recorded instead of printed.
class Session {
 public:
  Session() : lock_(petsc_mutex()) {
    ensure_initialized();
    g_petsc_message.clear();
    check(PetscPushErrorHandler(record_error, nullptr), "PetscPushErrorHandler");
  }
  ~Session() { PetscPopErrorHandler(); }
  Session(const Session &) = delete;
  Session &operator=(const Session &) = delete;

 private:
  std::lock_guard<std::recursive_mutex> lock_;
};

// Destroying: only while PETSc runs (a host may have finalized it first).
bool petsc_alive() {
  PetscBool initialized = PETSC_FALSE, finalized = PETSC_TRUE;
  if (PetscInitialized(&initialized) || !initialized) return false;
  return !PetscFinalized(&finalized) && !finalized;
}

// ---- the matrix ---------------------------------------------------------------

PetscInt petsc_int(int64_t v, const char *what) {
  if (v > static_cast<int64_t>(std::numeric_limits<PetscInt>::max()))
    fail(ND_ERR_SIZE, std::string("the matrix has too many ") + what + " for PETSc's " +
                          std::to_string(8 * sizeof(PetscInt)) + "-bit indices (" + std::to_string(v) + ")");
  return static_cast<PetscInt>(v);
}

// A MATSEQAIJ with our pattern (rows sorted, explicit zeros kept: its value
// array is ours, entry for entry) and the options prefix "nd_".
Mat make_matrix(const Csr &pattern, PetscInt block_size) {
  const PetscInt n = petsc_int(pattern.n, "rows");
  petsc_int(static_cast<int64_t>(pattern.col.size()), "entries");
  std::vector<PetscInt> ptr(pattern.ptr.begin(), pattern.ptr.end()), col(pattern.col.begin(), pattern.col.end());
  std::vector<PetscScalar> zero(pattern.col.size(), 0.0);
  Mat A = nullptr;
  check(MatCreate(PETSC_COMM_SELF, &A), "MatCreate");
  try {
    check(MatSetSizes(A, n, n, n, n), "MatSetSizes");
    check(MatSetType(A, MATSEQAIJ), "MatSetType");
    check(MatSetOptionsPrefix(A, "nd_"), "MatSetOptionsPrefix");
    if (block_size > 1) check(MatSetBlockSize(A, block_size), "MatSetBlockSize");
    check(MatSeqAIJSetPreallocationCSR(A, ptr.data(), col.data(), zero.data()), "MatSeqAIJSetPreallocationCSR");
    check(MatSetOption(A, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  } catch (...) {
    MatDestroy(&A);
    throw;
  }
  return A;
}

void set_values(Mat A, const Csr &M) {
  PetscInt nnz = 0;
  MatInfo info;
  check(MatGetInfo(A, MAT_LOCAL, &info), "MatGetInfo");
  nnz = static_cast<PetscInt>(info.nz_used);
  if (static_cast<size_t>(nnz) != M.val.size())
    fail(ND_ERR_INTERNAL, "the matrix does not have the pattern its PETSc solver was made for");
  PetscScalar *a = nullptr;
  check(MatSeqAIJGetArray(A, &a), "MatSeqAIJGetArray");
  std::copy(M.val.begin(), M.val.end(), a);
  check(MatSeqAIJRestoreArray(A, &a), "MatSeqAIJRestoreArray");  // raises the matrix's state
}

// Vectors over the caller's array (no copy) and a work vector.
Vec make_vector(PetscInt n) {
  Vec v = nullptr;
  check(VecCreateSeq(PETSC_COMM_SELF, n, &v), "VecCreateSeq");
  return v;
}

void destroy(Mat &A) {
  if (A && petsc_alive()) MatDestroy(&A);
  A = nullptr;
}
void destroy(Vec &v) {
  if (v && petsc_alive()) VecDestroy(&v);
  v = nullptr;
}

// ---- MUMPS ----------------------------------------------------------------------

class PetscMumps : public Factorization {
 public:
  explicit PetscMumps(const Csr &pattern) : n_(pattern.n) {
    Session s;
    try {
      A_ = make_matrix(pattern, 1);
      b_ = make_vector(static_cast<PetscInt>(n_));
      x_ = make_vector(static_cast<PetscInt>(n_));
    } catch (...) {
      release();
      throw;
    }
  }
  ~PetscMumps() override { release(); }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    require_finite(A);
    Session session;
    factored_ = false;
    set_values(A_, A);
    const bool cholesky = s == Structure::SymmetricPositiveDefinite;
    MatFactorInfo info;
    check(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
    if (!F_ || cholesky != cholesky_) {  // the analysis (MUMPS JOB = 1)
      destroy(F_);
      cholesky_ = cholesky;
      check(MatSetOption(A_, MAT_SYMMETRIC, cholesky ? PETSC_TRUE : PETSC_FALSE), "MatSetOption");
      check(MatGetFactor(A_, MATSOLVERMUMPS, cholesky ? MAT_FACTOR_CHOLESKY : MAT_FACTOR_LU, &F_), "MatGetFactor");
      // the inertia also where a root node would go to ScaLAPACK (parallel runs)
      check(MatMumpsSetIcntl(F_, 13, 1), "MatMumpsSetIcntl(13)");
      check(MatSetFromOptions(F_), "MatSetFromOptions");
      if (cholesky)
        check(MatCholeskyFactorSymbolic(F_, A_, nullptr, &info), "MatCholeskyFactorSymbolic (MUMPS analysis)");
      else
        check(MatLUFactorSymbolic(F_, A_, nullptr, nullptr, &info), "MatLUFactorSymbolic (MUMPS analysis)");
      require_no_factor_error("analysis", s);
    }
    if (cholesky)
      check(MatCholeskyFactorNumeric(F_, A_, &info), "MatCholeskyFactorNumeric (MUMPS)");
    else
      check(MatLUFactorNumeric(F_, A_, &info), "MatLUFactorNumeric (MUMPS)");
    require_no_factor_error("factorization", s);
    if (cholesky) {
      PetscInt negative = 0;
      check(MatMumpsGetInfog(F_, 12, &negative), "MatMumpsGetInfog(12)");
      if (negative > 0)
        fail_not_positive_definite(def_, "MUMPS LDL^T: " + std::to_string(negative) + " negative pivots of " +
                                             std::to_string(n_));
      def_ = Definiteness::PositiveDefinite;
    }
    factored_ = true;
  }
  void solve(double *x) const override {
    if (!factored_) fail(ND_ERR_INTERNAL, "PETSc MUMPS: solve before a successful factorization");
    Session session;
    place_rhs(b_, x_, x, n_);
    const PetscErrorCode code = MatSolve(F_, b_, x_);
    VecResetArray(x_);
    check(code, "MatSolve (MUMPS)");
  }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "petsc-mumps"; }

 private:
  void release() {
    std::lock_guard<std::recursive_mutex> lock(petsc_mutex());
    destroy(F_), destroy(A_), destroy(b_), destroy(x_);
  }
  // MUMPS reports its failures in INFOG(1) < 0, PETSc in the factor's error.
  void require_no_factor_error(const char *phase, Structure s) {
    MatFactorError err = MAT_FACTOR_NOERROR;
    check(MatFactorGetError(F_, &err), "MatFactorGetError");
    if (err == MAT_FACTOR_NOERROR) return;
    PetscInt infog1 = 0, infog2 = 0;
    MatMumpsGetInfog(F_, 1, &infog1);
    MatMumpsGetInfog(F_, 2, &infog2);
    const std::string st = " (MUMPS " + std::string(phase) + ": INFOG(1) = " + std::to_string(infog1) +
                           ", INFOG(2) = " + std::to_string(infog2) + ")";
    destroy(F_);  // a failed factor is not reused: the next factor() analyses again
    if (infog1 == -10) {
      if (s == Structure::SymmetricPositiveDefinite) fail_not_positive_definite(def_, "singular" + st);
      fail(ND_ERR_SINGULAR, "the matrix is singular" + st);
    }
    if (err == MAT_FACTOR_OUTMEMORY || infog1 == -13 || infog1 == -9 || infog1 == -8 || infog1 == -14 ||
        infog1 == -15 || infog1 == -17 || infog1 == -20)
      fail(ND_ERR_NOMEM, "out of memory" + st);
    fail(ND_ERR_INTERNAL, "MUMPS failed" + st);
  }

  int64_t n_;
  Mat A_ = nullptr, F_ = nullptr;
  Vec b_ = nullptr, x_ = nullptr;
  bool cholesky_ = false, factored_ = false;
  Definiteness def_ = Definiteness::Unknown;
};

// ---- GAMG -----------------------------------------------------------------------

// The rigid-body modes of the unknowns (dim translations, and 1 rotation in
// 2D or 3 in 3D about the centroid), orthonormalized; empty when the geometry
// does not describe these unknowns. Whether the unknowns come in whole nodes
// (free DOFs node by node, every component free) goes to block_size.
std::vector<std::vector<double>> rigid_body_modes(const DofGeometry *g, int64_t n, PetscInt &block_size) {
  block_size = 1;
  std::vector<std::vector<double>> modes;
  if (!g || g->dim < 1 || g->dim > 3 || static_cast<int64_t>(g->component.size()) != n ||
      static_cast<int64_t>(g->x.size()) != n * g->dim || n == 0)
    return modes;
  const int d = g->dim;
  double centre[3] = {0, 0, 0};
  for (int64_t i = 0; i < n; ++i)
    for (int k = 0; k < d; ++k) centre[k] += g->x[i * d + k] / static_cast<double>(n);
  const int nmodes = d == 1 ? 1 : d == 2 ? 3 : 6;
  modes.assign(static_cast<size_t>(nmodes), std::vector<double>(static_cast<size_t>(n), 0.0));
  for (int64_t i = 0; i < n; ++i) {
    const int c = g->component[i];
    double y[3] = {0, 0, 0};
    for (int k = 0; k < d; ++k) y[k] = g->x[i * d + k] - centre[k];
    modes[c][i] = 1;  // translation along c
    if (d == 2) modes[2][i] = c == 0 ? -y[1] : y[0];  // rotation (-y, x)
    if (d == 3) {  // rotations about z, x, y: omega x y
      if (c == 0) modes[3][i] = -y[1], modes[5][i] = y[2];
      if (c == 1) modes[3][i] = y[0], modes[4][i] = -y[2];
      if (c == 2) modes[4][i] = y[1], modes[5][i] = -y[0];
    }
  }
  // modified Gram-Schmidt, twice; modes that vanish (all their DOFs clamped) are dropped
  std::vector<std::vector<double>> basis;
  for (auto &v : modes) {
    const double before = std::sqrt(std::inner_product(v.begin(), v.end(), v.begin(), 0.0));
    for (int pass = 0; pass < 2; ++pass)
      for (const auto &q : basis) {
        const double h = std::inner_product(q.begin(), q.end(), v.begin(), 0.0);
        for (int64_t i = 0; i < n; ++i) v[i] -= h * q[i];
      }
    const double norm = std::sqrt(std::inner_product(v.begin(), v.end(), v.begin(), 0.0));
    if (!(norm > 1e-10 * before)) continue;
    for (double &e : v) e /= norm;
    basis.push_back(std::move(v));
  }
  bool whole_nodes = n % d == 0;
  for (int64_t i = 0; whole_nodes && i < n; ++i)
    whole_nodes = g->component[i] == i % d && std::equal(&g->x[i * d], &g->x[i * d] + d, &g->x[(i - i % d) * d]);
  if (whole_nodes) block_size = d;
  return basis;
}

class PetscGamg : public Factorization {
 public:
  PetscGamg(const Csr &pattern, const DofGeometry *geometry) : n_(pattern.n) {
    PetscInt block_size = 1;
    const std::vector<std::vector<double>> modes = rigid_body_modes(geometry, n_, block_size);
    Session s;
    try {
      build(pattern, block_size, modes);
    } catch (...) {
      release();
      throw;
    }
  }
  ~PetscGamg() override { release(); }
  void build(const Csr &pattern, PetscInt block_size, const std::vector<std::vector<double>> &modes) {
    A_ = make_matrix(pattern, block_size);
    b_ = make_vector(static_cast<PetscInt>(n_));
    x_ = make_vector(static_cast<PetscInt>(n_));
    if (!modes.empty()) {
      std::vector<Vec> vecs;
      MatNullSpace space = nullptr;
      PetscErrorCode code = 0;
      for (const auto &m : modes) {
        Vec v = nullptr;
        if ((code = VecDuplicate(b_, &v))) break;
        vecs.push_back(v);
        PetscScalar *a = nullptr;
        if ((code = VecGetArrayWrite(v, &a))) break;
        std::copy(m.begin(), m.end(), a);
        if ((code = VecRestoreArrayWrite(v, &a))) break;
      }
      if (!code) code = MatNullSpaceCreate(PETSC_COMM_SELF, PETSC_FALSE, static_cast<PetscInt>(vecs.size()),
                                           vecs.data(), &space);
      if (!code) code = MatSetNearNullSpace(A_, space);
      if (space) MatNullSpaceDestroy(&space);
      for (Vec &v : vecs) VecDestroy(&v);
      check(code, "MatSetNearNullSpace (rigid-body modes)");
    }
    check(KSPCreate(PETSC_COMM_SELF, &ksp_), "KSPCreate");
    check(KSPSetOptionsPrefix(ksp_, "nd_"), "KSPSetOptionsPrefix");
  }
  void release() {
    std::lock_guard<std::recursive_mutex> lock(petsc_mutex());
    if (ksp_ && petsc_alive()) KSPDestroy(&ksp_);
    ksp_ = nullptr;
    destroy(A_), destroy(b_), destroy(x_);
  }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    require_finite(A);
    Session session;
    ready_ = false;
    structure_ = s;
    set_values(A_, A);
    const bool spd = s == Structure::SymmetricPositiveDefinite;
    check(MatSetOption(A_, MAT_SYMMETRIC, spd ? PETSC_TRUE : PETSC_FALSE), "MatSetOption");
    check(KSPSetOperators(ksp_, A_, A_), "KSPSetOperators");
    check(KSPSetType(ksp_, spd ? KSPCG : KSPGMRES), "KSPSetType");
    // the true residual in the stopping rule: CG computes it, GMRES when preconditioned from the right
    check(KSPSetPCSide(ksp_, spd ? PC_LEFT : PC_RIGHT), "KSPSetPCSide");
    check(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    check(KSPSetTolerances(ksp_, kKrylovRtol, 0.0, PETSC_DEFAULT, kKrylovMaxIterations), "KSPSetTolerances");
    PC pc = nullptr;
    check(KSPGetPC(ksp_, &pc), "KSPGetPC");
    check(PCSetType(pc, PCGAMG), "PCSetType(PCGAMG)");
    check(KSPSetFromOptions(ksp_), "KSPSetFromOptions");
    check(KSPSetUp(ksp_), "KSPSetUp (GAMG hierarchy)");
    PCFailedReason why = PC_NOERROR;
    check(PCGetFailedReason(pc, &why), "PCGetFailedReason");
    if (why != PC_NOERROR)
      fail(why == PC_FACTOR_OUTMEMORY ? ND_ERR_NOMEM : ND_ERR_SINGULAR,
           std::string("PETSc GAMG set-up failed: ") + PCFailedReasons[why]);
    ready_ = true;
  }
  void solve(double *x) const override {
    if (!ready_) fail(ND_ERR_INTERNAL, "PETSc GAMG: solve before a successful set-up");
    Session session;
    place_rhs(b_, x_, x, n_);
    PetscErrorCode code = KSPSolve(ksp_, b_, x_);
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    PetscInt its = 0;
    PetscReal rnorm = 0, bnorm = 0;
    if (!code) code = KSPGetConvergedReason(ksp_, &reason);
    if (!code) code = KSPGetIterationNumber(ksp_, &its);
    if (!code) code = KSPGetResidualNorm(ksp_, &rnorm);
    if (!code) code = VecNorm(b_, NORM_2, &bnorm);
    VecResetArray(x_);
    check(code, "KSPSolve (GAMG)");
    if (reason > 0) return;
    const bool spd = structure_ == Structure::SymmetricPositiveDefinite;
    const std::string st = std::string(spd ? "CG" : "GMRES") + " + GAMG stopped (" + KSPConvergedReasons[reason] +
                           ") after " + std::to_string(its) + " iterations at ||b - A x|| / ||b|| = " +
                           num(bnorm > 0 ? rnorm / bnorm : rnorm) + " (rtol " + num(kKrylovRtol) + ")";
    if (spd && (reason == KSP_DIVERGED_INDEFINITE_MAT || reason == KSP_DIVERGED_INDEFINITE_PC)) {
      def_ = Definiteness::NotPositiveDefinite;
      fail(ND_ERR_INDEFINITE, "the matrix is not positive definite (" + st + ")");
    }
    fail(ND_ERR_SINGULAR, "the linear solve failed: " + st +
                              "; the matrix is singular or too ill-conditioned for it: try ND_SOLVER_PETSC_MUMPS");
  }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "petsc-gamg"; }

 private:
  int64_t n_;
  Mat A_ = nullptr;
  Vec b_ = nullptr, x_ = nullptr;
  KSP ksp_ = nullptr;
  bool ready_ = false;
  Structure structure_ = Structure::General;
  mutable Definiteness def_ = Definiteness::Unknown;
};

}  // namespace

std::unique_ptr<Factorization> make_petsc_mumps_factorization(const Csr &p) { return std::make_unique<PetscMumps>(p); }
std::unique_ptr<Factorization> make_petsc_gamg_factorization(const Csr &p, const DofGeometry *g) {
  return std::make_unique<PetscGamg>(p, g);
}

}  // namespace nd
