// CHOLMOD: sparse Cholesky (supernodal LL^T or simplicial LDL^T, CHOLMOD's
// choice), and the factor that is updated in place
// (linalg/updatable_cholesky.hpp). The pattern is analysed once (ordering,
// symbolic factorization), each matrix of it factored numerically. Our CSR
// arrays, read as CSC, describe A^T = A.
#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "linalg/ordering.hpp"
#include "linalg/suitesparse.hpp"
#include "linalg/supernodal.hpp"
#include "linalg/updatable_cholesky.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// A supernodal rank-one modification's cost per entry of L on its path, ns:
// the cost model's constant (linalg/updatable_cholesky.hpp; the simplicial
// LDL^T's, cholmod_l_updown, 0.7), fitted once, not timed at run time
constexpr double kSupernodalModifyNs = 0.25;

// A CHOLMOD status that is not OK: out of memory is ND_ERR_NOMEM, a problem
// too large for its integers ND_ERR_SIZE, anything else ND_ERR_INTERNAL
// with the status (CHOLMOD_NOT_POSDEF is handled where it can occur).
[[noreturn]] void fail_cholmod(int status, const char *what) {
  const std::string st = " (CHOLMOD status " + std::to_string(status) + ")";
  if (status == CHOLMOD_OUT_OF_MEMORY) fail(ND_ERR_NOMEM, std::string("out of memory in the CHOLMOD ") + what + st);
  if (status == CHOLMOD_TOO_LARGE) fail(ND_ERR_SIZE, std::string("the matrix is too large for the CHOLMOD ") + what + st);
  fail(ND_ERR_INTERNAL, std::string("CHOLMOD ") + what + " failed" + st);
}

// f(i, k) for each entry k of the pattern's upper triangle, column by
// column: CSR row i read as CSC column i, its rows <= i (CHOLMOD, with stype
// 1, reads no other)
template <class F>
void for_upper(const Csr &A, F &&f) {
  for (int64_t i = 0; i < A.n; ++i)
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1] && A.col[k] <= i; ++k) f(i, k);
}

// The pattern analysed: CHOLMOD's workspace, the matrix (values filled per
// factorization) and the symbolic factor.
class CholmodPattern {
 public:
  // ordering: METIS's ordering of this pattern if already made (that of
  // another CholmodPattern's; empty: AMD), else made here
  explicit CholmodPattern(const Csr &pattern, const std::vector<int64_t> *ordering = nullptr)
      : n_(pattern.n), nnz_(pattern.col.size()) {
    cholmod_l_start(&c_);
    c_.print = 0;  // the library never prints
    // One ordering: METIS's nested dissection (linalg/ordering.hpp), given
    // to CHOLMOD, else AMD. By default CHOLMOD tries several (AMD, then
    // METIS when AMD's fill is high) and silently skips one that runs out
    // of memory: the factorization, and the results in their last bits,
    // then depended on the memory available. Here running out of memory is
    // an error, and the ordering depends on the pattern alone. Nested
    // dissection also gives less fill and fewer flops than AMD, most in 3D.
    ordering_ = ordering ? *ordering : nested_dissection(pattern);
    c_.nmethods = 1;
    c_.method[0].ordering = ordering_.empty() ? CHOLMOD_AMD : CHOLMOD_GIVEN;
    c_.postorder = 1;
    // given the upper triangle alone: half the entries for CHOLMOD's
    // transposes and copies
    std::vector<int64_t> start(static_cast<size_t>(n_) + 1, 0);  // a column's first entry
    for_upper(pattern, [&](int64_t i, int64_t) { ++start[i + 1]; });
    for (int64_t i = 0; i < n_; ++i) start[i + 1] += start[i];
    A_ = cholmod_l_allocate_sparse(n_, n_, start[n_], 1, 1, 1, CHOLMOD_REAL, &c_);
    if (A_) {
      std::copy(start.begin(), start.end(), static_cast<int64_t *>(A_->p));
      auto *r = static_cast<int64_t *>(A_->i);
      int64_t e = 0;
      for_upper(pattern, [&](int64_t, int64_t k) { r[e++] = pattern.col[k]; });
      L_ = cholmod_l_analyze_p(A_, ordering_.empty() ? nullptr : ordering_.data(), nullptr, 0, &c_);
    }
    if (!L_) {  // a constructor that throws runs no destructor: release here
      const int status = c_.status;
      const char *what = A_ ? "analysis" : "matrix allocation";
      release();
      fail_cholmod(status, what);
    }
  }
  ~CholmodPattern() { release(); }
  CholmodPattern(const CholmodPattern &) = delete;
  CholmodPattern &operator=(const CholmodPattern &) = delete;

  // The numeric factorization of A into L (by default the pattern's own
  // factor); def: the verdict (NotPositiveDefinite before it throws)
  void factor(const Csr &A, Definiteness &def) { factor(A, def, L_); }
  void factor(const Csr &A, Definiteness &def, cholmod_factor *L) {
    def = Definiteness::Unknown;
    require_finite(A);
    if (A.n != n_ || A.col.size() != nnz_) fail(ND_ERR_INTERNAL, "CHOLMOD given a matrix of another pattern");
    auto *upper = static_cast<double *>(A_->x);
    int64_t e = 0;
    for_upper(A, [&](int64_t, int64_t k) { upper[e++] = A.val[k]; });
    cholmod_l_factorize(A_, L, &c_);
    if (c_.status == CHOLMOD_NOT_POSDEF)
      fail_not_positive_definite(def, "leading minor " + std::to_string(L->minor + 1) + " is not positive");
    if (c_.status < CHOLMOD_OK) fail_cholmod(c_.status, "factorization");  // > 0: a warning (a small pivot)
    if (!L->is_ll) {  // simplicial LDL^T factors indefinite matrices too: D tells
      const auto *p = static_cast<const int64_t *>(L->p);
      const auto *x = static_cast<const double *>(L->x);
      d_.resize(static_cast<size_t>(n_));
      for (int64_t j = 0; j < n_; ++j) d_[j] = x[p[j]];  // D(j) comes first in column j
      require_positive_pivots(n_, d_.data(), def);
    }
    def = Definiteness::PositiveDefinite;
  }
  void solve(double *x) const { solve(L_, x); }
  void solve(cholmod_factor *L, double *x) const {
    cholmod_dense b;
    std::memset(&b, 0, sizeof b);
    b.nrow = static_cast<size_t>(n_);
    b.ncol = 1;
    b.nzmax = b.d = static_cast<size_t>(n_);
    b.x = x;
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    // (cholmod_l_solve's arithmetic, its result and workspaces kept from
    // solve to solve rather than allocated and freed at each)
    if (!cholmod_l_solve2(CHOLMOD_A, L, &b, nullptr, &X_, nullptr, &Y_, &E_, &c_)) fail_cholmod(c_.status, "solve");
    if (n_ > 0) std::memcpy(x, X_->x, sizeof(double) * static_cast<size_t>(n_));
  }

  int64_t n_;
  size_t nnz_;                       // the pattern's entries
  std::vector<int64_t> ordering_;    // METIS's (empty: AMD's, CHOLMOD's own)
  mutable cholmod_common c_;
  cholmod_sparse *A_ = nullptr;
  cholmod_factor *L_ = nullptr;
  std::vector<double> d_;

 private:
  mutable cholmod_dense *X_ = nullptr, *Y_ = nullptr, *E_ = nullptr;  // solve's
  void release() {
    for (cholmod_dense **w : {&X_, &Y_, &E_}) cholmod_l_free_dense(w, &c_);
    cholmod_l_free_factor(&L_, &c_);
    cholmod_l_free_sparse(&A_, &c_);
    cholmod_l_finish(&c_);
  }
};

// CHOLMOD's supernodal factor, as the sweeps and updates read it
SupernodalFactor view(const cholmod_factor *F) {
  SupernodalFactor L;
  L.n = static_cast<int64_t>(F->n), L.count = static_cast<int64_t>(F->nsuper);
  L.super = static_cast<const int64_t *>(F->super), L.pi = static_cast<const int64_t *>(F->pi);
  L.px = static_cast<const int64_t *>(F->px), L.s_rows = static_cast<const int64_t *>(F->s);
  L.perm = static_cast<const int64_t *>(F->Perm);
  L.x = static_cast<double *>(F->x);
  return L;
}

// the reciprocals of a numeric supernodal factor's diagonal (the sweeps' small blocks)
void diagonal_reciprocals(const SupernodalFactor &L, std::vector<double> &inv) {
  inv.resize(static_cast<size_t>(L.n));
  for (int64_t k = 0; k < L.count; ++k) {
    const SupernodalFactor::Block b = L[k];
    for (int j = 0; j < b.cols; ++j) inv[b.first + j] = 1.0 / b.L[static_cast<int64_t>(j) * b.ld + j];
  }
}

// x <- P^T L^{-T} L^{-1} P x for k columns of n, over a numeric supernodal
// factor: the solves of A's factor and of the updated one
void supernodal_solve(const cholmod_factor *F, const SupernodalTree &tree, const double *inv, double *x,
                      int64_t k, SupernodalWork &w) {
  const SupernodalFactor L = view(F);
  w.fit(L, F->maxesize);
  std::vector<double> &y = w.y, &e = w.e;
  std::vector<char> &reached = w.reached;
  for (int64_t j = 0; j < k; ++j) {
    double *xj = x + j * L.n;
    supernodal_forward(L, tree, inv, xj, y, reached, e);
    supernodal_backward(L, inv, y, e, nullptr);
    for (int64_t c = 0; c < L.n; ++c) xj[L.perm[c]] = y[c];  // x = P^T y
  }
}

class Cholmod : public Factorization {
 public:
  explicit Cholmod(const Csr &pattern, const std::vector<int64_t> *ordering = nullptr) : f_(pattern, ordering) {
    if (f_.L_->is_super) tree_ = std::make_unique<SupernodalTree>(view(f_.L_));
  }
  void factor(const Csr &A, Structure s) override;
  // A supernodal factor is solved here (forward and backward below), not by
  // cholmod_l_solve: its small diagonal blocks (kCholmodOwnTriangle) by our
  // own loops, where OpenBLAS's dtrsv costs more in its call (a buffer taken
  // under a mutex) than in its arithmetic (docs/performance.md, "Own
  // supernodal solve"). The solves of few nonzeros or few rows below share
  // these loops, so that they make solve()'s bits.
  void solve(double *x) const override {
    if (sparse_solves(f_.n_)) solve_many(x, f_.n_, 1);
    else f_.solve(x);
  }
  // Each column as solve() makes it, bit for bit (tests/unit_linalg.cpp),
  // its forward solve only over the supernodes its nonzeros reach: the
  // columns of the contact points (fast/contact_columns.hpp) have a few
  // nonzeros each, and reach a small part of L's entries.
  void solve_many(double *x, int64_t n, int64_t k) const override;
  // Each column's values at the rows `at` as solve() makes them, bit for
  // bit, its backward solve only over the supernodes of those rows and their
  // ancestors (which alone they read): for the contact points' DOFs a small
  // part of L on large 2D meshes, most of it in 3D (backward_share_at).
  void solve_many_at(double *x, int64_t n, int64_t k, const std::vector<int64_t> &at, double *out) const override;
  double backward_share_at(const std::vector<int64_t> &at) const override;
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "cholmod"; }
  // the numeric factor (null before the first factorization)
  const cholmod_factor *numeric() const { return def_ == Definiteness::PositiveDefinite ? f_.L_ : nullptr; }
  const std::vector<int64_t> &ordering() const { return f_.ordering_; }

 private:
  // the solves over part of the supernodes apply: a supernodal LL^T with its
  // permutation, numerically factored, within the BLAS's int arguments
  bool sparse_solves(int64_t n) const {
    const cholmod_factor *L = f_.L_;
    return tree_ && L->is_super && L->is_ll && L->Perm && L->ordering != CHOLMOD_NATURAL &&
           def_ == Definiteness::PositiveDefinite && L->maxesize <= static_cast<size_t>(INT32_MAX) &&
           n <= INT32_MAX && n == f_.n_;
  }
  // the supernodes the backward solve needs for the unknowns `at`: theirs
  // and their ancestors' (a supernode reads the rows below its diagonal
  // block, which are its ancestors'); and each unknown's row in L
  std::vector<char> needed_for(const std::vector<int64_t> &at, std::vector<int64_t> &kept_row) const;
  void forward(const double *x, std::vector<double> &y, std::vector<char> &reached, std::vector<double> &e) const {
    supernodal_forward(view(f_.L_), *tree_, inv_.data(), x, y, reached, e);
  }
  void backward(std::vector<double> &y, std::vector<double> &e, const std::vector<char> *needed) const {
    supernodal_backward(view(f_.L_), inv_.data(), y, e, needed);
  }
  CholmodPattern f_;
  Definiteness def_ = Definiteness::Unknown;
  std::unique_ptr<SupernodalTree> tree_;  // (supernodal factors)
  std::vector<double> inv_;               // 1 / L(j, j) (sparse_solves: made with the factor)
  mutable SupernodalWork work_;           // solve_many's
};

void Cholmod::factor(const Csr &A, Structure s) {
  def_ = Definiteness::Unknown;
  if (s != Structure::SymmetricPositiveDefinite) fail(ND_ERR_INTERNAL, "CHOLMOD given a non-symmetric matrix");
  inv_.clear();
  f_.factor(A, def_);
  if (!sparse_solves(f_.n_)) return;
  diagonal_reciprocals(view(f_.L_), inv_);
}

void Cholmod::solve_many(double *x, int64_t n, int64_t k) const {
  if (!sparse_solves(n)) return Factorization::solve_many(x, n, k);
  supernodal_solve(f_.L_, *tree_, inv_.data(), x, k, work_);
}

std::vector<char> Cholmod::needed_for(const std::vector<int64_t> &at, std::vector<int64_t> &kept_row) const {
  const int64_t n = f_.n_;
  const auto *perm = static_cast<const int64_t *>(f_.L_->Perm);
  std::vector<int64_t> row_of(static_cast<size_t>(n));
  for (int64_t c = 0; c < n; ++c) row_of[perm[c]] = c;
  std::vector<char> needed(f_.L_->nsuper, 0);
  kept_row.resize(at.size());
  for (size_t i = 0; i < at.size(); ++i) {
    if (at[i] < 0 || at[i] >= n) fail(ND_ERR_INTERNAL, "solve_many_at: an unknown out of range");
    kept_row[i] = row_of[at[i]];
    tree_->mark_path(kept_row[i], needed);
  }
  return needed;
}

double Cholmod::backward_share_at(const std::vector<int64_t> &at) const {
  if (!sparse_solves(f_.n_)) return 1.0;
  const auto *px = static_cast<const int64_t *>(f_.L_->px);
  std::vector<int64_t> kept_row;
  const std::vector<char> needed = needed_for(at, kept_row);
  double part = 0, all = 0;  // L's entries, those of the needed supernodes
  for (size_t s = 0; s < needed.size(); ++s) {
    const double entries = static_cast<double>(px[s + 1] - px[s]);
    all += entries;
    if (needed[s]) part += entries;
  }
  return all > 0 ? part / all : 1.0;
}

void Cholmod::solve_many_at(double *x, int64_t n, int64_t k, const std::vector<int64_t> &at, double *out) const {
  if (!sparse_solves(n)) return Factorization::solve_many_at(x, n, k, at, out);
  const cholmod_factor *L = f_.L_;
  const size_t m = at.size();
  std::vector<int64_t> kept_row;
  const std::vector<char> needed = needed_for(at, kept_row);
  std::vector<double> y(static_cast<size_t>(n)), e(std::max<size_t>(L->maxesize, 1));
  std::vector<char> reached(L->nsuper);
  for (int64_t j = 0; j < k; ++j) {
    forward(x + j * n, y, reached, e);
    backward(y, e, &needed);
    for (size_t i = 0; i < m; ++i) out[static_cast<size_t>(j) * m + i] = y[kept_row[i]];
  }
}

// the ordering of A's CHOLMOD factor, if that is what A_factor is (else null)
const std::vector<int64_t> *ordering_of(const Factorization *A_factor) {
  const auto *c = A_factor ? dynamic_cast<const Cholmod *>(&A_factor->backend()) : nullptr;
  return c ? &c->ordering() : nullptr;
}

}  // namespace

std::unique_ptr<Factorization> make_cholmod_factorization(const Csr &p) { return std::make_unique<Cholmod>(p); }

std::unique_ptr<Factorization> make_cholmod_factorization_like(const Csr &p, const Factorization *ordered_like) {
  const std::vector<int64_t> *ordering = ordering_of(ordered_like);
  return std::make_unique<Cholmod>(p, ordering && static_cast<int64_t>(ordering->size()) == p.n ? ordering : nullptr);
}

double cholmod_factor_nonzeros(const Csr &pattern) {
  CholmodPattern f(pattern);
  return f.c_.lnz;
}

bool cholmod_is_supernodal(const Csr &pattern) { return cholmod_widest_supernode(pattern) > 0; }

int64_t cholmod_widest_supernode(const Csr &pattern) {
  const CholmodPattern f(pattern);
  const cholmod_factor *L = f.L_;
  if (!L->is_super) return 0;
  const auto *super = static_cast<const int64_t *>(L->super);
  int64_t widest = 0;
  for (size_t s = 0; s < L->nsuper; ++s) widest = std::max(widest, super[s + 1] - super[s]);
  return widest;
}

// ---- the updatable factor ------------------------------------------------------

// Where CHOLMOD's analysis is supernodal (3D meshes, the larger 2D ones) the
// factor stays supernodal LL^T: copied from A's or factored, modified in place
// by our rank-one updates and solved by our sweeps (linalg/supernodal.hpp).
// Elsewhere it is a simplicial LDL^T (T factored, or A's factor copied, and
// converted), modified by cholmod_l_updown and solved by cholmod_l_solve.
struct UpdatableCholesky::Impl {
  Impl(const Csr &pattern, const std::vector<int64_t> *ordering)
      : f(pattern, ordering), flops(f.c_.fl), lnz(f.c_.lnz) {
    const auto *perm = static_cast<const int64_t *>(f.L_->Perm);
    row_of.resize(static_cast<size_t>(f.n_));
    for (int64_t i = 0; i < f.n_; ++i) row_of[perm[i]] = i;  // CHOLMOD wants C(Perm, :)
    const cholmod_factor *L = f.L_;
    super = L->is_super && L->Perm && L->maxesize <= static_cast<size_t>(INT32_MAX) && f.n_ <= INT32_MAX;
    if (super) tree = std::make_unique<SupernodalTree>(view(L));
  }
  // path[j]: the nonzeros of L in the columns from j up to the etree's root
  // (a simplicial column's parent is its first row below the diagonal)
  void find_paths() {
    if (super) {
      path = supernodal_paths(view(W));
      return;
    }
    const auto *p = static_cast<const int64_t *>(W->p), *i = static_cast<const int64_t *>(W->i);
    const auto *nz = static_cast<const int64_t *>(W->nz);
    path.assign(static_cast<size_t>(f.n_), 0.0);
    for (int64_t j = f.n_ - 1; j >= 0; --j)  // a parent comes after its child
      path[j] = static_cast<double>(nz[j]) + (nz[j] > 1 ? path[i[p[j] + 1]] : 0.0);
  }
  // W made numeric (factored, or copied from A's factor): as the updates want it
  void made() {
    if (super) {
      diagonal_reciprocals(view(W), inv);
    } else if (!cholmod_l_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, W, &f.c_)) {
      const int status = f.c_.status;
      cholmod_l_free_factor(&W, &f.c_);
      fail_cholmod(status, "conversion to LDL^T");
    }
    if (path.empty()) find_paths();  // the structure is the analysis': found once
  }
  ~Impl() { cholmod_l_free_factor(&W, &f.c_); }
  CholmodPattern f;
  bool super = false;                              // the supernodal form (else simplicial LDL^T)
  cholmod_factor *W = nullptr;                     // the numeric factor (null: none valid)
  std::unique_ptr<SupernodalTree> tree;            // (super)
  std::vector<double> inv;                         // (super) 1 / L(j, j)
  mutable SupernodalWork work;                     // (super) the solves'
  SupernodalModifier modifier;                     // (super)
  std::vector<int64_t> rows;                       // (super) scratch: the columns' permuted rows
  std::vector<int64_t> row_of;                     // a DOF's row in the permuted order
  std::vector<std::pair<int64_t, double>> column;  // scratch: one column, sorted
  double flops, lnz;                               // of the factorization, from the analysis
  std::vector<double> path;                        // see find_paths (empty: not yet)
  int64_t simplicial_entries = 0;                  // modified_entries of cholmod_l_updown's calls
};


UpdatableCholesky::UpdatableCholesky(const Csr &pattern, Counters *counters, const Factorization *ordered_like)
    : impl_(std::make_unique<Impl>(pattern, ordering_of(ordered_like))), counters_(counters) {
  count(counters_, &Counters::symbolic_analyses);
}
UpdatableCholesky::~UpdatableCholesky() = default;

void UpdatableCholesky::factor(const Csr &T) {
  count(counters_, &Counters::factorizations);
  Impl &m = *impl_;
  cholmod_l_free_factor(&m.W, &m.f.c_);
  // the analysis (f.L_ stays symbolic) copied and factored there: one
  // numeric factor is held, not a second copy
  m.W = cholmod_l_copy_factor(m.f.L_, &m.f.c_);
  if (!m.W) fail_cholmod(m.f.c_.status, "factor copy");
  try {
    Definiteness def;
    m.f.factor(T, def, m.W);
  } catch (...) {
    cholmod_l_free_factor(&m.W, &m.f.c_);
    throw;
  }
  m.made();
}

bool UpdatableCholesky::start_from(const Factorization &A_factor) {
  Impl &m = *impl_;
  const auto *c = dynamic_cast<const Cholmod *>(&A_factor.backend());
  const cholmod_factor *L = c ? c->numeric() : nullptr;
  if (!L || static_cast<int64_t>(L->n) != m.f.n_ || static_cast<bool>(L->is_super) != m.super) return false;
  const auto *perm = static_cast<const int64_t *>(L->Perm), *ours = static_cast<const int64_t *>(m.f.L_->Perm);
  if (!std::equal(perm, perm + m.f.n_, ours)) return false;  // another analysis: its rows are not ours
  cholmod_factor *W = cholmod_l_copy_factor(const_cast<cholmod_factor *>(L), &m.f.c_);
  if (!W) fail_cholmod(m.f.c_.status, "factor copy");
  cholmod_l_free_factor(&m.W, &m.f.c_);
  m.W = W;
  m.made();
  return true;
}

bool UpdatableCholesky::has_costs() const { return !impl_->path.empty(); }

double UpdatableCholesky::factor_cost() const { return std::max(50.0 * impl_->lnz, impl_->flops / 40.0); }

double UpdatableCholesky::solve_cost() const { return 0.6 * impl_->lnz; }

double UpdatableCholesky::path_entries(const SparseColumns &C) const {
  const Impl &m = *impl_;
  if (m.path.empty()) fail(ND_ERR_INTERNAL, "an update's cost asked before the first factorization");
  double entries = 0;
  for (int64_t j = 0; j < C.count(); ++j) {  // a column's path starts at its first row
    int64_t first = m.f.n_;
    for (int64_t e = C.ptr[j]; e < C.ptr[j + 1]; ++e) first = std::min(first, m.row_of[C.idx[e]]);
    if (first < m.f.n_) entries += m.path[first];
  }
  return entries;
}

double UpdatableCholesky::modify_cost(const SparseColumns &C) const {
  return (impl_->super ? kSupernodalModifyNs : 0.7) * path_entries(C);
}

int64_t UpdatableCholesky::modified_entries() const {
  return impl_->modifier.rotated_entries() + impl_->simplicial_entries;
}

bool UpdatableCholesky::modify(bool add, const SparseColumns &C) {
  Impl &m = *impl_;
  CholmodPattern &f = m.f;
  const int64_t k = C.count();
  if (!m.W) return false;
  if (k == 0) return true;
  if (m.super) {
    std::vector<int64_t> &rows = m.rows;  // C's rows, permuted
    rows.resize(C.idx.size());
    for (size_t e = 0; e < rows.size(); ++e) rows[e] = m.row_of[C.idx[e]];
    if (!m.modifier.modify(view(m.W), *m.tree, m.inv.data(), add, C.ptr.data(), rows.data(), C.val.data(), k)) {
      cholmod_l_free_factor(&m.W, &f.c_);  // (possibly) half modified: no longer a factor of anything
      return false;
    }
    return true;
  }
  cholmod_sparse *S = cholmod_l_allocate_sparse(f.n_, k, C.idx.size(), 1, 1, 0, CHOLMOD_REAL, &f.c_);
  if (!S) fail_cholmod(f.c_.status, "update allocation");
  auto *Sp = static_cast<int64_t *>(S->p), *Si = static_cast<int64_t *>(S->i);
  auto *Sx = static_cast<double *>(S->x);
  for (int64_t j = 0; j < k; ++j) {  // permuted rows, sorted as CHOLMOD requires
    auto &col = m.column;
    col.clear();
    for (int64_t e = C.ptr[j]; e < C.ptr[j + 1]; ++e) col.emplace_back(m.row_of[C.idx[e]], C.val[e]);
    std::sort(col.begin(), col.end());
    Sp[j] = C.ptr[j];
    for (size_t e = 0; e < col.size(); ++e) Si[Sp[j] + e] = col[e].first, Sx[Sp[j] + e] = col[e].second;
  }
  Sp[k] = C.ptr[k];
  cholmod_factor *W = m.W;
  m.simplicial_entries += static_cast<int64_t>(path_entries(C));  // (paths known: m.W is a factor)
  const int ok = cholmod_l_updown(add ? 1 : 0, S, W, &f.c_);
  const int status = f.c_.status;
  cholmod_l_free_sparse(&S, &f.c_);
  if (!ok) cholmod_l_free_factor(&m.W, &f.c_);  // half modified: no longer a factor of anything
  if (!ok && status == CHOLMOD_OUT_OF_MEMORY) fail_cholmod(status, "update");
  if (!ok || status < CHOLMOD_OK) return false;
  const auto *p = static_cast<const int64_t *>(W->p);
  const auto *x = static_cast<const double *>(W->x);
  for (int64_t j = 0; j < f.n_; ++j)  // D(j) comes first in column j
    if (!(x[p[j]] > 0) || !std::isfinite(x[p[j]])) return false;
  return true;
}

void UpdatableCholesky::solve(double *x) const {
  count(counters_, &Counters::solves);
  const Impl &m = *impl_;
  if (!m.W) fail(ND_ERR_INTERNAL, "a solve with no valid updated factor");
  if (!m.super) return m.f.solve(m.W, x);
  supernodal_solve(m.W, *m.tree, m.inv.data(), x, 1, m.work);
}

}  // namespace nd
