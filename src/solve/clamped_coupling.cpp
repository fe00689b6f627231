#include "solve/clamped_coupling.hpp"

#include <string>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

namespace {
// entry k of C = alpha M + beta K in the clamped rows' free columns (lumped: no M there)
double c_fc(const Discretization &d, int64_t k) {
  const ClampedRows &cr = *d.clamped;
  return (d.lumped ? 0.0 : d.damping_alpha * cr.M.val[k]) + d.damping_beta * cr.K.val[k];
}
// (C_cc V)_c: the clamped rows' own block of C times V
double c_cc_times(const Discretization &d, int64_t c, const double *V) {
  const ClampedRows &cr = *d.clamped;
  double sum = d.lumped ? d.damping_alpha * cr.M_lumped[c] * V[c] : 0.0;
  for (int64_t k = cr.Kcc.ptr[c]; k < cr.Kcc.ptr[c + 1]; ++k)
    sum += ((d.lumped ? 0.0 : d.damping_alpha * cr.Mcc.val[k]) + d.damping_beta * cr.Kcc.val[k]) * V[cr.Kcc.col[k]];
  return sum;
}
}  // namespace

void subtract_clamped_coupling(const Discretization &d, const ClampedMean &m, double scale, double *r) {
  const ClampedRows &cr = *d.clamped;
  const bool damped = d.damped() && !m.V.empty();
  // the clamped rows' free columns are the free rows' clamped columns (M, K symmetric)
  for (int64_t c = 0; c < cr.K.n; ++c)
    for (int64_t k = cr.K.ptr[c]; k < cr.K.ptr[c + 1]; ++k) {
      double coupling = (d.lumped ? 0.0 : cr.M.val[k] * m.A[c]) + cr.K.val[k] * m.U[c];
      if (damped) coupling += c_fc(d, k) * m.V[c];
      r[cr.K.col[k]] -= scale * coupling;
    }
}

void add_clamped_block(const Discretization &d, const ClampedMean &m, std::vector<double> &R) {
  const ClampedRows &cr = *d.clamped;
  const bool damped = d.damped() && !m.V.empty();
  for (int64_t c = 0; c < cr.Kcc.n; ++c) {
    double sum = d.lumped ? cr.M_lumped[c] * m.A[c] : 0.0;
    for (int64_t k = cr.Kcc.ptr[c]; k < cr.Kcc.ptr[c + 1]; ++k)
      sum += (d.lumped ? 0.0 : cr.Mcc.val[k] * m.A[cr.Kcc.col[k]]) + cr.Kcc.val[k] * m.U[cr.Kcc.col[k]];
    if (damped) sum += c_cc_times(d, c, m.V.data());
    R[c] += sum;
  }
}

double clamped_damping_work(const Discretization &d, const ClampedMean &m, const double *dU_f, const double *Vbar_f,
                            const std::vector<double> &dU_c) {
  const ClampedRows &cr = *d.clamped;
  double w = 0;
  for (int64_t c = 0; c < cr.K.n; ++c) {
    double row = c_cc_times(d, c, m.V.data());  // C_cc Vbar_c
    for (int64_t k = cr.K.ptr[c]; k < cr.K.ptr[c + 1]; ++k) {
      const int64_t f = cr.K.col[k];
      const double e = c_fc(d, k);
      row += e * Vbar_f[f];           // C_cf Vbar_f
      w += dU_f[f] * e * m.V[c];      // dU_f . C_fc Vbar_c
    }
    w += dU_c[static_cast<size_t>(c)] * row;
  }
  return w;
}

void add_clamped_energy(const Discretization &d, const State &s, double &kinetic, double &strain) {
  if (s.Uc.empty() || !d.clamped) return;
  const ClampedRows &cr = *d.clamped;
  const double *Uc = s.Uc.data(), *Vc = s.Vc.data();
  double kin = 0, str = 0;
  for (int64_t c = 0; c < cr.K.n; ++c) {
    double mv = d.lumped ? cr.M_lumped[c] * Vc[c] : 0.0, ku = 0;
    for (int64_t k = cr.K.ptr[c]; k < cr.K.ptr[c + 1]; ++k) {
      const int64_t f = cr.K.col[k];
      if (!d.lumped) mv += 2 * cr.M.val[k] * s.V[f];
      ku += 2 * cr.K.val[k] * s.U[f];
    }
    for (int64_t k = cr.Kcc.ptr[c]; k < cr.Kcc.ptr[c + 1]; ++k) {
      const int64_t j = cr.Kcc.col[k];
      if (!d.lumped) mv += cr.Mcc.val[k] * Vc[j];
      ku += cr.Kcc.val[k] * Uc[j];
    }
    kin += Vc[c] * mv, str += Uc[c] * ku;
  }
  kinetic += kin, strain += str;
}

void require_motion_supported(const Discretization &d, const State &next, bool distributed, bool explicit_scheme) {
  auto refuse = [](const std::string &why) {
    fail(ND_ERR_STATE, "prescribed motion (nd_problem_set_dirichlet_value) " + why + "; the step was not taken");
  };
  if (d.rows || distributed) refuse("needs the operators and the state whole on one rank");
  if (explicit_scheme && !d.massless.empty())
    refuse("with mass redistribution needs an implicit scheme (the massless DOFs' static solve has no lifting)");
  const ContactPoints &cp = d.contact;
  std::vector<int64_t> row_of;
  for (size_t q = 0; q < cp.a_fixed.size(); ++q) {
    for (const SparseRow *row : {&cp.a_fixed[q], q < cp.s_fixed.size() ? &cp.s_fixed[q] : &cp.a_fixed[q]}) {
      if (row->idx.empty()) continue;
      if (row_of.empty()) {
        row_of.assign(d.dofs.free.size(), -1);
        for (size_t c = 0; c < d.clamped->dofs.size(); ++c) row_of[d.clamped->dofs[c]] = static_cast<int64_t>(c);
      }
      for (int64_t dof : row->idx)
        if (next.Uc[row_of[dof]] != 0)
          refuse("moves DOF " + std::to_string(dof) + ", which contact point " + std::to_string(q) +
                 "'s rows read: keep the clamped DOFs of the contact facets' cells at 0");
    }
  }
}

}  // namespace nd
