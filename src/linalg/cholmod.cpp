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

// A CHOLMOD status that is not OK: out of memory is ND_ERR_NOMEM, a problem
// too large for its integers ND_ERR_SIZE, anything else ND_ERR_INTERNAL
// with the status (CHOLMOD_NOT_POSDEF is handled where it can occur).
[[noreturn]] void fail_cholmod(int status, const char *what) {
  const std::string st = " (CHOLMOD status " + std::to_string(status) + ")";
  if (status == CHOLMOD_OUT_OF_MEMORY) fail(ND_ERR_NOMEM, std::string("out of memory in the CHOLMOD ") + what + st);
  if (status == CHOLMOD_TOO_LARGE) fail(ND_ERR_SIZE, std::string("the matrix is too large for the CHOLMOD ") + what + st);
  fail(ND_ERR_INTERNAL, std::string("CHOLMOD ") + what + " failed" + st);
}

class Cholmod : public Factorization {
 public:
  explicit Cholmod(const Csr &pattern) : n_(pattern.n) {
    cholmod_l_start(&c_);
    c_.print = 0;  // the library never prints
    // One ordering, AMD. By default CHOLMOD tries several (AMD, then METIS
    // when AMD's fill is high) and silently skips one that runs out of
    // memory: the factorization, and the results in their last bits, then
    // depended on the memory available. Now running out of memory is an error.
    c_.nmethods = 1;
    c_.method[0].ordering = CHOLMOD_AMD;
    c_.postorder = 1;
    A_ = cholmod_l_allocate_sparse(n_, n_, pattern.col.size(), 1, 1, 1, CHOLMOD_REAL, &c_);
    if (A_) {
      std::memcpy(A_->p, pattern.ptr.data(), sizeof(int64_t) * pattern.ptr.size());
      std::memcpy(A_->i, pattern.col.data(), sizeof(int64_t) * pattern.col.size());
      L_ = cholmod_l_analyze(A_, &c_);
    }
    if (!L_) {  // a constructor that throws runs no destructor: release here
      const int status = c_.status;
      const char *what = A_ ? "analysis" : "matrix allocation";
      release();
      fail_cholmod(status, what);
    }
  }
  ~Cholmod() override { release(); }
  void release() {
    cholmod_l_free_factor(&L_, &c_);
    cholmod_l_free_sparse(&A_, &c_);
    cholmod_l_finish(&c_);
  }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    if (s != Structure::SymmetricPositiveDefinite) fail(ND_ERR_INTERNAL, "CHOLMOD given a non-symmetric matrix");
    require_finite(A);
    std::memcpy(A_->x, A.val.data(), sizeof(double) * A.val.size());
    cholmod_l_factorize(A_, L_, &c_);
    if (c_.status == CHOLMOD_NOT_POSDEF)
      fail_not_positive_definite(def_, "leading minor " + std::to_string(L_->minor + 1) + " is not positive");
    if (c_.status < CHOLMOD_OK) fail_cholmod(c_.status, "factorization");  // > 0: a warning (a small pivot)
    if (!L_->is_ll) {  // simplicial LDL^T factors indefinite matrices too: D tells
      const auto *p = static_cast<const int64_t *>(L_->p);
      const auto *x = static_cast<const double *>(L_->x);
      d_.resize(static_cast<size_t>(n_));
      for (int64_t j = 0; j < n_; ++j) d_[j] = x[p[j]];  // D(j) comes first in column j
      require_positive_pivots(n_, d_.data(), def_);
    }
    def_ = Definiteness::PositiveDefinite;
  }
  void solve(double *x) const override {
    cholmod_dense b;
    std::memset(&b, 0, sizeof b);
    b.nrow = static_cast<size_t>(n_);
    b.ncol = 1;
    b.nzmax = b.d = static_cast<size_t>(n_);
    b.x = x;
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *r = cholmod_l_solve(CHOLMOD_A, L_, &b, &c_);
    if (!r) fail_cholmod(c_.status, "solve");
    std::memcpy(x, r->x, sizeof(double) * static_cast<size_t>(n_));
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
