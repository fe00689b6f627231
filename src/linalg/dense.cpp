// Dense LAPACK Cholesky (SPD) or LU (general). LAPACKE's _work variants,
// column-major: they call LAPACK directly (no workspace malloc'd by LAPACKE,
// no NaN scan: the matrix and the right-hand side are checked here).
#include <lapacke.h>

#include <cmath>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

class DenseFactorization : public Factorization {
 public:
  explicit DenseFactorization(int64_t n) : n_(n) {}
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    require_finite(A);
    if (n_ == 0) fail(ND_ERR_SIZE, "the matrix has no rows");  // LAPACK would print and fail
    a_.assign(static_cast<size_t>(n_ * n_), 0.0);
    for (int64_t i = 0; i < n_; ++i)
      for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k) a_[A.col[k] * n_ + i] = A.val[k];
    spd_ = s == Structure::SymmetricPositiveDefinite;
    lapack_int info;
    if (spd_) {
      info = LAPACKE_dpotrf_work(LAPACK_COL_MAJOR, 'L', n_, a_.data(), n_);
      if (info > 0) fail_not_positive_definite(def_, "Cholesky pivot " + std::to_string(info) + " is not positive");
    } else {
      ipiv_.resize(static_cast<size_t>(n_));
      info = LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, n_, n_, a_.data(), n_, ipiv_.data());
      if (info > 0) fail(ND_ERR_SINGULAR, "the matrix is singular (LU pivot " + std::to_string(info) + " is zero)");
    }
    if (info < 0) fail_lapack(info, "dense factorization");
    if (spd_) def_ = Definiteness::PositiveDefinite;  // else Unknown: LU says nothing
  }
  void solve(double *x) const override {
    for (int64_t i = 0; i < n_; ++i)  // (LAPACK would carry a NaN through)
      if (!std::isfinite(x[i])) fail(ND_ERR_NONFINITE_STATE, "the right-hand side has a non-finite entry (row " + std::to_string(i) + ")");
    const lapack_int info = spd_ ? LAPACKE_dpotrs_work(LAPACK_COL_MAJOR, 'L', n_, 1, a_.data(), n_, x, n_)
                                 : LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', n_, 1, a_.data(), n_, ipiv_.data(), x, n_);
    if (info < 0) fail_lapack(info, "dense solve");
  }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "dense"; }

 private:
  int64_t n_;
  bool spd_ = false;
  Definiteness def_ = Definiteness::Unknown;
  std::vector<double> a_;
  std::vector<lapack_int> ipiv_;
};

}  // namespace

std::unique_ptr<Factorization> make_dense_factorization(const Csr &pattern) {
  return std::make_unique<DenseFactorization>(pattern.n);
}

}  // namespace nd
