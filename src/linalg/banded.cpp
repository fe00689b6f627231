// Banded LAPACK Cholesky (SPD) or LU (general) after a reverse Cuthill-McKee
// ordering, which makes 1D operators (P1 and P2) tridiagonal or pentadiagonal.
// LAPACKE's _work variants, column-major: they call LAPACK directly (no
// workspace malloc'd by LAPACKE, no NaN scan: the inputs are checked here).
#include <lapacke.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "linalg/ordering.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

class BandedFactorization : public Factorization {
 public:
  explicit BandedFactorization(const Csr &pattern) : n_(pattern.n) {
    perm_ = reverse_cuthill_mckee(pattern);
    inv_.resize(static_cast<size_t>(n_));
    for (int64_t i = 0; i < n_; ++i) inv_[perm_[i]] = i;
    kd_ = bandwidth(pattern, perm_);
  }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    require_finite(A);
    if (n_ == 0) fail(ND_ERR_SIZE, "the matrix has no rows");  // LAPACK would print and fail
    spd_ = s == Structure::SymmetricPositiveDefinite;
    lapack_int info;
    if (spd_) {  // upper band: ab[kd + i - j + j*ld] = A(i, j), i <= j
      ld_ = kd_ + 1;
      ab_.assign(static_cast<size_t>(ld_ * n_), 0.0);
      for (int64_t r = 0; r < n_; ++r)
        for (int64_t k = A.ptr[r]; k < A.ptr[r + 1]; ++k) {
          const int64_t i = inv_[r], j = inv_[A.col[k]];
          if (i <= j) ab_[kd_ + i - j + j * ld_] = A.val[k];
        }
      info = LAPACKE_dpbtrf_work(LAPACK_COL_MAJOR, 'U', n_, kd_, ab_.data(), ld_);
      if (info > 0) fail_not_positive_definite(def_, "Cholesky pivot " + std::to_string(info) + " is not positive");
    } else {  // ab[2kd + i - j + j*ld] = A(i, j) with room for the LU fill
      ld_ = 3 * kd_ + 1;
      ab_.assign(static_cast<size_t>(ld_ * n_), 0.0);
      for (int64_t r = 0; r < n_; ++r)
        for (int64_t k = A.ptr[r]; k < A.ptr[r + 1]; ++k) {
          const int64_t i = inv_[r], j = inv_[A.col[k]];
          ab_[2 * kd_ + i - j + j * ld_] = A.val[k];
        }
      ipiv_.resize(static_cast<size_t>(n_));
      info = LAPACKE_dgbtrf_work(LAPACK_COL_MAJOR, n_, n_, kd_, kd_, ab_.data(), ld_, ipiv_.data());
      if (info > 0) fail(ND_ERR_SINGULAR, "the matrix is singular (LU pivot " + std::to_string(info) + " is zero)");
    }
    if (info < 0) fail_lapack(info, "banded factorization");
    if (spd_) def_ = Definiteness::PositiveDefinite;  // else Unknown: LU says nothing
  }
  void solve(double *x) const override {
    if (!spd_)  // what LAPACKE_dgbtrs checked (LAPACK would carry a NaN through)
      for (int64_t i = 0; i < n_; ++i)
        if (!std::isfinite(x[i]))
          fail(ND_ERR_NONFINITE_STATE, "the right-hand side has a non-finite entry (row " + std::to_string(i) + ")");
    work_.resize(static_cast<size_t>(n_));
    for (int64_t i = 0; i < n_; ++i) work_[i] = x[perm_[i]];
    if (spd_)
      cholesky_band_solve(work_.data());
    else if (const lapack_int info = LAPACKE_dgbtrs_work(LAPACK_COL_MAJOR, 'N', n_, kd_, kd_, 1, ab_.data(), ld_,
                                                    ipiv_.data(), work_.data(), n_);
             info < 0)
      fail_lapack(info, "banded solve");
    for (int64_t i = 0; i < n_; ++i) x[perm_[i]] = work_[i];
  }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "banded"; }

 private:
  // U^T U x = b with the upper band factor of dpbtrf. Written out because
  // LAPACKE_dpbtrs checks the whole band for NaN and dtbsv goes one column
  // at a time: for the narrow bands of 1D (kd = 1, 2) that overhead is
  // most of the work, against these two loops' few instructions a row.
  void cholesky_band_solve(double *x) const {
    const double *ab = ab_.data();
    for (int64_t j = 0; j < n_; ++j) {  // U^T y = b: column j of U is contiguous
      const double *col = ab + j * ld_ + kd_ - j;  // col[i] = U(i, j)
      double s = x[j];
      for (int64_t i = std::max<int64_t>(0, j - kd_); i < j; ++i) s -= col[i] * x[i];
      x[j] = s / col[j];
    }
    for (int64_t i = n_ - 1; i >= 0; --i) {  // U x = y
      double s = x[i];
      const int64_t last = std::min<int64_t>(n_ - 1, i + kd_);
      for (int64_t j = i + 1; j <= last; ++j) s -= ab[kd_ + i - j + j * ld_] * x[j];
      x[i] = s / ab[kd_ + i * ld_];  // U(i, i)
    }
  }

  int64_t n_, kd_ = 0, ld_ = 0;
  bool spd_ = false;
  Definiteness def_ = Definiteness::Unknown;
  std::vector<int64_t> perm_, inv_;
  std::vector<double> ab_;
  std::vector<lapack_int> ipiv_;
  mutable std::vector<double> work_;
};

}  // namespace

std::unique_ptr<Factorization> make_banded_factorization(const Csr &pattern) {
  return std::make_unique<BandedFactorization>(pattern);
}

}  // namespace nd
