// The PETSc backends (built with -DND_WITH_PETSC=ON).
//
//   ND_SOLVER_PETSC_MUMPS  MUMPS through PETSc's factor interface: Cholesky
//       (MUMPS's symmetric LDL^T, SYM = 2, so that it also factors what is not
//       positive definite and counts the negative pivots, INFOG(12), over all
//       ranks) when SPD is requested, LU otherwise. The analysis is redone
//       only when the structure asked for changes.
//   ND_SOLVER_PETSC_GAMG   a Krylov method preconditioned by PETSc's smoothed
//       aggregation multigrid: CG for SPD, right-preconditioned GMRES for the
//       others, both stopping at ||b - A x|| <= rtol ||b|| (the true residual),
//       rtol = kKrylovRtol; GAMG gets the rigid-body modes of the unknowns as
//       its near-null space when a DofGeometry is given. factor() builds the
//       multigrid hierarchy; it cannot certify definiteness (Unknown): an
//       indefinite matrix requested as SPD is reported as ND_ERR_INDEFINITE only
//       when CG meets negative curvature during a solve.
//
// Distribution: the DofGeometry's communicator (none:
// PETSC_COMM_SELF's MPI_COMM_SELF) holds the ranks that solve together. Every
// rank has the whole matrix and right-hand side (the mesh and the state are
// replicated); each rank owns the rows of its nodes' free DOFs (Layout;
// parallel/ownership.hpp), puts them in the MATMPIAIJ and the VecMPI, the solve is
// PETSc's over all ranks, and the solution is gathered to every rank
// (VecScatterCreateToAll), so that solve(double *) keeps its meaning: the whole
// vector in, the whole solution out, on every rank. factor() and solve() are
// collective: every rank calls them in the same order (the ranks run the same
// deterministic code on the same data). On one rank the matrix is the
// MATSEQAIJ whose value array is ours, and the solve works in the caller's
// array.
//
// Options: both backends give their objects the options prefix "nd_" and read
// the options database after setting the defaults, so that PETSc's own
// options change them without a new call: PETSC_OPTIONS="-nd_ksp_rtol 1e-10
// -nd_pc_gamg_threshold 0.01 -nd_mat_mumps_icntl_14 50". Nothing unprefixed
// applies to them.
//
// Slice 3: the cells are partitioned (petsc_partition_cells below, for
// parallel/ownership.hpp), a rank's rows are its nodes' free DOFs, numbered
// rank after rank (DofGeometry::row_of), and factor_parts() assembles the
// matrix from the ranks' parts (each rank adds its own cells' contributions,
// ADD_VALUES; PETSc sends the entries of other ranks' rows to them): the step
// matrix A is made so. factor() still inserts this rank's rows of the whole
// matrix (the mass matrix, the refactoring tangent, the coercivity check).
// Next: the state, the contact points and the vectors distributed too, so
// that nothing of size n is replicated.
//
// PETSc is global to the process: every PETSc call of the library runs under
// one mutex (so that handles used from distinct threads stay safe), with an
// error handler that records PETSc's message instead of printing it; every
// PetscErrorCode is checked and becomes an nd::Error. Initialization: see
// petsc_session() below.
#include <petscksp.h>  // first: it keeps the MPI C++ bindings out (OMPI_SKIP_MPICXX)

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "common/format.hpp"
#include "linalg/backends.hpp"
#include "nitschedyn.h"
#include "parallel/agreement.hpp"
#include "parallel/communicator_mpi.hpp"
#include "parallel/ownership.hpp"

#ifdef ND_HAVE_SCOTCH
extern "C" void SCOTCH_randomReset(void);  // (scotch.h needs its integer types configured)
#endif

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

// Which rows this rank owns: [begin, end) of n. With a DofGeometry that says
// (row_of, row_begin, row_end) the rows of each rank are the free DOFs of its
// nodes, numbered rank after rank (our unknown u is row row_of[u]); otherwise
// the unknowns' own order, cut in contiguous blocks of block_size rows dealt
// out as evenly as the count allows.
struct Layout {
  MPI_Comm comm = MPI_COMM_SELF;
  int size = 1;
  PetscInt n = 0, begin = 0, end = 0;
  std::shared_ptr<const std::vector<int64_t>> row_of;  // null: row u is unknown u
  std::vector<int64_t> own;  // the unknown of each of this rank's rows (empty: row_of is null)
  bool distributed() const { return size > 1; }
  int64_t unknown(PetscInt local_row) const { return row_of ? own[local_row] : begin + local_row; }
  PetscInt row(int64_t unknown) const { return static_cast<PetscInt>(row_of ? (*row_of)[unknown] : unknown); }
};

Layout make_layout(const DofGeometry *g, int64_t n, PetscInt block_size) {
  Layout L;
  const Communicator *c = g ? g->comm.get() : nullptr;
  L.comm = mpi_comm(c);
  L.size = communicator_size(c);
  const int rank = communicator_rank(c);
  L.n = petsc_int(n, "rows");
  if (g && g->row_end >= 0) {  // the rows given
    L.begin = static_cast<PetscInt>(g->row_begin);
    L.end = static_cast<PetscInt>(g->row_end);
    if (L.begin > L.end || L.end > L.n || (L.end - L.begin) % block_size != 0 ||
        (g->row_of && static_cast<int64_t>(g->row_of->size()) != n))
      fail(ND_ERR_INTERNAL, "the rows a rank owns (" + std::to_string(L.begin) + " .. " + std::to_string(L.end) +
                                ") are not whole blocks of the " + std::to_string(L.n) + " rows");
    if (g->row_of) {
      L.row_of = g->row_of;
      L.own.resize(static_cast<size_t>(L.end - L.begin));
      for (int64_t u = 0; u < n; ++u)
        if (const int64_t r = (*L.row_of)[u]; r >= L.begin && r < L.end) L.own[r - L.begin] = u;
    }
    return L;
  }
  const PetscInt blocks = L.n / block_size, share = blocks / L.size, extra = blocks % L.size;
  L.begin = block_size * (rank * share + std::min<PetscInt>(rank, extra));
  L.end = L.begin + block_size * (share + (rank < extra ? 1 : 0));
  return L;
}

// A matrix with our pattern (rows sorted, explicit zeros kept) over the
// layout's ranks, this rank's rows inserted, options prefix "nd_". On one
// rank a MATSEQAIJ whose value array is ours, entry for entry.
class Matrix {
 public:
  Matrix(const Csr &pattern, PetscInt block_size, const Layout &L) : L_(L) {
    petsc_int(static_cast<int64_t>(pattern.col.size()), "entries");
    // this rank's rows in the layout's numbering, columns sorted; src_: where
    // each entry is in the pattern (empty: the rows keep their order, and
    // entry k is the pattern's first_ + k)
    const PetscInt rows = L.end - L.begin;
    ptr_.assign(static_cast<size_t>(rows + 1), 0);
    // the entries of unknown i's row in the pattern (which may store a rank's rows only)
    auto entries_of = [&pattern](int64_t i) {
      const int64_t at = pattern.slot(i);
      if (at < 0) fail(ND_ERR_INTERNAL, "the pattern does not hold row " + std::to_string(i) + " of the rank's rows");
      return std::make_pair(pattern.ptr[at], pattern.ptr[at + 1]);
    };
    first_ = L.row_of || rows == 0 ? 0 : entries_of(L.begin).first;
    int64_t entries = 0;
    for (PetscInt k = 0; k < rows; ++k) {
      const auto [b, e] = entries_of(L.unknown(k));
      entries += e - b;
    }
    col_.reserve(static_cast<size_t>(entries));
    if (L.row_of) src_.reserve(static_cast<size_t>(entries));
    std::vector<std::pair<PetscInt, int64_t>> row;
    for (PetscInt k = 0; k < rows; ++k) {
      const auto [b, e] = entries_of(L.unknown(k));
      if (!L.row_of) {
        col_.insert(col_.end(), pattern.col.begin() + b, pattern.col.begin() + e);
      } else {
        row.clear();
        for (int64_t j = b; j < e; ++j) row.emplace_back(L.row(pattern.col[j]), j);
        std::sort(row.begin(), row.end());
        for (const auto &[col, j] : row) col_.push_back(col), src_.push_back(j);
      }
      ptr_[k + 1] = static_cast<PetscInt>(col_.size());
    }
    std::vector<PetscScalar> zero(col_.size(), 0.0);
    check(MatCreate(L.comm, &A_), "MatCreate");
    try {
      build(L, block_size, zero);
    } catch (...) {
      MatDestroy(&A_);
      throw;
    }
  }
  void build(const Layout &L, PetscInt block_size, const std::vector<PetscScalar> &zero) {
    const PetscInt own = L.end - L.begin;
    check(MatSetSizes(A_, own, own, L.n, L.n), "MatSetSizes");
    check(MatSetType(A_, MATAIJ), "MatSetType");  // MATSEQAIJ on one rank, else MATMPIAIJ
    check(MatSetOptionsPrefix(A_, "nd_"), "MatSetOptionsPrefix");
    if (block_size > 1) check(MatSetBlockSize(A_, block_size), "MatSetBlockSize");
    // each call applies only to its own type
    check(MatSeqAIJSetPreallocationCSR(A_, ptr_.data(), col_.data(), zero.data()), "MatSeqAIJSetPreallocationCSR");
    check(MatMPIAIJSetPreallocationCSR(A_, ptr_.data(), col_.data(), zero.data()), "MatMPIAIJSetPreallocationCSR");
    check(MatSetOption(A_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE), "MatSetOption");
  }
  ~Matrix() {
    if (A_ && petsc_alive()) MatDestroy(&A_);
  }
  Matrix(const Matrix &) = delete;
  Matrix &operator=(const Matrix &) = delete;
  Mat get() const { return A_; }

  // M's values of this rank's rows (M has the pattern the matrix was made for);
  // false when they are in place (one rank), true when the matrix is to be assembled
  bool set_values(const Csr &M) {
    MatInfo info;
    check(MatGetInfo(A_, MAT_LOCAL, &info), "MatGetInfo");
    const size_t last = src_.empty() ? first_ + col_.size() : 1 + *std::max_element(src_.begin(), src_.end());
    if (M.n != L_.n || static_cast<size_t>(info.nz_used) != col_.size() || M.val.size() < last)
      fail(ND_ERR_INTERNAL, "the matrix does not have the pattern its PETSc solver was made for");
    if (src_.empty() && !L_.distributed()) {  // one rank: the rows in their order, entry for entry
      PetscScalar *a = nullptr;
      check(MatSeqAIJGetArray(A_, &a), "MatSeqAIJGetArray");
      std::copy(M.val.begin() + first_, M.val.begin() + first_ + col_.size(), a);
      check(MatSeqAIJRestoreArray(A_, &a), "MatSeqAIJRestoreArray");  // raises the matrix's state
      return false;
    }
    std::vector<PetscScalar> gathered;
    if (!src_.empty()) {
      gathered.resize(src_.size());
      for (size_t k = 0; k < src_.size(); ++k) gathered[k] = M.val[src_[k]];
    }
    const PetscScalar *v = src_.empty() ? M.val.data() + first_ : gathered.data();
    for (PetscInt r = 0; r < L_.end - L_.begin; ++r) {
      const PetscInt i = L_.begin + r, k = ptr_[r];
      check(MatSetValues(A_, 1, &i, ptr_[r + 1] - k, &col_[k], &v[k], INSERT_VALUES), "MatSetValues");
    }
    return true;
  }

  // The matrix as the sum over the ranks of their parts (each rank's: its
  // own cells' contributions, rows anywhere): this rank adds its part; the
  // entries of other ranks' rows go to them in the assembly.
  void add_parts(const Csr &own) {
    if (own.n != L_.n) fail(ND_ERR_INTERNAL, "the rank's part of the matrix has another size than the matrix");
    check(MatZeroEntries(A_), "MatZeroEntries");
    std::vector<PetscInt> cols;
    for (int64_t at = 0; at < own.stored(); ++at) {
      const int64_t b = own.ptr[at], e = own.ptr[at + 1];
      if (b == e) continue;
      const PetscInt r = L_.row(own.row_at(at));
      cols.resize(static_cast<size_t>(e - b));
      for (int64_t k = b; k < e; ++k) cols[k - b] = L_.row(own.col[k]);
      check(MatSetValues(A_, 1, &r, static_cast<PetscInt>(e - b), cols.data(), &own.val[b], ADD_VALUES),
            "MatSetValues (ADD_VALUES)");
    }
  }
  // A's rows of this rank, or the sum of the ranks' parts when `own` is given.
  // What a rank does alone (the checks, its values) may fail on that rank
  // only: the ranks agree on it before the assembly, which they call together
  // (parallel/agreement.hpp).
  void fill(const Csr &A, const Csr *own) {
    bool assemble = true;
    const MPI_Comm comm = L_.comm;
    const bool several = L_.distributed();
    auto worst_of = [comm, several](int mine) {
      if (several && MPI_Allreduce(MPI_IN_PLACE, &mine, 1, MPI_INT, MPI_MIN, comm) != MPI_SUCCESS)
        fail(ND_ERR_INTERNAL, "MPI_Allreduce of the ranks' statuses failed");
      return mine;
    };
    on_every_rank(
        worst_of,
        [&] {
          require_finite(A);
          if (own) {
            require_finite(*own);
            add_parts(*own);
          } else {
            assemble = set_values(A);
          }
        },
        "filling the distributed matrix", "no rank factored it");
    if (!assemble) return;
    check(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY), "MatAssemblyBegin");
    check(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY), "MatAssemblyEnd");
  }

 private:
  Layout L_;
  Mat A_ = nullptr;
  std::vector<PetscInt> ptr_, col_;  // this rank's rows, columns in the layout's numbering
  std::vector<int64_t> src_;         // the pattern's index of each entry (empty: first_ + k)
  int64_t first_ = 0;
};

// The right-hand side and solution vectors of a matrix's layout, and the
// solution gathered to every rank.
class Vectors {
 public:
  Vectors(Mat A, const Layout &L) : L_(L) {
    try {
      check(MatCreateVecs(A, &x_, &b_), "MatCreateVecs");
      if (L.distributed()) check(VecScatterCreateToAll(x_, &to_all_, &all_), "VecScatterCreateToAll");
    } catch (...) {
      release();
      throw;
    }
  }
  ~Vectors() { release(); }
  void release() {
    if (!petsc_alive()) return;
    for (VecScatter *s : {&to_all_, &pick_})
      if (*s) VecScatterDestroy(s);
    for (Vec *v : {&b_, &x_, &all_, &picked_})
      if (*v) VecDestroy(v);
  }
  Vectors(const Vectors &) = delete;
  Vectors &operator=(const Vectors &) = delete;
  Vec rhs() const { return b_; }
  bool distributed() const { return L_.distributed(); }
  // the other ranks' rows of a solution, gathered to this one
  int64_t received() const { return L_.distributed() ? L_.n - (L_.end - L_.begin) : 0; }
  // of the unknowns `at`, those of the other ranks' rows
  int64_t received(const std::vector<int64_t> &at) const {
    if (!L_.distributed()) return 0;
    int64_t other = 0;
    for (int64_t u : at) other += L_.row(u) < L_.begin || L_.row(u) >= L_.end;
    return other;
  }
  // Where a solution goes on several ranks: gathered whole, or (at non-null)
  // only its values at the unknowns *at, to out
  struct Keep {
    const std::vector<int64_t> *at = nullptr;
    double *out = nullptr;
  };

  // x (the whole vector, on every rank) in place: b <- this rank's rows of x,
  // run(b, solution) solves, x <- the whole solution (or what keep says).
  // One rank: the solution is written in x's storage directly.
  // With a guess (a whole vector), the solution vector starts as its rows.
  template <class Run>
  PetscErrorCode solve(double *x, Run &&run, Keep keep = {}, const double *guess = nullptr) const {
    PetscScalar *a = nullptr;
    PetscErrorCode code = VecGetArrayWrite(b_, &a);
    if (code) return code;
    for (PetscInt k = 0; k < L_.end - L_.begin; ++k) a[k] = x[L_.unknown(k)];
    if ((code = VecRestoreArrayWrite(b_, &a))) return code;
    if (guess && !L_.distributed()) std::copy(guess, guess + L_.n, x);  // (x is the solution's storage below)
    if (guess && L_.distributed()) {
      if ((code = VecGetArrayWrite(x_, &a))) return code;
      for (PetscInt k = 0; k < L_.end - L_.begin; ++k) a[k] = guess[L_.unknown(k)];
      if ((code = VecRestoreArrayWrite(x_, &a))) return code;
    }
    if (!L_.distributed()) {
      if ((code = VecPlaceArray(x_, x))) return code;
      code = run(b_, x_);
      VecResetArray(x_);
      return code;
    }
    if ((code = run(b_, x_))) return code;
    return keep.at ? pick(x_, *keep.at, keep.out) : gather(x_, x);
  }

  // The same for k whole vectors (column j at x + j n), as dense matrices of
  // this rank's rows: run(B, X) solves them all at once; with keep.at, column
  // j's values at those unknowns go to keep.out + j m.
  template <class Run>
  PetscErrorCode solve_many(double *x, int64_t k, Run &&run, Keep keep = {}) const {
    const PetscInt own = L_.end - L_.begin;
    Mat B = nullptr, X = nullptr;
    PetscErrorCode code = MatCreateDense(L_.comm, own, PETSC_DECIDE, L_.n, static_cast<PetscInt>(k), nullptr, &B);
    if (!code) code = MatCreateDense(L_.comm, own, PETSC_DECIDE, L_.n, static_cast<PetscInt>(k), nullptr, &X);
    PetscScalar *b = nullptr;
    if (!code) code = MatDenseGetArrayWrite(B, &b);
    if (!code) {
      for (int64_t j = 0; j < k; ++j)
        for (PetscInt r = 0; r < own; ++r) b[j * own + r] = x[j * L_.n + L_.unknown(r)];
      code = MatDenseRestoreArrayWrite(B, &b);
    }
    if (!code) code = run(B, X);
    PetscScalar *s = nullptr;
    if (!code) code = MatDenseGetArray(X, &s);
    for (int64_t j = 0; !code && j < k; ++j) {  // each column gathered to every rank, or picked
      if ((code = VecPlaceArray(x_, s + j * own))) break;
      code = keep.at ? pick(x_, *keep.at, keep.out + static_cast<size_t>(j) * keep.at->size())
                     : gather(x_, x + j * L_.n);
      VecResetArray(x_);
    }
    if (s) MatDenseRestoreArray(X, &s);
    MatDestroy(&B);
    MatDestroy(&X);
    return code;
  }

 private:
  // x <- the whole vector of the distributed v, on every rank
  PetscErrorCode gather(Vec v, double *x) const {
    PetscErrorCode code;
    if ((code = VecScatterBegin(to_all_, v, all_, INSERT_VALUES, SCATTER_FORWARD))) return code;
    if ((code = VecScatterEnd(to_all_, v, all_, INSERT_VALUES, SCATTER_FORWARD))) return code;
    const PetscScalar *r = nullptr;
    if ((code = VecGetArrayRead(all_, &r))) return code;
    for (int64_t u = 0; u < L_.n; ++u) x[u] = r[L_.row(u)];
    return VecRestoreArrayRead(all_, &r);
  }
  // out[i] <- v at the unknown at[i], through a scatter made for that list
  // (again when it changes on any rank: making it is collective)
  PetscErrorCode pick(Vec v, const std::vector<int64_t> &at, double *out) const {
    PetscErrorCode code;
    int changed = !pick_ || at != pick_at_;
    if (MPI_Allreduce(MPI_IN_PLACE, &changed, 1, MPI_INT, MPI_LOR, L_.comm) != MPI_SUCCESS) return PETSC_ERR_LIB;
    if (changed) {
      if (pick_ && (code = VecScatterDestroy(&pick_))) return code;
      if (picked_ && (code = VecDestroy(&picked_))) return code;
      pick_at_.clear();
      std::vector<PetscInt> rows(at.size());
      for (size_t i = 0; i < at.size(); ++i) rows[i] = L_.row(at[i]);
      IS from = nullptr;
      const PetscInt m = static_cast<PetscInt>(at.size());
      if ((code = ISCreateGeneral(PETSC_COMM_SELF, m, rows.data(), PETSC_COPY_VALUES, &from))) return code;
      code = VecCreateSeq(PETSC_COMM_SELF, m, &picked_);
      if (!code) code = VecScatterCreate(v, from, picked_, nullptr, &pick_);
      ISDestroy(&from);
      if (code) return code;
      pick_at_ = at;
    }
    if ((code = VecScatterBegin(pick_, v, picked_, INSERT_VALUES, SCATTER_FORWARD))) return code;
    if ((code = VecScatterEnd(pick_, v, picked_, INSERT_VALUES, SCATTER_FORWARD))) return code;
    const PetscScalar *r = nullptr;
    if ((code = VecGetArrayRead(picked_, &r))) return code;
    std::copy(r, r + at.size(), out);
    return VecRestoreArrayRead(picked_, &r);
  }

  Layout L_;
  Vec b_ = nullptr, x_ = nullptr, all_ = nullptr;
  VecScatter to_all_ = nullptr;
  mutable Vec picked_ = nullptr;  // the values at pick_at_, through pick_
  mutable VecScatter pick_ = nullptr;
  mutable std::vector<int64_t> pick_at_;
};

void destroy(Mat &A) {
  if (A && petsc_alive()) MatDestroy(&A);
  A = nullptr;
}

// ---- MUMPS ----------------------------------------------------------------------

class PetscMumps : public Factorization {
 public:
  PetscMumps(const Csr &pattern, const DofGeometry *geometry) : n_(pattern.n) {
    Session s;
    const Layout L = make_layout(geometry, n_, 1);
    A_ = std::make_unique<Matrix>(pattern, 1, L);
    v_ = std::make_unique<Vectors>(A_->get(), L);
  }
  ~PetscMumps() override {
    std::lock_guard<std::recursive_mutex> lock(petsc_mutex());
    destroy(F_);
    v_.reset();
    A_.reset();
  }
  void factor(const Csr &A, Structure s) override { factor_from(A, nullptr, s); }
  void factor_parts(const Csr &A, const Csr &own, Structure s) override { factor_from(A, &own, s); }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "petsc-mumps"; }
  int64_t received_per_solve() const override { return v_ ? v_->received() : 0; }
  void solve(double *x) const override {
    if (!factored_) fail(ND_ERR_INTERNAL, "PETSc MUMPS: solve before a successful factorization");
    Session session;
    check(v_->solve(x, [&](Vec b, Vec sol) { return MatSolve(F_, b, sol); }), "MatSolve (MUMPS)");
  }
  // over several ranks (not bitwise reproducible: MUMPS schedules its work
  // dynamically) one multi-right-hand-side solve; on one rank each column
  // alone, the bits of solve()
  void solve_many(double *x, int64_t n, int64_t k) const override {
    if (!v_->distributed() || k < 2) return Factorization::solve_many(x, n, k);
    if (n != n_) fail(ND_ERR_INTERNAL, "PETSc MUMPS: right-hand sides of another size than the matrix");
    if (!factored_) fail(ND_ERR_INTERNAL, "PETSc MUMPS: solve before a successful factorization");
    Session session;
    check(v_->solve_many(x, k, [&](Mat B, Mat X) { return MatMatSolve(F_, B, X); }), "MatMatSolve (MUMPS)");
  }
  // the same block solve, of each solution only the rows `at` gathered (one
  // column: MatSolve, cheaper than MatMatSolve for a single right-hand side)
  void solve_many_at(double *x, int64_t n, int64_t k, const std::vector<int64_t> &at, double *out) const override {
    if (!v_->distributed()) return Factorization::solve_many_at(x, n, k, at, out);
    if (n != n_) fail(ND_ERR_INTERNAL, "PETSc MUMPS: right-hand sides of another size than the matrix");
    if (!factored_) fail(ND_ERR_INTERNAL, "PETSc MUMPS: solve before a successful factorization");
    Session session;
    if (k == 1) {
      check(v_->solve(x, [&](Vec b, Vec sol) { return MatSolve(F_, b, sol); }, {&at, out}), "MatSolve (MUMPS)");
      return;
    }
    check(v_->solve_many(x, k, [&](Mat B, Mat X) { return MatMatSolve(F_, B, X); }, {&at, out}),
          "MatMatSolve (MUMPS)");
  }
  int64_t received_at(const std::vector<int64_t> &at) const override { return v_ ? v_->received(at) : 0; }

 private:
  // MUMPS sizes its work arrays from the analysis' estimate plus ICNTL(14)
  // per cent (20 by default); the estimate can fall short (INFOG(1) = -8, -9,
  // -17, -20: "increase ICNTL(14)", seen with 4 slab ranks on the hexahedral
  // ball), which is not a lack of memory: the factorization is made again
  // with 4 times the relaxation, up to kMostRelaxation per cent
  static constexpr int kMostRelaxation = 1280;
  void factor_from(const Csr &A, const Csr *own, Structure s) {
    for (;;) {
      try {
        factor_once(A, own, s);
        return;
      } catch (const WorkspaceShort &short_of) {
        if (relaxation_ >= kMostRelaxation) fail(ND_ERR_NOMEM, "out of memory" + short_of.status);
        relaxation_ = 4 * std::max(relaxation_, 20);
      }
    }
  }
  struct WorkspaceShort {
    std::string status;
  };
  void factor_once(const Csr &A, const Csr *own, Structure s) {
    def_ = Definiteness::Unknown;
    Session session;
    factored_ = false;
    A_->fill(A, own);
    const bool cholesky = s == Structure::SymmetricPositiveDefinite;
    MatFactorInfo info;
    check(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
    if (!F_ || cholesky != cholesky_) {  // the analysis (MUMPS JOB = 1)
      destroy(F_);
      cholesky_ = cholesky;
      check(MatSetOption(A_->get(), MAT_SYMMETRIC, cholesky ? PETSC_TRUE : PETSC_FALSE), "MatSetOption");
      check(MatGetFactor(A_->get(), MATSOLVERMUMPS, cholesky ? MAT_FACTOR_CHOLESKY : MAT_FACTOR_LU, &F_), "MatGetFactor");
      // the inertia also where a root node would go to ScaLAPACK (parallel runs)
      check(MatMumpsSetIcntl(F_, 13, 1), "MatMumpsSetIcntl(13)");
      if (relaxation_ > 0) check(MatMumpsSetIcntl(F_, 14, relaxation_), "MatMumpsSetIcntl(14)");
      check(MatSetFromOptions(F_), "MatSetFromOptions");
      if (cholesky)
        check(MatCholeskyFactorSymbolic(F_, A_->get(), nullptr, &info), "MatCholeskyFactorSymbolic (MUMPS analysis)");
      else
        check(MatLUFactorSymbolic(F_, A_->get(), nullptr, nullptr, &info), "MatLUFactorSymbolic (MUMPS analysis)");
      require_no_factor_error("analysis", s);
    }
    if (cholesky)
      check(MatCholeskyFactorNumeric(F_, A_->get(), &info), "MatCholeskyFactorNumeric (MUMPS)");
    else
      check(MatLUFactorNumeric(F_, A_->get(), &info), "MatLUFactorNumeric (MUMPS)");
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
    // (the work arrays' estimate fell short: factor_from retries with more)
    if (infog1 == -8 || infog1 == -9 || infog1 == -17 || infog1 == -20) throw WorkspaceShort{st};
    if (err == MAT_FACTOR_OUTMEMORY || infog1 == -13 || infog1 == -14 || infog1 == -15)
      fail(ND_ERR_NOMEM, "out of memory" + st);
    fail(ND_ERR_INTERNAL, "MUMPS failed" + st);
  }

  int64_t n_;
  std::unique_ptr<Matrix> A_;
  std::unique_ptr<Vectors> v_;
  Mat F_ = nullptr;
  bool cholesky_ = false, factored_ = false;
  Definiteness def_ = Definiteness::Unknown;
  int relaxation_ = 0;  // ICNTL(14) once a factorization fell short (0: MUMPS's default)
};

// ---- GAMG -----------------------------------------------------------------------

// Sums of k values over the ranks of `comm`, the same bits on every rank:
// each rank's values gathered, then added rank after rank.
void sum_over_ranks(MPI_Comm comm, int size, double *x, int k) {
  if (size == 1 || k == 0) return;
  std::vector<double> all(static_cast<size_t>(size) * static_cast<size_t>(k));
  if (MPI_Allgather(x, k, MPI_DOUBLE, all.data(), k, MPI_DOUBLE, comm) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Allgather of the ranks' sums failed");
  for (int j = 0; j < k; ++j) {
    x[j] = 0;
    for (int r = 0; r < size; ++r) x[j] += all[static_cast<size_t>(r) * k + j];
  }
}

// The rigid-body modes of the unknowns (dim translations, and 1 rotation in
// 2D or 3 in 3D about the centroid), orthonormalized; empty when the geometry
// does not describe these unknowns. Whether the unknowns come in whole nodes
// (free DOFs node by node, every component free) goes to block_size.
// With a geometry of the rank's rows only (split rows) the modes are the
// rank's rows of them, from sums over the ranks (collective; the same
// verdicts on every rank), and no array is n long; else every unknown's.
std::vector<std::vector<double>> rigid_body_modes(const DofGeometry *g, int64_t n, PetscInt &block_size) {
  block_size = 1;
  std::vector<std::vector<double>> modes;
  const bool own = g && g->own_rows_only;
  const int64_t m = own ? g->row_end - g->row_begin : n;  // the unknowns described here
  if (!g || g->dim < 1 || g->dim > 3 || static_cast<int64_t>(g->component.size()) != m ||
      static_cast<int64_t>(g->x.size()) != m * g->dim || n == 0)
    return modes;
  const MPI_Comm comm = mpi_comm(g->comm.get());
  const int size = own ? communicator_size(g->comm.get()) : 1;
  const int d = g->dim;
  double centre[3] = {0, 0, 0};
  for (int64_t i = 0; i < m; ++i)
    for (int k = 0; k < d; ++k) centre[k] += g->x[i * d + k] / static_cast<double>(n);
  sum_over_ranks(comm, size, centre, d);
  const int nmodes = d == 1 ? 1 : d == 2 ? 3 : 6;
  modes.assign(static_cast<size_t>(nmodes), std::vector<double>(static_cast<size_t>(m), 0.0));
  for (int64_t i = 0; i < m; ++i) {
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
  // modified Gram-Schmidt, twice; modes that vanish (all their DOFs clamped)
  // are dropped. Each product is summed over the ranks (with one rank: the
  // product itself).
  auto dot = [&](const std::vector<double> &a, const std::vector<double> &b) {
    double h = std::inner_product(a.begin(), a.end(), b.begin(), 0.0);
    sum_over_ranks(comm, size, &h, 1);
    return h;
  };
  std::vector<std::vector<double>> basis;
  for (auto &v : modes) {
    const double before = std::sqrt(dot(v, v));
    for (int pass = 0; pass < 2; ++pass)
      for (const auto &q : basis) {
        const double h = dot(q, v);
        for (int64_t i = 0; i < m; ++i) v[i] -= h * q[i];
      }
    const double norm = std::sqrt(dot(v, v));
    if (!(norm > 1e-10 * before)) continue;
    for (double &e : v) e /= norm;
    basis.push_back(std::move(v));
  }
  // (a rank's rows are whole nodes of its own, consecutive in its order)
  int whole_nodes = m % d == 0;
  for (int64_t i = 0; whole_nodes && i < m; ++i)
    whole_nodes = g->component[i] == i % d && std::equal(&g->x[i * d], &g->x[i * d] + d, &g->x[(i - i % d) * d]);
  if (own && size > 1 && MPI_Allreduce(MPI_IN_PLACE, &whole_nodes, 1, MPI_INT, MPI_MIN, comm) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Allreduce of the ranks' node blocks failed");
  if (whole_nodes) block_size = d;
  return basis;
}

class PetscGamg : public Factorization {
 public:
  PetscGamg(const Csr &pattern, const DofGeometry *geometry) : n_(pattern.n) {
    PetscInt block_size = 1;
    const std::vector<std::vector<double>> modes = rigid_body_modes(geometry, n_, block_size);
    Session s;
    const Layout L = make_layout(geometry, n_, block_size);
    A_ = std::make_unique<Matrix>(pattern, block_size, L);
    v_ = std::make_unique<Vectors>(A_->get(), L);
    if (!modes.empty()) set_near_null_space(modes, L, geometry->own_rows_only);
    check(KSPCreate(L.comm, &ksp_), "KSPCreate");
    check(KSPSetOptionsPrefix(ksp_, "nd_"), "KSPSetOptionsPrefix");
  }
  ~PetscGamg() override {
    std::lock_guard<std::recursive_mutex> lock(petsc_mutex());
    if (ksp_ && petsc_alive()) KSPDestroy(&ksp_);
    v_.reset();
    A_.reset();
  }
  // the modes over every unknown (each rank gives its own rows), or (own:
  // a geometry of the rank's rows) over those rows only
  void set_near_null_space(const std::vector<std::vector<double>> &modes, const Layout &L, bool own) {
    std::vector<Vec> vecs;
    MatNullSpace space = nullptr;
    PetscErrorCode code = 0;
    for (const auto &m : modes) {
      Vec v = nullptr;
      if ((code = VecDuplicate(v_->rhs(), &v))) break;
      vecs.push_back(v);
      PetscScalar *a = nullptr;
      if ((code = VecGetArrayWrite(v, &a))) break;
      for (PetscInt k = 0; k < L.end - L.begin; ++k) a[k] = own ? m[static_cast<size_t>(k)] : m[L.unknown(k)];
      if ((code = VecRestoreArrayWrite(v, &a))) break;
    }
    if (!code) code = MatNullSpaceCreate(L.comm, PETSC_FALSE, static_cast<PetscInt>(vecs.size()), vecs.data(), &space);
    if (!code) code = MatSetNearNullSpace(A_->get(), space);
    if (space) MatNullSpaceDestroy(&space);
    for (Vec &v : vecs) VecDestroy(&v);
    check(code, "MatSetNearNullSpace (rigid-body modes)");
  }
  void factor(const Csr &A, Structure s) override { factor_from(A, nullptr, s); }
  void factor_parts(const Csr &A, const Csr &own, Structure s) override { factor_from(A, &own, s); }
  // Newton's tangents T = A + kappa N'(U) differ from each other in the
  // contact points' few rows: the hierarchy set up for one serves the next
  // almost as well as its own, and set-ups are a large part of a run's
  // time (docs/performance.md, "GAMG hierarchy reuse"). So a tangent keeps
  // it while its solves take at most kStaleFactor times the iterations of the first solve
  // after the set-up (then the next tangent sets up anew), and a solve that
  // does not converge with it sets up for its matrix and solves again.
  bool refactor(const Csr &A, Structure s) override {
    if (!ready_ || stale_ || s != structure_) {
      factor_from(A, nullptr, s);
      return true;
    }
    Session session;
    ready_ = false;
    A_->fill(A, nullptr);
    check(KSPSetReusePreconditioner(ksp_, PETSC_TRUE), "KSPSetReusePreconditioner");
    check(KSPSetOperators(ksp_, A_->get(), A_->get()), "KSPSetOperators");
    def_ = Definiteness::Unknown;
    kept_ = true;
    ready_ = true;
    return false;
  }
  int64_t setups_in_solves() const override { return setups_in_solves_; }
  int64_t krylov_iterations() const override { return krylov_iterations_; }
  void factor_from(const Csr &A, const Csr *own, Structure s) {
    def_ = Definiteness::Unknown;
    Session session;
    ready_ = false;
    kept_ = stale_ = false;
    first_iterations_ = -1;
    structure_ = s;
    A_->fill(A, own);
    check(KSPSetReusePreconditioner(ksp_, PETSC_FALSE), "KSPSetReusePreconditioner");
    const bool spd = s == Structure::SymmetricPositiveDefinite;
    check(MatSetOption(A_->get(), MAT_SYMMETRIC, spd ? PETSC_TRUE : PETSC_FALSE), "MatSetOption");
    check(KSPSetOperators(ksp_, A_->get(), A_->get()), "KSPSetOperators");
    check(KSPSetType(ksp_, spd ? KSPCG : KSPGMRES), "KSPSetType");
    // the true residual in the stopping rule: CG computes it, GMRES when preconditioned from the right
    check(KSPSetPCSide(ksp_, spd ? PC_LEFT : PC_RIGHT), "KSPSetPCSide");
    check(KSPSetNormType(ksp_, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
    check(KSPSetTolerances(ksp_, kKrylovRtol, 0.0, PETSC_DEFAULT, kKrylovMaxIterations), "KSPSetTolerances");
    PC pc = nullptr;
    check(KSPGetPC(ksp_, &pc), "KSPGetPC");
    check(PCSetType(pc, PCGAMG), "PCSetType(PCGAMG)");
    // every set-up builds the aggregates and prolongators for its matrix (by
    // default GAMG keeps them when the pattern is the same: measured, a
    // hierarchy made for c M + K with c = 1e4 and set up again for c = 1e-2
    // gave an indefinite preconditioner); refactor keeps the whole hierarchy
    check(PCGAMGSetReuseInterpolation(pc, PETSC_FALSE), "PCGAMGSetReuseInterpolation");
    check(KSPSetFromOptions(ksp_), "KSPSetFromOptions");
    check(KSPSetUp(ksp_), "KSPSetUp (GAMG hierarchy)");
    PCFailedReason why = PC_NOERROR;
    check(PCGetFailedReason(pc, &why), "PCGetFailedReason");
    if (why != PC_NOERROR)
      fail(why == PC_FACTOR_OUTMEMORY ? ND_ERR_NOMEM : ND_ERR_SINGULAR,
           std::string("PETSc GAMG set-up failed: ") + PCFailedReasons[why]);
    ready_ = true;
  }
  void solve(double *x) const override { solve_keeping(x, {}); }
  // (the time step's predictor as the first guess saves CG iterations)
  void solve_from(double *x, const double *guess) const override { solve_keeping(x, {}, guess); }
  bool starts_from_guess() const override { return true; }
  // each column a Krylov solve, of each solution only the rows `at` gathered
  void solve_many_at(double *x, int64_t n, int64_t k, const std::vector<int64_t> &at, double *out) const override {
    if (!v_->distributed()) return Factorization::solve_many_at(x, n, k, at, out);
    if (n != n_) fail(ND_ERR_INTERNAL, "PETSc GAMG: right-hand sides of another size than the matrix");
    for (int64_t j = 0; j < k; ++j) solve_keeping(x + j * n, {&at, out + static_cast<size_t>(j) * at.size()});
  }
  // from the guess, of the solution only the rows `at` gathered
  void solve_from_at(double *x, int64_t n, const double *guess, const std::vector<int64_t> &at,
                     double *out) const override {
    if (n != n_) fail(ND_ERR_INTERNAL, "PETSc GAMG: right-hand side of another size than the matrix");
    solve_keeping(x, {&at, out}, guess);
    if (!v_->distributed())  // (one rank: the whole solution is in x)
      for (size_t i = 0; i < at.size(); ++i) out[i] = x[at[i]];
  }
  int64_t received_at(const std::vector<int64_t> &at) const override { return v_ ? v_->received(at) : 0; }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "petsc-gamg"; }
  int64_t received_per_solve() const override { return v_ ? v_->received() : 0; }

 private:
  void solve_keeping(double *x, Vectors::Keep keep, const double *guess = nullptr) const {
    if (!ready_) fail(ND_ERR_INTERNAL, "PETSc GAMG: solve before a successful set-up");
    Session session;
    KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
    PetscInt its = 0;
    PetscReal rnorm = 0, bnorm = 0;
    check(v_->solve(x,
                    [&](Vec b, Vec sol) {
                      auto krylov = [&](bool from_guess) {
                        PetscErrorCode code = KSPSetInitialGuessNonzero(ksp_, from_guess ? PETSC_TRUE : PETSC_FALSE);
                        if (!code) code = KSPSolve(ksp_, b, sol);
                        if (!code) code = KSPGetConvergedReason(ksp_, &reason);
                        if (!code) code = KSPGetIterationNumber(ksp_, &its);
                        if (!code) krylov_iterations_ += its;
                        return code;
                      };
                      PetscErrorCode code = krylov(guess != nullptr);
                      if (!code && kept_ && reason <= 0) {  // the kept hierarchy stopped serving: set up for this matrix
                        // (KSPSetOperators again: after a solve KSPSetUp skips the PC until the operators change)
                        code = KSPSetReusePreconditioner(ksp_, PETSC_FALSE);
                        if (!code) code = KSPSetOperators(ksp_, A_->get(), A_->get());
                        kept_ = stale_ = false;
                        first_iterations_ = -1;
                        ++setups_in_solves_;
                        if (!code) code = krylov(false);  // (from zero: sol holds the failed iterate)
                      }
                      if (!code && reason > 0) {
                        if (first_iterations_ < 0) first_iterations_ = its;
                        if (kept_ && its > kStaleFactor * first_iterations_) stale_ = true;
                      }
                      if (!code) code = KSPGetResidualNorm(ksp_, &rnorm);
                      if (!code) code = VecNorm(b, NORM_2, &bnorm);
                      return code;
                    },
                    keep, guess),
          "KSPSolve (GAMG)");
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
  int64_t n_;
  std::unique_ptr<Matrix> A_;
  std::unique_ptr<Vectors> v_;
  KSP ksp_ = nullptr;
  bool ready_ = false;
  Structure structure_ = Structure::General;
  mutable Definiteness def_ = Definiteness::Unknown;
  // refactor's kept hierarchy: kept_ while a tangent uses one set up for an
  // earlier matrix; stale_ once a solve took more than kStaleFactor times
  // first_iterations_ (the first solve's after the set-up)
  static constexpr PetscInt kStaleFactor = 2;
  mutable bool kept_ = false, stale_ = false;
  mutable PetscInt first_iterations_ = -1;
  mutable int64_t setups_in_solves_ = 0;
  mutable int64_t krylov_iterations_ = 0;  // of every solve, since creation
};

}  // namespace

// ---- the partition of the cells (parallel/ownership.hpp) --------------------------

bool petsc_partition_cells(const Communicator *c, int64_t n_cells, const std::vector<int64_t> &ia,
                           const std::vector<int64_t> &ja, std::vector<int> &owner, std::string &method) {
  Session session;
  const MPI_Comm comm = mpi_comm(c);
  const PetscInt local = petsc_int(static_cast<int64_t>(ia.size()) - 1, "cells");
  PetscInt *i = nullptr, *j = nullptr;  // the adjacency matrix takes them (PetscFree)
  check(PetscMalloc1(ia.size(), &i), "PetscMalloc1");
  if (PetscMalloc1(std::max<size_t>(ja.size(), 1), &j)) {
    PetscFree(i);
    fail(ND_ERR_NOMEM, "out of memory for the cells' dual graph");
  }
  std::transform(ia.begin(), ia.end(), i, [](int64_t v) { return static_cast<PetscInt>(v); });
  std::transform(ja.begin(), ja.end(), j, [](int64_t v) { return static_cast<PetscInt>(v); });
  Mat adj = nullptr;
  MatPartitioning part = nullptr;
  IS is = nullptr;
  const PetscInt *parts = nullptr;
  struct Release {  // whatever was made, on every way out
    Mat &adj;
    MatPartitioning &part;
    IS &is;
    const PetscInt *&parts;
    ~Release() {
      if (!petsc_alive()) return;
      if (parts) ISRestoreIndices(is, &parts);
      if (is) ISDestroy(&is);
      if (part) MatPartitioningDestroy(&part);
      if (adj) MatDestroy(&adj);
    }
  } release{adj, part, is, parts};
  const PetscErrorCode made = MatCreateMPIAdj(comm, local, petsc_int(n_cells, "cells"), i, j, nullptr, &adj);
  if (made) {
    PetscFree(i), PetscFree(j);
    fail_petsc(made, "MatCreateMPIAdj (the cells' dual graph)");
  }
  check(MatPartitioningCreate(comm, &part), "MatPartitioningCreate");
  check(MatPartitioningSetAdjacency(part, adj), "MatPartitioningSetAdjacency");
  check(PetscObjectSetOptionsPrefix(reinterpret_cast<PetscObject>(part), "nd_"), "PetscObjectSetOptionsPrefix");
  // Which partitioners this PETSc has: setting an unregistered type fails.
  // Debian's PT-Scotch 7 runs threads that call MPI: with less than
  // MPI_THREAD_MULTIPLE it crashes or hangs now and then unless
  // SCOTCH_PTHREAD_NUMBER=1 keeps it to one thread.
  int level = MPI_THREAD_SINGLE;
  MPI_Query_thread(&level);
  const char *threads = std::getenv("SCOTCH_PTHREAD_NUMBER");
  const bool scotch_safe = level == MPI_THREAD_MULTIPLE || (threads && std::strcmp(threads, "1") == 0);
  bool found = false;
  for (MatPartitioningType type : {MATPARTITIONINGPTSCOTCH, MATPARTITIONINGPARMETIS})
    if (!found && (scotch_safe || std::strcmp(type, MATPARTITIONINGPTSCOTCH) != 0) && !MatPartitioningSetType(part, type))
      found = true;
  g_petsc_message.clear();
  PetscBool asked = PETSC_FALSE;
  check(PetscOptionsHasName(nullptr, "nd_", "-mat_partitioning_type", &asked), "PetscOptionsHasName");
  if (!found && !asked) return false;
  check(MatPartitioningSetFromOptions(part), "MatPartitioningSetFromOptions");
  MatPartitioningType type = nullptr;
  check(MatPartitioningGetType(part, &type), "MatPartitioningGetType");
#ifdef ND_HAVE_SCOTCH
  // PT-Scotch draws from Scotch's one random generator, which each
  // partition advanced: a second problem of the same mesh in the process got
  // another partition, and with it other bits. Reset,
  // one Scotch thread gives the same partition every time (several threads,
  // with MPI_THREAD_MULTIPLE, still vary from call to call)
  if (type && std::strcmp(type, MATPARTITIONINGPTSCOTCH) == 0) SCOTCH_randomReset();
#endif
  check(MatPartitioningApply(part, &is), "MatPartitioningApply");
  method = type ? type : "?";
  PetscInt n_is = 0;
  check(ISGetLocalSize(is, &n_is), "ISGetLocalSize");
  check(ISGetIndices(is, &parts), "ISGetIndices");
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<int> mine(parts, parts + n_is), counts(static_cast<size_t>(size)), first(static_cast<size_t>(size), 0);
  const int n_mine = static_cast<int>(n_is);
  if (MPI_Allgather(&n_mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm) != MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Allgather of the partition's sizes failed");
  std::partial_sum(counts.begin(), counts.end() - 1, first.begin() + 1);
  owner.assign(static_cast<size_t>(n_cells), 0);
  if (MPI_Allgatherv(mine.data(), n_mine, MPI_INT, owner.data(), counts.data(), first.data(), MPI_INT, comm) !=
      MPI_SUCCESS)
    fail(ND_ERR_INTERNAL, "MPI_Allgatherv of the cells' owners failed");
  return true;
}

std::unique_ptr<Factorization> make_petsc_mumps_factorization(const Csr &p, const DofGeometry *g) {
  return std::make_unique<PetscMumps>(p, g);
}
std::unique_ptr<Factorization> make_petsc_gamg_factorization(const Csr &p, const DofGeometry *g) {
  return std::make_unique<PetscGamg>(p, g);
}

}  // namespace nd
