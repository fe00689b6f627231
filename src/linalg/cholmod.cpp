// CHOLMOD: sparse Cholesky (supernodal LL^T or simplicial LDL^T, CHOLMOD's
// choice), and the simplicial LDL^T that is updated in place
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
#include "linalg/updatable_cholesky.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

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
    // then depended on the memory available. Now running out of memory is
    // an error, and the ordering depends on the pattern alone. Against AMD,
    // measured on the bench meshes: nnz(L) 7-26% and the factorization's
    // flops 25-51% lower (disk P2 h=1 and h=0.5, ball P1 h=4 and h=2, ball
    // P2 h=4; the largest gains in 3D).
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
    cholmod_dense *r = cholmod_l_solve(CHOLMOD_A, L, &b, &c_);
    if (!r) fail_cholmod(c_.status, "solve");
    std::memcpy(x, r->x, sizeof(double) * static_cast<size_t>(n_));
    cholmod_l_free_dense(&r, &c_);
  }

  int64_t n_;
  size_t nnz_;                       // the pattern's entries
  std::vector<int64_t> ordering_;    // METIS's (empty: AMD's, CHOLMOD's own)
  mutable cholmod_common c_;
  cholmod_sparse *A_ = nullptr;
  cholmod_factor *L_ = nullptr;
  std::vector<double> d_;

 private:
  void release() {
    cholmod_l_free_factor(&L_, &c_);
    cholmod_l_free_sparse(&A_, &c_);
    cholmod_l_finish(&c_);
  }
};

// A supernodal factor's elimination tree: which supernodes a right-hand
// side with few nonzeros reaches in the forward solve (those of its
// nonzeros' columns and their ancestors; the others stay zero), and which
// the backward solve needs for a few rows (theirs and their ancestors).
struct SupernodalTree {
  explicit SupernodalTree(const cholmod_factor *L) {
    const auto *super = static_cast<const int64_t *>(L->super), *pi = static_cast<const int64_t *>(L->pi);
    const auto *rows = static_cast<const int64_t *>(L->s);
    const int64_t ns = static_cast<int64_t>(L->nsuper);
    of_column.resize(L->n);
    parent.assign(static_cast<size_t>(ns), -1);
    for (int64_t s = 0; s < ns; ++s)
      for (int64_t j = super[s]; j < super[s + 1]; ++j) of_column[j] = s;
    for (int64_t s = 0; s < ns; ++s) {  // the parent holds the first row below the diagonal block
      const int64_t cols = super[s + 1] - super[s];
      if (pi[s + 1] - pi[s] > cols) parent[s] = of_column[rows[pi[s] + cols]];
    }
  }
  // marks column c's supernode and its ancestors (stops at one already marked)
  void mark_path(int64_t c, std::vector<char> &marked) const {
    for (int64_t s = of_column[c]; s >= 0 && !marked[s]; s = parent[s]) marked[s] = 1;
  }
  std::vector<int64_t> of_column, parent;  // a column's supernode; a supernode's parent (-1: a root)
};

class Cholmod : public Factorization {
 public:
  explicit Cholmod(const Csr &pattern, const std::vector<int64_t> *ordering = nullptr) : f_(pattern, ordering) {
    if (f_.L_->is_super) tree_ = std::make_unique<SupernodalTree>(f_.L_);
  }
  void factor(const Csr &A, Structure s) override;
  // A supernodal factor is solved here (forward and backward below), not by
  // cholmod_l_solve: its small diagonal blocks (kCholmodOwnTriangle) by our
  // own loops, where OpenBLAS's dtrsv costs more in its call (a buffer taken
  // under a mutex) than in its arithmetic. Against cholmod_l_solve, one
  // thread, alternating in one process: 0.77-0.87 of its time on disk P2
  // h = 4 ... 1 and P1 h = 1, 0.5; 0.90-0.95 on disk P2 h = 0.5; 0.92-1.0
  // on the balls. The solves of few nonzeros or few rows below share these
  // loops, so that they make solve()'s bits.
  void solve(double *x) const override {
    if (sparse_solves(f_.n_)) solve_many(x, f_.n_, 1);
    else f_.solve(x);
  }
  // Each column as solve() makes it, bit for bit (tests/unit_linalg.cpp),
  // its forward solve only over the supernodes its nonzeros reach: the
  // columns of the contact points (solve/contact_columns.hpp) have a few
  // nonzeros each, and reach 10 % (2D) to 35 % (3D) of L's entries.
  void solve_many(double *x, int64_t n, int64_t k) const override;
  // Each column's values at the rows `at` as solve() makes them, bit for
  // bit, its backward solve only over the supernodes of those rows and their
  // ancestors (which alone they read): the contact points' DOFs need 28-43 %
  // of L's entries on the disks (82-91 % on the balls; backward_share_at).
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
  // y = L^{-1} P x over the supernodes x's nonzeros reach (the others stay
  // zero); reached and e are workspaces (ns and maxesize long)
  void forward(const double *x, std::vector<double> &y, std::vector<char> &reached, std::vector<double> &e) const;
  // y = L^{-T} y over the supernodes `needed` marks (null: all), root
  // first; e is a workspace (maxesize long)
  void backward(std::vector<double> &y, std::vector<double> &e, const std::vector<char> *needed) const;
  CholmodPattern f_;
  Definiteness def_ = Definiteness::Unknown;
  std::unique_ptr<SupernodalTree> tree_;  // (supernodal factors)
  std::vector<double> inv_;               // 1 / L(j, j) (sparse_solves: made with the factor)
};

// The Fortran BLAS, as CHOLMOD's own solve calls it (its large diagonal
// blocks and the rows below them)
extern "C" {
void dtrsv_(const char *uplo, const char *trans, const char *diag, const int *n, const double *a, const int *lda,
            double *x, const int *incx);
void dgemv_(const char *trans, const int *m, const int *n, const double *alpha, const double *a, const int *lda,
            const double *x, const int *incx, const double *beta, double *y, const int *incy);
}

// The diagonal blocks of at most kCholmodOwnTriangle columns are solved by
// these two loops, wider ones by dtrsv (whose blocked kernels win there: our
// loops on every block made the balls' solves 1.3-1.4x slower). 16, 32 and
// 64 measured alike on the disks; 32 was the best on the balls.
// Both multiply by the diagonal's reciprocals (inv) rather than divide (a
// division's latency sits on the chain from column to column), and L, inv
// and y do not overlap (__restrict: the updates vectorize). One solve, 201
// timed: 0.92 of the time before on disk P1 h = 1, 0.94-0.97 on disk P2
// h = 1 and ball P1 h = 4; unchanged where wide blocks (the BLAS) dominate.
// y = L^{-1} y, L lower triangular, column-major with leading dimension ld
void lower_solve(int cols, const double *__restrict L, int ld, const double *__restrict inv, double *__restrict y) {
  for (int j = 0; j < cols; ++j) {
    const double *__restrict Lj = L + static_cast<int64_t>(j) * ld;
    const double yj = y[j] * inv[j];
    y[j] = yj;
    for (int i = j + 1; i < cols; ++i) y[i] -= Lj[i] * yj;
  }
}
// y = L^{-T} y, L as above: each dot product in four sums (i mod 4), not
// one chain of dependent adds
void lower_transpose_solve(int cols, const double *__restrict L, int ld, const double *__restrict inv,
                           double *__restrict y) {
  for (int j = cols - 1; j >= 0; --j) {
    const double *__restrict Lj = L + static_cast<int64_t>(j) * ld;
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    int i = j + 1;
    for (; i + 3 < cols; i += 4) {
      s0 += Lj[i] * y[i];
      s1 += Lj[i + 1] * y[i + 1];
      s2 += Lj[i + 2] * y[i + 2];
      s3 += Lj[i + 3] * y[i + 3];
    }
    for (; i < cols; ++i) s0 += Lj[i] * y[i];
    y[j] = (y[j] - ((s0 + s1) + (s2 + s3))) * inv[j];
  }
}

// A numeric supernodal factor's supernodes, its arrays read once per sweep
// (not from the factor again behind each BLAS call). Block s: its
// diagonal block (cols columns from `first`, column-major with leading
// dimension ld) and the block below it (`below` rows, at the unknowns
// `rows`), both in L.
struct Supernodes {
  explicit Supernodes(const cholmod_factor *F)
      : count(static_cast<int64_t>(F->nsuper)), super(static_cast<const int64_t *>(F->super)),
        pi(static_cast<const int64_t *>(F->pi)), px(static_cast<const int64_t *>(F->px)),
        s_rows(static_cast<const int64_t *>(F->s)), x(static_cast<const double *>(F->x)) {}
  struct Block {
    int64_t first;
    int cols, ld, below;
    const int64_t *rows;
    const double *L;
  };
  Block operator[](int64_t s) const {
    const int cols = static_cast<int>(super[s + 1] - super[s]), ld = static_cast<int>(pi[s + 1] - pi[s]);
    return Block{super[s], cols, ld, ld - cols, s_rows + pi[s] + cols, x + px[s]};
  }
  int64_t count;
  const int64_t *super, *pi, *px, *s_rows;
  const double *x;
};
void Cholmod::factor(const Csr &A, Structure s) {
  def_ = Definiteness::Unknown;
  if (s != Structure::SymmetricPositiveDefinite) fail(ND_ERR_INTERNAL, "CHOLMOD given a non-symmetric matrix");
  inv_.clear();
  f_.factor(A, def_);
  if (!sparse_solves(f_.n_)) return;
  const Supernodes L(f_.L_);  // the reciprocals of L's diagonal, for the sweeps' small blocks
  inv_.resize(static_cast<size_t>(f_.n_));
  for (int64_t k = 0; k < L.count; ++k) {
    const Supernodes::Block b = L[k];
    for (int j = 0; j < b.cols; ++j) inv_[b.first + j] = 1.0 / b.L[static_cast<int64_t>(j) * b.ld + j];
  }
}

const int kOne = 1;
const double kMinusOne = -1.0, kPlusOne = 1.0;

void Cholmod::forward(const double *x, std::vector<double> &y, std::vector<char> &reached,
                      std::vector<double> &e) const {
  const Supernodes L(f_.L_);
  const auto *perm = static_cast<const int64_t *>(f_.L_->Perm);
  std::fill(reached.begin(), reached.end(), 0);
  for (int64_t c = 0; c < f_.n_; ++c) {  // y = P x, and the supernodes its nonzeros reach
    y[c] = x[perm[c]];
    if (y[c] != 0) tree_->mark_path(c, reached);
  }
  for (int64_t s = 0; s < L.count; ++s) {  // y = L^{-1} y over those (a parent comes after its children)
    if (!reached[s]) continue;
    const Supernodes::Block b = L[s];
    double *ys = y.data() + b.first;
    for (int i = 0; i < b.below; ++i) e[i] = y[b.rows[i]];
    if (b.cols <= kCholmodOwnTriangle) lower_solve(b.cols, b.L, b.ld, inv_.data() + b.first, ys);
    else dtrsv_("L", "N", "N", &b.cols, b.L, &b.ld, ys, &kOne);
    if (b.below > 0) {
      dgemv_("N", &b.below, &b.cols, &kMinusOne, b.L + b.cols, &b.ld, ys, &kOne, &kPlusOne, e.data(), &kOne);
      for (int i = 0; i < b.below; ++i) y[b.rows[i]] = e[i];
    }
  }
}

void Cholmod::backward(std::vector<double> &y, std::vector<double> &e, const std::vector<char> *needed) const {
  const Supernodes L(f_.L_);
  for (int64_t s = L.count - 1; s >= 0; --s) {
    if (needed && !(*needed)[s]) continue;
    const Supernodes::Block b = L[s];
    double *ys = y.data() + b.first;
    for (int i = 0; i < b.below; ++i) e[i] = y[b.rows[i]];
    if (b.below > 0)
      dgemv_("C", &b.below, &b.cols, &kMinusOne, b.L + b.cols, &b.ld, e.data(), &kOne, &kPlusOne, ys, &kOne);
    if (b.cols <= kCholmodOwnTriangle) lower_transpose_solve(b.cols, b.L, b.ld, inv_.data() + b.first, ys);
    else dtrsv_("L", "C", "N", &b.cols, b.L, &b.ld, ys, &kOne);
  }
}

void Cholmod::solve_many(double *x, int64_t n, int64_t k) const {
  if (!sparse_solves(n)) return Factorization::solve_many(x, n, k);
  const cholmod_factor *L = f_.L_;
  const auto *perm = static_cast<const int64_t *>(L->Perm);
  std::vector<double> y(static_cast<size_t>(n)), e(std::max<size_t>(L->maxesize, 1));
  std::vector<char> reached(L->nsuper);
  for (int64_t j = 0; j < k; ++j) {
    double *xj = x + j * n;
    forward(xj, y, reached, e);
    backward(y, e, nullptr);
    for (int64_t c = 0; c < n; ++c) xj[perm[c]] = y[c];  // x = P^T y
  }
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

// T is factored as CHOLMOD chooses (supernodal, with the BLAS, on 3D
// meshes: a simplicial factorization of ball_h2 took 15x longer), then
// converted to the simplicial LDL^T that the updates modify and the solves use.
struct UpdatableCholesky::Impl {
  Impl(const Csr &pattern, const std::vector<int64_t> *ordering)
      : f(pattern, ordering), flops(f.c_.fl), lnz(f.c_.lnz) {
    const auto *perm = static_cast<const int64_t *>(f.L_->Perm);
    row_of.resize(static_cast<size_t>(f.n_));
    for (int64_t i = 0; i < f.n_; ++i) row_of[perm[i]] = i;  // CHOLMOD wants C(Perm, :)
  }
  // path[j]: the nonzeros of L in the columns from j up to the etree's root
  // (a simplicial column's parent is its first row below the diagonal)
  void find_paths() {
    const auto *p = static_cast<const int64_t *>(W->p), *i = static_cast<const int64_t *>(W->i);
    const auto *nz = static_cast<const int64_t *>(W->nz);
    path.assign(static_cast<size_t>(f.n_), 0.0);
    for (int64_t j = f.n_ - 1; j >= 0; --j)  // a parent comes after its child
      path[j] = static_cast<double>(nz[j]) + (nz[j] > 1 ? path[i[p[j] + 1]] : 0.0);
  }
  ~Impl() { cholmod_l_free_factor(&W, &f.c_); }
  CholmodPattern f;
  cholmod_factor *W = nullptr;                     // the simplicial LDL^T (null: none valid)
  std::vector<int64_t> row_of;                     // a DOF's row in the permuted order
  std::vector<std::pair<int64_t, double>> column;  // scratch: one column, sorted
  double flops, lnz;                               // of the factorization, from the analysis
  std::vector<double> path;                        // see find_paths (empty: not yet)
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
  // the analysis (f.L_ stays symbolic) copied and factored there, then
  // converted in place: one numeric factor is held, not a second copy
  m.W = cholmod_l_copy_factor(m.f.L_, &m.f.c_);
  if (!m.W) fail_cholmod(m.f.c_.status, "factor copy");
  try {
    Definiteness def;
    m.f.factor(T, def, m.W);
  } catch (...) {
    cholmod_l_free_factor(&m.W, &m.f.c_);
    throw;
  }
  if (!cholmod_l_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, m.W, &m.f.c_)) {
    const int status = m.f.c_.status;
    cholmod_l_free_factor(&m.W, &m.f.c_);
    fail_cholmod(status, "conversion to LDL^T");
  }
  if (m.path.empty()) m.find_paths();  // the structure is the analysis': found once
}

bool UpdatableCholesky::start_from(const Factorization &A_factor) {
  Impl &m = *impl_;
  const auto *c = dynamic_cast<const Cholmod *>(&A_factor.backend());
  const cholmod_factor *L = c ? c->numeric() : nullptr;
  if (!L || static_cast<int64_t>(L->n) != m.f.n_) return false;
  const auto *perm = static_cast<const int64_t *>(L->Perm), *ours = static_cast<const int64_t *>(m.f.L_->Perm);
  if (!std::equal(perm, perm + m.f.n_, ours)) return false;  // another analysis: its rows are not ours
  cholmod_factor *W = cholmod_l_copy_factor(const_cast<cholmod_factor *>(L), &m.f.c_);
  if (!W) fail_cholmod(m.f.c_.status, "factor copy");
  if (!cholmod_l_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, W, &m.f.c_)) {
    const int status = m.f.c_.status;
    cholmod_l_free_factor(&W, &m.f.c_);
    fail_cholmod(status, "conversion to LDL^T");
  }
  cholmod_l_free_factor(&m.W, &m.f.c_);
  m.W = W;
  if (m.path.empty()) m.find_paths();
  return true;
}

bool UpdatableCholesky::has_costs() const { return !impl_->path.empty(); }

double UpdatableCholesky::factor_cost() const { return std::max(50.0 * impl_->lnz, impl_->flops / 40.0); }

double UpdatableCholesky::modify_cost(const SparseColumns &C) const {
  const Impl &m = *impl_;
  if (m.path.empty()) fail(ND_ERR_INTERNAL, "an update's cost asked before the first factorization");
  double entries = 0;
  for (int64_t j = 0; j < C.count(); ++j) {  // a column's path starts at its first row
    int64_t first = m.f.n_;
    for (int64_t e = C.ptr[j]; e < C.ptr[j + 1]; ++e) first = std::min(first, m.row_of[C.idx[e]]);
    if (first < m.f.n_) entries += m.path[first];
  }
  return 0.7 * entries;
}

bool UpdatableCholesky::modify(bool add, const SparseColumns &C) {
  CholmodPattern &f = impl_->f;
  const int64_t k = C.count();
  if (!impl_->W) return false;
  if (k == 0) return true;
  cholmod_sparse *S = cholmod_l_allocate_sparse(f.n_, k, C.idx.size(), 1, 1, 0, CHOLMOD_REAL, &f.c_);
  if (!S) fail_cholmod(f.c_.status, "update allocation");
  auto *Sp = static_cast<int64_t *>(S->p), *Si = static_cast<int64_t *>(S->i);
  auto *Sx = static_cast<double *>(S->x);
  for (int64_t j = 0; j < k; ++j) {  // permuted rows, sorted as CHOLMOD requires
    auto &col = impl_->column;
    col.clear();
    for (int64_t e = C.ptr[j]; e < C.ptr[j + 1]; ++e) col.emplace_back(impl_->row_of[C.idx[e]], C.val[e]);
    std::sort(col.begin(), col.end());
    Sp[j] = C.ptr[j];
    for (size_t e = 0; e < col.size(); ++e) Si[Sp[j] + e] = col[e].first, Sx[Sp[j] + e] = col[e].second;
  }
  Sp[k] = C.ptr[k];
  cholmod_factor *W = impl_->W;
  const int ok = cholmod_l_updown(add ? 1 : 0, S, W, &f.c_);
  const int status = f.c_.status;
  cholmod_l_free_sparse(&S, &f.c_);
  if (!ok) cholmod_l_free_factor(&impl_->W, &f.c_);  // half modified: no longer a factor of anything
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
  if (!impl_->W) fail(ND_ERR_INTERNAL, "a solve with no valid updated factor");
  impl_->f.solve(impl_->W, x);
}

}  // namespace nd
