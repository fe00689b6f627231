// One small interface over the direct solvers. A factorization is created
// for a pattern (the symbolic work: ordering, bandwidth) and then factors any
// matrix of that pattern numerically, as often as needed.
#pragma once
#include <memory>
#include <vector>

#include "common/counters.hpp"
#include "linalg/csr.hpp"
#include "parallel/communicator.hpp"

namespace nd {

enum class Structure { SymmetricPositiveDefinite, General };
// What the last factor() learnt about the matrix (NotPositiveDefinite: it
// threw ND_ERR_INDEFINITE). Unknown: factored as General, the backend's
// pivoting hid the inertia, or factor() failed otherwise.
enum class Definiteness { PositiveDefinite, NotPositiveDefinite, Unknown };

class Factorization {
 public:
  virtual ~Factorization() = default;
  // Throws ND_ERR_INDEFINITE (SPD requested on a matrix that is certainly
  // not positive definite) or ND_ERR_SINGULAR.
  virtual void factor(const Csr &A, Structure s) = 0;
  // The same matrix A given also as this rank's part `own` (the
  // contributions of its own cells: the parts of all ranks sum to A). A
  // backend that distributes the matrix assembles it from the parts; the
  // others factor A.
  virtual void factor_parts(const Csr &A, const Csr &own, Structure s) {
    (void)own;
    factor(A, s);
  }
  // A matrix of the pattern, with new values, in a run of matrices close to
  // each other (Newton's tangents): a direct backend factors it and returns
  // true; an iterative one may keep the preconditioner it set up for an
  // earlier matrix while that serves, and returns false (its Krylov solves
  // still reach their tolerance on the new matrix).
  virtual bool refactor(const Csr &A, Structure s) {
    factor(A, s);
    return true;
  }
  // preconditioner set-ups an iterative backend made inside its solves since
  // it was created (a kept preconditioner that stopped serving; refactor)
  virtual int64_t setups_in_solves() const { return 0; }
  // Krylov iterations of its solves since it was created (0: a direct backend)
  virtual int64_t krylov_iterations() const { return 0; }
  virtual void solve(double *x) const = 0;  // in place, one right-hand side
  // solve(x), an iterative backend starting its Krylov iterations from
  // `guess` (a whole vector, e.g. a time step's predictor; its stopping rule
  // on the residual is the same): a direct backend ignores it
  virtual void solve_from(double *x, const double *guess) const {
    (void)guess;
    solve(x);
  }
  // does solve_from read its guess (an iterative backend)? A caller keeps
  // one only for such a backend
  virtual bool starts_from_guess() const { return false; }
  // in place, k right-hand sides (column j at x + j n): each column as
  // solve() would make it (the same bits), unless a backend that is not
  // bitwise reproducible anyway solves them as one block (MUMPS over several
  // ranks: one multi-right-hand-side solve instead of k)
  virtual void solve_many(double *x, int64_t n, int64_t k) const {
    for (int64_t j = 0; j < k; ++j) solve(x + j * n);
  }
  // values a solve receives from the other ranks (a backend that
  // distributes its rows gathers the solution to every rank)
  virtual int64_t received_per_solve() const { return 0; }
  // solve_many, keeping of each solution only the unknowns `at` (m of them):
  // out[j m + i] = x_j[at[i]], x overwritten. A backend that distributes its
  // rows gathers only those to this rank, not every row; the others solve
  // as solve_many (the same bits) and copy.
  virtual void solve_many_at(double *x, int64_t n, int64_t k, const std::vector<int64_t> &at, double *out) const;
  // the part of a whole solve's backward work that solve_many_at makes for
  // the unknowns `at`: 1 when it solves whole (every backend but supernodal
  // CHOLMOD, which solves only for those). A caller may keep columns at few
  // rows when that is small (fast/contact_columns.hpp).
  virtual double backward_share_at(const std::vector<int64_t> &at) const {
    (void)at;
    return 1.0;
  }
  // solve_from, keeping only the unknowns `at`: out[i] = x[at[i]] (one
  // column of solve_many_at, which a direct backend makes; an iterative one
  // starts from the guess)
  virtual void solve_from_at(double *x, int64_t n, const double *guess, const std::vector<int64_t> &at,
                             double *out) const {
    (void)guess;
    solve_many_at(x, n, 1, at, out);
  }
  // x <- A^{-1} x right at the unknowns `at` only (solve_from_at), NaN at the
  // others: on split rows a caller reads no other row, and a NaN would show
  // one that slipped through
  void solve_at(double *x, int64_t n, const std::vector<int64_t> &at, const double *guess = nullptr) const;
  // values solve_many_at receives from the other ranks per right-hand side
  virtual int64_t received_at(const std::vector<int64_t> &at) const {
    (void)at;
    return received_per_solve();
  }
  virtual Definiteness definiteness() const = 0;
  virtual const char *name() const = 0;
  // the backend's own object under any wrapper (its counters): for code that
  // reads a backend's factor (UpdatableCholesky::start_from)
  virtual const Factorization &backend() const { return *this; }
};

// Where the unknowns sit and which ranks solve for them.
// x, component: for each unknown (free DOF) its node's coordinates and its
// component. Algebraic multigrid (ND_SOLVER_PETSC_GAMG) builds the rigid-body
// modes from them (its near-null space); the other solvers ignore them, so
// they are filled only for it (linear_solver_reads_coordinates; empty: none).
// comm: the ranks that solve together (the PETSc backends distribute their
// rows over them; the others solve the whole system on every rank);
// row_of: each unknown's row in the distributed matrix, where the rows of
// each rank are consecutive (null: the unknowns' own order), and
// [row_begin, row_end) this rank's rows, the free DOFs of its nodes
// (parallel/ownership.hpp; row_end < 0: an even split of the rows).
struct DofGeometry {
  int dim = 0;
  std::vector<double> x;         // dim per unknown described
  std::vector<int> component;    // 0 .. dim-1 per unknown described
  bool located = false;          // x and component filled (else empty)
  void forget_coordinates() { x = {}, component = {}, located = false; }
  // x and component hold this rank's rows only, in their order (with row_of:
  // split rows), not every unknown: GAMG's near-null space reads no other
  bool own_rows_only = false;
  CommunicatorPtr comm;          // null: this process alone
  std::shared_ptr<const std::vector<int64_t>> row_of;
  int64_t row_begin = 0, row_end = -1;
};

// solver: an ND_SOLVER_* value; s: the structure of the matrices it will
// factor. AUTO picks by size and bandwidth, CHOLMOD falls back to UMFPACK
// for non-symmetric matrices. Any other id throws ND_ERR_KEY, and so does a
// known id whose backend this build lacks (linear_solver_unavailable). With
// counters, the making (symbolic analysis), every factor() and every solve()
// are counted there. geometry (may be null): see DofGeometry. ordered_like
// (may be null): a factor of a matrix of the same pattern whose fill-reducing
// ordering the new one reuses where both are CHOLMOD's (any ordering is
// correct: only the fill depends on it)
std::unique_ptr<Factorization> make_factorization(int solver, const Csr &pattern, Structure s,
                                                  Counters *counters = nullptr,
                                                  const DofGeometry *geometry = nullptr,
                                                  const Factorization *ordered_like = nullptr);
// whether make_factorization accepts this id (AUTO or a registered backend)
bool linear_solver_known(int solver);
// whether this backend's factor() decides positive definiteness (a direct
// factorization does; an iterative solver does not): the checks that must
// decide it (check_coercivity) use AUTO's direct choice when it does not
bool linear_solver_certifies_definiteness(int solver);
// whether each solve is a Krylov iteration (GAMG): a solve costs many
// products with the matrix and the preconditioner, a set-up a few solves
bool linear_solver_iterative(int solver);
// whether the solver reads where the unknowns sit (DofGeometry::x and
// component: GAMG's rigid-body modes); for the others they are not built
bool linear_solver_reads_coordinates(int solver);
// whether the solver spreads its matrices' rows over a communicator's ranks
// (the PETSc backends; the others solve the whole system on every rank)
bool linear_solver_distributes(int solver);
// For an ND_SOLVER_* id of a backend this build does not have (the PETSc ones
// without ND_WITH_PETSC): why, naming the id; otherwise nullptr.
const char *linear_solver_unavailable(int solver);

}  // namespace nd
