#include "problem/massless.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>

#include "assembly/coercivity.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "nitschedyn.h"
#include "solve/contact_law.hpp"

namespace nd {

namespace {
// Friction: the discretization's law seen from the local points (a law by
// point reads its region's law at q: the discretization's index of local q)
class LocalPointLaw final : public PointLaw {
 public:
  LocalPointLaw(std::shared_ptr<const PointLaw> law, const std::vector<size_t> &point)
      : PointLaw(law->traits()), law_(std::move(law)), point_(point) {}
  const char *name() const override { return law_->name(); }
  void at(double x, double &value, double &slope) const override { law_->at(x, value, slope); }
  void over_step(const TimeRule &r, double P, double Pn, double &value, double &slope) const override {
    law_->over_step(r, P, Pn, value, slope);
  }
  void over_step_m(const TimeRule &r, size_t q, double gamma, int m, const double *P, const double *Pn,
                   double *value, double *J) const override {
    law_->over_step_m(r, point_[q], gamma, m, P, Pn, value, J);
  }

 private:
  std::shared_ptr<const PointLaw> law_;
  const std::vector<size_t> &point_;  // (the solver's, which owns this law)
};

// row's entries on the local DOFs (local[i] >= 0), local indices, into `in`
void split_row(const SparseRow &row, const std::vector<int64_t> &local, SparseRow &in) {
  for (size_t k = 0; k < row.idx.size(); ++k) {
    const int64_t j = local[static_cast<size_t>(row.idx[k])];
    if (j >= 0) in.idx.push_back(j), in.val.push_back(row.val[k]);
  }
}
}  // namespace

MasslessSolver::MasslessSolver(const Discretization &d, int solver)
    : theta_(d.theta), law_(d.contact_law), counters_(d.counters) {
  const int64_t n = d.K_theta.n;
  std::vector<int64_t> local(static_cast<size_t>(n), -1);
  for (int64_t i = 0; i < n; ++i)
    if (d.massless[static_cast<size_t>(i)]) {
      local[static_cast<size_t>(i)] = static_cast<int64_t>(dofs_.size());
      dofs_.push_back(i);
    }
  const int64_t m = static_cast<int64_t>(dofs_.size());
  // (K_Theta)_mm and (K_Theta)_mf, row by row (local numbering keeps the columns sorted)
  const Csr &K = d.K_theta;
  if (K.part) fail(ND_ERR_INTERNAL, "mass redistribution on operators split over the ranks");  // (splits_rows)
  A_.n = m;
  std::vector<int64_t> &ptr = A_.ptr.mut(), &col = A_.col.mut();
  ptr.assign(1, 0);
  cptr_.assign(1, 0);
  for (int64_t i : dofs_) {
    for (int64_t k = K.ptr[i]; k < K.ptr[i + 1]; ++k) {
      const int64_t j = local[static_cast<size_t>(K.col[k])];
      if (j >= 0) {
        col.push_back(j);
        A_.val.push_back(K.val[k]);
      } else {
        ccol_.push_back(K.col[k]);
        cval_.push_back(K.val[k]);
      }
    }
    ptr.push_back(static_cast<int64_t>(col.size()));
    cptr_.push_back(static_cast<int64_t>(ccol_.size()));
  }
  M0_ = A_.zeros_like();
  // the points whose rows reach m; a_q and s_q share their index list
  const ContactPoints &cp = d.contact;
  const size_t mt = static_cast<size_t>(cp.m - 1);  // friction: the tangential pairs per point
  for (size_t q = 0; q < cp.size(); ++q) {
    SparseRow a, s, pf;
    for (size_t k = 0; k < cp.a[q].idx.size(); ++k) {
      const int64_t i = cp.a[q].idx[k], j = local[static_cast<size_t>(i)];
      if (j >= 0) {
        a.idx.push_back(j), a.val.push_back(cp.a[q].val[k]);
        s.idx.push_back(j), s.val.push_back(cp.s[q].val[k]);
      } else {
        pf.idx.push_back(i), pf.val.push_back(cp.a[q].val[k] - cp.gamma[q] * cp.s[q].val[k]);
      }
    }
    if (a.idx.empty()) continue;  // N_m does not see it, nor does it see U_m
    cp_.a.push_back(std::move(a));
    cp_.s.push_back(std::move(s));
    cp_.w.push_back(cp.w[q]);
    cp_.gamma.push_back(cp.gamma[q]);
    cp_.gap.push_back(cp.gap[q]);
    pf_.push_back(std::move(pf));
    point_.push_back(q);
    // (a pair's point couples the two bodies' massless DOFs, which (K_Theta)_mm's
    // pattern lacks: the tangent widens it for the points with pairings)
    if (!cp.pairing.empty())
      cp_.pairing.insert(cp_.pairing.end(), cp.pairing.begin() + static_cast<std::ptrdiff_t>(q * kPairingValues),
                         cp.pairing.begin() + static_cast<std::ptrdiff_t>((q + 1) * kPairingValues));
    // friction: the tangential pairs likewise (a_q's index list), their
    // parts on the other DOFs shifting the slip references as pf the gaps
    for (size_t j = q * mt; j < (q + 1) * mt; ++j) {
      SparseRow ta, ts, ptf;
      split_row(cp.ta[j], local, ta);
      split_row(cp.ts[j], local, ts);
      for (size_t k = 0; k < cp.ta[j].idx.size(); ++k)
        if (local[static_cast<size_t>(cp.ta[j].idx[k])] < 0)
          ptf.idx.push_back(cp.ta[j].idx[k]), ptf.val.push_back(cp.ta[j].val[k] - cp.gamma[q] * cp.ts[j].val[k]);
      cp_.ta.push_back(std::move(ta));
      cp_.ts.push_back(std::move(ts));
      ptf_.push_back(std::move(ptf));
      slip_point_.push_back(j);
    }
    if (mt) cp_.friction.push_back(cp.friction[q]);
  }
  if (mt) {
    cp_.m = cp.m;
    law_ = std::make_shared<LocalPointLaw>(d.contact_law, point_);
    gap_t_.resize(slip_point_.size());
  }
  r_.resize(static_cast<size_t>(m));
  x_.resize(static_cast<size_t>(m));
  gap_.resize(cp_.size());
  // factored once: a step without active points is one solve with it
  factor_ = make_factorization(solver, A_, Structure::SymmetricPositiveDefinite, counters_);
  try {
    factor_->factor(A_, Structure::SymmetricPositiveDefinite);
  } catch (const Error &e) {
    if (e.code() != ND_ERR_INDEFINITE) throw;
    // (K_Theta)_mm is a principal block of K_Theta: not positive definite, nor is K_Theta
    const std::string safe = safe_gamma0(d.theta, d.gamma0_limit);
    fail(ND_ERR_INDEFINITE, "K_Theta on the massless contact DOFs (mass redistribution, explicit scheme): " +
                                std::string(e.what()) + "; with Theta = " + num(d.theta) + " and gamma0 = " +
                                num(d.gamma0) + " their static equilibrium is not well posed: lower gamma0" +
                                (safe.empty() ? std::string()
                                              : "; " + safe + ", and gamma0 = 0 chooses one automatically"));
  }
  // the tangent (K_Theta)_mm + N~'(x): symmetric, and positive definite, iff
  // Theta = 1 and the law's tangent is (not Coulomb's)
  const Structure ts =
      theta_ == 1 && law_->traits().symmetric ? Structure::SymmetricPositiveDefinite : Structure::General;
  tangent_ = make_refactoring_tangent(A_, *factor_, solver, ts, counters_);
}

int MasslessSolver::solve(const NewtonOptions &opt, const std::vector<double> &F, const std::vector<double> &gap,
                          const std::vector<double> &slip, double t, std::vector<double> &U) {
  // r = F_m - (K_Theta)_mf U_f; the gaps seen by x: g_q - p_q,f . U_f
  double scale2 = 0;  // the size of r's terms: its round-off
  for (size_t i = 0; i < dofs_.size(); ++i) {
    double s = F.empty() ? 0.0 : F[static_cast<size_t>(dofs_[i])], a = std::fabs(s);
    for (int64_t k = cptr_[i]; k < cptr_[i + 1]; ++k) {
      const double term = cval_[static_cast<size_t>(k)] * U[static_cast<size_t>(ccol_[k])];
      s -= term;
      a += std::fabs(term);
    }
    r_[i] = s;
    scale2 += a * a;
    x_[i] = U[static_cast<size_t>(dofs_[i])];
  }
  for (size_t q = 0; q < gap_.size(); ++q) gap_[q] = (gap.empty() ? cp_.gap[q] : gap[point_[q]]) - pf_[q].dot(U.data());
  ContactLaw law{&cp_, theta_, nullptr, nullptr, gap_.data(), counters_};
  law.point_law = law_.get();
  if (!gap_t_.empty()) {  // friction: the references seen by x, s_j - pt_j,f . U_f
    for (size_t j = 0; j < gap_t_.size(); ++j)
      gap_t_[j] = (slip.empty() ? 0.0 : slip[slip_point_[j]]) - ptf_[j].dot(U.data());
    law.gap_t = gap_t_.data();
  }
  law.buffers = &scratch_;
  NewtonSystem sys{&A_, tangent_.get(), &M0_, 0.0, 1.0, &law};
  sys.guess = factor_->starts_from_guess();
  // Newton's rules, with atol at least the round-off of r: U_m can be exactly
  // 0 (the bar's contact node in contact, Theta = 1), where the rule "update
  // at the round-off of U" cannot hold and rtol = atol = 0 would ask for less
  // than round-off (docs/design.md §3)
  NewtonOptions o = opt;
  o.atol = std::max(opt.atol, 64 * DBL_EPSILON * std::sqrt(scale2));
  const NewtonResult res = newton_solve(sys, r_, o, x_);
  if (!res.converged)
    fail(ND_ERR_NEWTON, "Newton on the massless contact DOFs (mass redistribution) did not converge in " +
                            std::to_string(res.iterations) + " iterations at t = " + num(t) + " (residual " +
                            num(res.residual) + ", tolerance " + num(res.tolerance) + "); the step was not taken");
  for (size_t i = 0; i < dofs_.size(); ++i) U[static_cast<size_t>(dofs_[i])] = x_[i];
  return res.iterations;
}

}  // namespace nd
