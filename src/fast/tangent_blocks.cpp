// The low-rank tangent of laws with m > 1 values per point (friction;
// docs/design.md §10.2): A's factor reused through contact, and
//   T = A + sum_q B_q D_q P_q^T,  B_q = [b_q0 .. b_q,m-1], P_q likewise,
//   D_q = kappa (w_q/gamma_q) J_q  (the law's m x m Jacobian),
// solved by the Woodbury identity over the active points' values:
//   T^{-1} x = y - Z D w,  (I + G D) w = P^T y,  y = A^{-1} x,  Z = A^{-1} B,  G = P^T Z.
// det T = det A det(I + G D): singular exactly when T is. The columns
// Z_qk = A^{-1} b_qk are made on a point's first activation and kept for
// the solver's lifetime (A is fixed per step size), their bits independent
// of the others' (a restart, whose cache starts empty, is bitwise). Past the
// rank limit (the k m values of the k active points against
// lowrank_rank_limit) T is refactored instead.
#include <lapacke.h>

#include <algorithm>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "nitschedyn.h"
#include "fast/tangents.hpp"

namespace nd {
namespace {

class BlockTangent : public TangentSolver {
 public:
  BlockTangent(const Csr &A, const Factorization &A_factor, int solver, Structure s, int64_t max_rank,
               Counters *counters, const DofGeometry *geometry)
      : A_(A), A_factor_(A_factor), solver_(solver), structure_(s), max_rank_(max_rank), counters_(counters),
        geometry_(geometry) {}

  void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x,
             const double *guess, const std::vector<double> *P_U) override {
    ++stats.calls;
    if (solved_without_contact(A_factor_, any_active, x, guess)) return;
    const ContactPoints &cp = *law.cp;
    bind(cp, law.theta);
    const int m = cp.m;
    const std::vector<double> &P = law.P_at(U, P_U, P_scratch_);
    // the active points (any entry of J not zero) and their blocks D_q
    active_.clear();
    D_.clear();
    double value[3], J[9];
    for (size_t q = 0; q < cp.size(); ++q) {
      law.law_m(q, P, value, J);
      bool any = false;
      for (int k = 0; k < m * m; ++k) any = any || J[k] != 0;
      if (!any) continue;
      active_.push_back(static_cast<int64_t>(q));
      const double f = kappa * cp.w[q] / cp.gamma[q];
      for (int k = 0; k < m * m; ++k) D_.push_back(f * J[k]);
    }
    const int64_t k = static_cast<int64_t>(active_.size()) * m;  // the capacitance's order
    stats.max_rank = std::max(stats.max_rank, k);
    if (k == 0) return A_factor_.solve(x);
    if (max_rank_ >= 0 && k > max_rank_) {  // the refactorization is cheaper here
      if (!fallback_) fallback_ = make_refactoring_tangent(A_, A_factor_, solver_, structure_, counters_, geometry_);
      const TangentStats before = fallback_->stats;
      fallback_->solve(law, kappa, U, true, x, nullptr, &P);
      stats.refactorizations += fallback_->stats.refactorizations - before.refactorizations;
      return;
    }
    ++stats.lowrank;
    for (int64_t q : active_) require(cp, q);
    A_factor_.solve(x);  // y
    // C = I + G D (column-major, k x k), G_(i,a),(j,b) = p_ia . Z_jb
    count(counters_, &Counters::tangent_updates);
    const int64_t na = static_cast<int64_t>(active_.size());
    G_.resize(static_cast<size_t>(k * k));
    for (int64_t j = 0; j < na; ++j)
      for (int b = 0; b < m; ++b) {
        const double *z = Z_[static_cast<size_t>(active_[j]) * m + b].data();
        for (int64_t i = 0; i < na; ++i)
          for (int a = 0; a < m; ++a) G_[(i * m + a) + (j * m + b) * k] = p_dot(cp, active_[i], a, z);
      }
    C_.assign(static_cast<size_t>(k * k), 0.0);
    for (int64_t j = 0; j < na; ++j)  // (G D)'s block column j: G's block column j times D_j
      for (int b = 0; b < m; ++b)
        for (int c = 0; c < m; ++c) {
          const double d = D_[static_cast<size_t>(j * m * m + c * m + b)];  // D_j(c, b)
          if (d == 0) continue;
          for (int64_t r = 0; r < k; ++r) C_[r + (j * m + b) * k] += G_[r + (j * m + c) * k] * d;
        }
    for (int64_t i = 0; i < k; ++i) C_[i + i * k] += 1;
    ipiv_.resize(static_cast<size_t>(k));
    lapack_int info = LAPACKE_dgetrf_work(LAPACK_COL_MAJOR, static_cast<lapack_int>(k), static_cast<lapack_int>(k),
                                          C_.data(), static_cast<lapack_int>(k), ipiv_.data());
    if (info > 0)
      fail(ND_ERR_SINGULAR, "the Newton tangent is singular (capacitance pivot " + std::to_string(info) + " of " +
                                std::to_string(k) + " contact values is zero)");
    if (info < 0) fail(ND_ERR_INTERNAL, "LAPACKE_dgetrf: argument " + std::to_string(-info));
    w_.resize(static_cast<size_t>(k));
    for (int64_t i = 0; i < na; ++i)
      for (int a = 0; a < m; ++a) w_[i * m + a] = p_dot(cp, active_[i], a, x);
    info = LAPACKE_dgetrs_work(LAPACK_COL_MAJOR, 'N', static_cast<lapack_int>(k), 1, C_.data(),
                               static_cast<lapack_int>(k), ipiv_.data(), w_.data(), static_cast<lapack_int>(k));
    if (info < 0) fail(ND_ERR_INTERNAL, "LAPACKE_dgetrs: argument " + std::to_string(-info));
    // x = y - Z (D w)
    for (int64_t j = 0; j < na; ++j)
      for (int b = 0; b < m; ++b) {
        double dw = 0;
        for (int c = 0; c < m; ++c) dw += D_[static_cast<size_t>(j * m * m + b * m + c)] * w_[j * m + c];
        if (dw == 0) continue;
        const double *z = Z_[static_cast<size_t>(active_[j]) * m + b].data();
        for (int64_t i = 0; i < A_.n; ++i) x[i] -= dw * z[i];
      }
  }
  const char *name() const override { return "blocks"; }

 private:
  // p_qa . z, p_qa = a_qa - gamma_q s_qa (the a-th pair of rows)
  static double p_dot(const ContactPoints &cp, int64_t q, int a, const double *z) {
    const SparseRow &ar = cp.a_row(static_cast<size_t>(q), a), &sr = cp.s_row(static_cast<size_t>(q), a);
    const double g = cp.gamma[static_cast<size_t>(q)];
    double s = 0;
    for (size_t i = 0; i < ar.idx.size(); ++i) s += (ar.val[i] - g * sr.val[i]) * z[ar.idx[i]];
    return s;
  }
  // the columns are those of one set of points and one Theta
  void bind(const ContactPoints &cp, double theta) {
    if (cp_ == &cp && theta_ == theta && Z_.size() == cp.size() * static_cast<size_t>(cp.m)) return;
    cp_ = &cp, theta_ = theta;
    Z_.assign(cp.size() * static_cast<size_t>(cp.m), {});
  }
  // Z_qk = A^{-1} b_qk for every k, unless made
  void require(const ContactPoints &cp, int64_t q) {
    for (int k = 0; k < cp.m; ++k) {
      std::vector<double> &z = Z_[static_cast<size_t>(q) * cp.m + k];
      if (!z.empty()) continue;
      z.assign(static_cast<size_t>(A_.n), 0.0);
      const SparseRow &ar = cp.a_row(static_cast<size_t>(q), k), &sr = cp.s_row(static_cast<size_t>(q), k);
      const double tg = theta_ * cp.gamma[static_cast<size_t>(q)];
      for (size_t i = 0; i < ar.idx.size(); ++i) z[ar.idx[i]] += ar.val[i] - tg * sr.val[i];
      A_factor_.solve(z.data());
      ++stats.columns;
    }
  }

  const Csr &A_;
  const Factorization &A_factor_;
  int solver_;
  Structure structure_;
  int64_t max_rank_;
  Counters *counters_;
  const DofGeometry *geometry_;
  std::unique_ptr<TangentSolver> fallback_;
  const ContactPoints *cp_ = nullptr;
  double theta_ = 0;
  std::vector<std::vector<double>> Z_;  // per point and value; empty until needed
  std::vector<int64_t> active_;
  std::vector<double> D_, G_, C_, w_, P_scratch_;
  std::vector<lapack_int> ipiv_;
};

}  // namespace

std::unique_ptr<TangentSolver> make_block_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                  Structure structure, int64_t max_rank, Counters *counters,
                                                  const DofGeometry *geometry) {
  return std::make_unique<BlockTangent>(A, A_factor, solver, structure, max_rank, counters, geometry);
}

}  // namespace nd
