// CHOLMOD: sparse Cholesky (supernodal LL^T or simplicial LDL^T, CHOLMOD's
// choice). The pattern is analysed once (ordering, symbolic factorization),
// each matrix of it factored numerically. Our CSR arrays, read as CSC,
// describe A^T = A.
#include <cholmod.h>

#include <cstring>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "linalg/suitesparse.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

class Cholmod : public Factorization {
 public:
  explicit Cholmod(const Csr &pattern) : n_(pattern.n) {
    cholmod_l_start(&c_);
    c_.print = 0;  // the library never prints
    A_ = cholmod_l_allocate_sparse(n_, n_, pattern.col.size(), 1, 1, 1, CHOLMOD_REAL, &c_);
    if (!A_) fail(ND_ERR_NOMEM, "CHOLMOD could not allocate the matrix");
    std::memcpy(A_->p, pattern.ptr.data(), sizeof(int64_t) * pattern.ptr.size());
    std::memcpy(A_->i, pattern.col.data(), sizeof(int64_t) * pattern.col.size());
    L_ = cholmod_l_analyze(A_, &c_);
    if (!L_) fail(ND_ERR_NOMEM, "CHOLMOD analysis failed (status " + std::to_string(c_.status) + ")");
  }
  ~Cholmod() override {
    cholmod_l_free_factor(&L_, &c_);
    cholmod_l_free_sparse(&A_, &c_);
    cholmod_l_finish(&c_);
  }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    if (s != Structure::SymmetricPositiveDefinite) fail(ND_ERR_INTERNAL, "CHOLMOD given a non-symmetric matrix");
    std::memcpy(A_->x, A.val.data(), sizeof(double) * A.val.size());
    cholmod_l_factorize(A_, L_, &c_);
    if (c_.status == CHOLMOD_NOT_POSDEF)
      fail_not_positive_definite(def_, "leading minor " + std::to_string(L_->minor + 1) + " is not positive");
    if (c_.status != CHOLMOD_OK) fail(ND_ERR_NOMEM, "CHOLMOD factorization failed (status " + std::to_string(c_.status) + ")");
    if (!L_->is_ll) {  // simplicial LDL^T factors indefinite matrices too: D tells
      const auto *p = static_cast<const int64_t *>(L_->p);
      const auto *x = static_cast<const double *>(L_->x);
      d_.resize(static_cast<size_t>(n_));
      for (int64_t j = 0; j < n_; ++j) d_[j] = x[p[j]];  // D(j) comes first in column j
      require_positive_pivots(n_, d_.data(), def_);
    }
    def_ = Definiteness::PositiveDefinite;
  }
  void solve(double *x) const override { solve_many(x, n_, 1); }
  // one call for all columns: the supernodal solve works on blocks of them
  void solve_many(double *X, int64_t n, int64_t nrhs) const override {
    if (nrhs <= 0) return;
    cholmod_dense b;
    std::memset(&b, 0, sizeof b);
    b.nrow = static_cast<size_t>(n_);
    b.ncol = static_cast<size_t>(nrhs);
    b.d = static_cast<size_t>(n_);
    b.nzmax = b.d * b.ncol;
    b.x = X;
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *r = cholmod_l_solve(CHOLMOD_A, L_, &b, &c_);
    if (!r) fail(ND_ERR_NOMEM, "CHOLMOD solve failed");
    std::memcpy(X, r->x, sizeof(double) * static_cast<size_t>(n_ * nrhs));
    cholmod_l_free_dense(&r, &c_);
  }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "cholmod"; }

 private:
  int64_t n_;
  mutable cholmod_common c_;
  cholmod_sparse *A_ = nullptr;
  cholmod_factor *L_ = nullptr;
  std::vector<double> d_;
  Definiteness def_ = Definiteness::Unknown;
};

}  // namespace

std::unique_ptr<Factorization> make_cholmod_factorization(const Csr &p) { return std::make_unique<Cholmod>(p); }

}  // namespace nd
