#include "linalg/factorization.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "linalg/ordering.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// The registry. Adding a backend: its file, its ND_SOLVER_* value and one
// line here.
struct Backend {
  int id;
  std::unique_ptr<Factorization> (*make)(const Csr &pattern);
  // a backend that uses the DofGeometry (AMG's modes, the PETSc ones' communicator) has this instead
  std::unique_ptr<Factorization> (*make_geometric)(const Csr &pattern, const DofGeometry *geometry) = nullptr;
};
constexpr Backend kBackends[] = {
    {ND_SOLVER_DENSE, make_dense_factorization},     {ND_SOLVER_BANDED, make_banded_factorization},
    {ND_SOLVER_CHOLMOD, make_cholmod_factorization}, {ND_SOLVER_UMFPACK, make_umfpack_factorization},
    {ND_SOLVER_KLU, make_klu_factorization},
#ifdef ND_HAVE_PETSC
    {ND_SOLVER_PETSC_MUMPS, nullptr, make_petsc_mumps_factorization}, {ND_SOLVER_PETSC_GAMG, nullptr, make_petsc_gamg_factorization},
#endif
};

// Ids of the public list whose backend is optional at build time.
struct Optional {
  int id;
  const char *why;
};
constexpr Optional kOptional[] = {
    {ND_SOLVER_PETSC_MUMPS, "ND_SOLVER_PETSC_MUMPS (6) needs PETSc, and this build of libnitschedyn has none "
                            "(configure with -DND_WITH_PETSC=ON)"},
    {ND_SOLVER_PETSC_GAMG, "ND_SOLVER_PETSC_GAMG (7) needs PETSc, and this build of libnitschedyn has none "
                           "(configure with -DND_WITH_PETSC=ON)"},
};

const Backend *find_backend(int id) {
  for (const Backend &b : kBackends)
    if (b.id == id) return &b;
  return nullptr;
}

// AUTO (bench/solver_crossover; docs/performance.md, "Linear solver
// thresholds"): a step pays one solve, a Newton iteration with active contact
// a factorization too, so the solve decides. A dense solve falls behind
// CHOLMOD's long before its factorization does: dense only for the smallest
// systems. Banded solves lose to CHOLMOD's on 2D meshes: banded only for
// patterns that reverse Cuthill-McKee makes truly narrow (1D meshes:
// half-bandwidth 1-4).
constexpr int64_t kDenseMax = 40, kBandMax = 16;

// The backend that factors for `solver`: AUTO's choice, and CHOLMOD's
// fallback (Cholesky needs symmetry: non-symmetric systems go to UMFPACK).
int backend_for(int solver, const Csr &pattern, Structure s) {
  if (solver == ND_SOLVER_AUTO) {
    if (pattern.n <= kDenseMax) return ND_SOLVER_DENSE;
    if (bandwidth(pattern, reverse_cuthill_mckee(pattern)) <= kBandMax) return ND_SOLVER_BANDED;
    solver = ND_SOLVER_CHOLMOD;
  }
  if (solver == ND_SOLVER_CHOLMOD && s != Structure::SymmetricPositiveDefinite) return ND_SOLVER_UMFPACK;
  return solver;
}

}  // namespace

void Factorization::solve_many_at(double *x, int64_t n, int64_t k, const std::vector<int64_t> &at,
                                  double *out) const {
  solve_many(x, n, k);
  const size_t m = at.size();
  for (int64_t j = 0; j < k; ++j)
    for (size_t i = 0; i < m; ++i) out[static_cast<size_t>(j) * m + i] = x[j * n + at[i]];
}

void Factorization::solve_at(double *x, int64_t n, const std::vector<int64_t> &at, const double *guess) const {
  std::vector<double> kept(at.size());
  solve_from_at(x, n, guess, at, kept.data());
  std::fill(x, x + n, std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < at.size(); ++i) x[at[i]] = kept[i];
}

namespace {

// A backend with its work counted (ND_STAT_*).
class Counted : public Factorization {
 public:
  Counted(std::unique_ptr<Factorization> f, Counters *c) : f_(std::move(f)), c_(c) {}
  void factor(const Csr &A, Structure s) override {
    ++c_->factorizations;  // counted when tried: a failed factorization is work too
    f_->factor(A, s);
  }
  void factor_parts(const Csr &A, const Csr &own, Structure s) override {
    ++c_->factorizations;
    f_->factor_parts(A, own, s);
  }
  bool refactor(const Csr &A, Structure s) override {
    bool fresh = true;
    try {
      fresh = f_->refactor(A, s);
    } catch (...) {
      ++c_->factorizations;  // tried
      throw;
    }
    c_->factorizations += fresh;
    return fresh;
  }
  int64_t setups_in_solves() const override { return f_->setups_in_solves(); }
  int64_t krylov_iterations() const override { return f_->krylov_iterations(); }
  void solve(double *x) const override {
    ++c_->solves;
    c_->values_received += f_->received_per_solve();
    observed([&] { f_->solve(x); });
  }
  bool starts_from_guess() const override { return f_->starts_from_guess(); }
  void solve_from(double *x, const double *guess) const override {
    ++c_->solves;
    c_->values_received += f_->received_per_solve();
    observed([&] { f_->solve_from(x, guess); });
  }
  void solve_many(double *x, int64_t n, int64_t k) const override {
    c_->solves += k;  // one per right-hand side, as documented for ND_STAT_SOLVES
    c_->values_received += k * f_->received_per_solve();
    observed([&] { f_->solve_many(x, n, k); });
  }
  void solve_many_at(double *x, int64_t n, int64_t k, const std::vector<int64_t> &at, double *out) const override {
    c_->solves += k;
    c_->values_received += k * f_->received_at(at);
    observed([&] { f_->solve_many_at(x, n, k, at, out); });
  }
  double backward_share_at(const std::vector<int64_t> &at) const override { return f_->backward_share_at(at); }
  void solve_from_at(double *x, int64_t n, const double *guess, const std::vector<int64_t> &at,
                     double *out) const override {
    ++c_->solves;
    c_->values_received += f_->received_at(at);
    observed([&] { f_->solve_from_at(x, n, guess, at, out); });
  }
  int64_t received_per_solve() const override { return f_->received_per_solve(); }
  int64_t received_at(const std::vector<int64_t> &at) const override { return f_->received_at(at); }
  Definiteness definiteness() const override { return f_->definiteness(); }
  const char *name() const override { return f_->name(); }
  const Factorization &backend() const override { return f_->backend(); }

 private:
  // a solve's Krylov iterations, and a set-up it made anew (a factorization
  // too), counted also when it throws
  template <class Solve>
  void observed(Solve &&solve) const {
    struct Count {
      const Factorization &f;
      Counters *c;
      int64_t setups = f.setups_in_solves(), iterations = f.krylov_iterations();
      ~Count() {
        c->factorizations += f.setups_in_solves() - setups;
        c->krylov_iterations += f.krylov_iterations() - iterations;
      }
    } counted{*f_, c_};
    solve();
  }
  std::unique_ptr<Factorization> f_;
  Counters *c_;
};

}  // namespace

bool linear_solver_known(int solver) { return solver == ND_SOLVER_AUTO || find_backend(solver); }

// A Krylov backend proves nothing about the matrix's inertia (negative
// curvature met during CG is evidence, its absence is not).
bool linear_solver_iterative(int solver) { return solver == ND_SOLVER_PETSC_GAMG; }

bool linear_solver_certifies_definiteness(int solver) { return !linear_solver_iterative(solver); }

bool linear_solver_reads_coordinates(int solver) { return solver == ND_SOLVER_PETSC_GAMG; }

bool linear_solver_distributes(int solver) {
  return solver == ND_SOLVER_PETSC_MUMPS || solver == ND_SOLVER_PETSC_GAMG;
}

const char *linear_solver_unavailable(int solver) {
  if (find_backend(solver)) return nullptr;
  for (const Optional &o : kOptional)
    if (o.id == solver) return o.why;
  return nullptr;
}

std::unique_ptr<Factorization> make_factorization(int solver, const Csr &pattern, Structure s,
                                                  Counters *counters, const DofGeometry *geometry,
                                                  const Factorization *ordered_like) {
  const Backend *b = find_backend(backend_for(solver, pattern, s));
  if (!b) {
    if (const char *why = linear_solver_unavailable(solver)) fail(ND_ERR_KEY, why);
    fail(ND_ERR_KEY, "solver " + std::to_string(solver) + " is not an ND_SOLVER_* value");
  }
  std::unique_ptr<Factorization> f = b->make_geometric ? b->make_geometric(pattern, geometry)
                                     : ordered_like && b->id == ND_SOLVER_CHOLMOD
                                         ? make_cholmod_factorization_like(pattern, ordered_like)
                                         : b->make(pattern);
  if (!counters) return f;
  ++counters->symbolic_analyses;
  return std::make_unique<Counted>(std::move(f), counters);
}

void fail_not_positive_definite(Definiteness &def, const std::string &why) {
  def = Definiteness::NotPositiveDefinite;
  fail(ND_ERR_INDEFINITE, "the matrix is not positive definite (" + why + ")");
}

void require_positive_pivots(int64_t n, const double *d, Definiteness &def) {
  const int64_t bad = std::count_if(d, d + n, [](double x) { return !(x > 0); });  // NaN too
  if (bad) fail_not_positive_definite(def, "eigenvalues <= 0: " + std::to_string(bad) + " of " + std::to_string(n));
  def = Definiteness::PositiveDefinite;
}

void require_finite(const Csr &A) {
  for (size_t k = 0; k < A.val.size(); ++k)
    if (!std::isfinite(A.val[k]))
      fail(ND_ERR_NONFINITE_STATE, "the matrix has a non-finite entry (row " +
                                       std::to_string(A.row_at(std::upper_bound(A.ptr.begin(), A.ptr.end(), static_cast<int64_t>(k)) - A.ptr.begin() - 1)) +
                                       ", column " + std::to_string(A.col[k]) + ")");
}

void fail_lapack(int info, const char *what) {
  // LAPACKE_WORK_MEMORY_ERROR, LAPACKE_TRANSPOSE_MEMORY_ERROR (lapacke.h)
  if (info == -1010 || info == -1011) fail(ND_ERR_NOMEM, std::string("out of memory in the LAPACK ") + what);
  fail(ND_ERR_INTERNAL, std::string("LAPACK ") + what + ": argument " + std::to_string(-info) + " is invalid");
}

void lu_definiteness(int64_t n, const int64_t *p, const int64_t *q, const double *udiag, Definiteness &def) {
  def = Definiteness::Unknown;
  if (std::equal(p, p + n, q)) require_positive_pivots(n, udiag, def);
}

}  // namespace nd
