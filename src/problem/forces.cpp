#include "problem/forces.hpp"

#include <algorithm>

#include "assembly/bulk.hpp"
#include "assembly/redistribution.hpp"
#include "monitor/energies.hpp"
#include "solve/products.hpp"

namespace nd {

ClampedRows clamped_rows(const Space &s, const DofMap &dofs, const CellMaterials &mat,
                         const std::vector<char> *contact_nodes) {
  ClampedRows cr;
  std::vector<int64_t> row_of(dofs.free.size(), -1);
  for (size_t k = 0; k < dofs.free.size(); ++k)
    if (dofs.free[k] < 0) {
      row_of[k] = static_cast<int64_t>(cr.dofs.size());
      cr.dofs.push_back(static_cast<int64_t>(k));
    }
  const int d = s.dim;
  // the free columns (K, M) and the clamped ones (Kcc, Mcc) of each clamped row
  std::vector<std::vector<int64_t>> cols(cr.dofs.size()), cols_c(cr.dofs.size());
  for (int64_t c = 0; c < s.mesh->n_cells; ++c) {
    const int64_t *nodes = s.nodes_of(c);
    const int nb = s.basis_of(c).n;
    for (int i = 0; i < nb * d; ++i) {
      const int64_t r = row_of[nodes[i / d] * d + i % d];
      if (r < 0) continue;
      for (int j = 0; j < nb * d; ++j) {
        const int64_t dof = nodes[j / d] * d + j % d;
        if (dofs.free[dof] >= 0) cols[r].push_back(dofs.free[dof]);
        else cols_c[r].push_back(row_of[dof]);
      }
    }
  }
  cr.K = csr_from_rows(std::move(cols));
  cr.M = cr.K.zeros_like();
  cr.Kcc = csr_from_rows(std::move(cols_c));
  cr.Mcc = cr.Kcc.zeros_like();
  cr.M_lumped.assign(cr.dofs.size(), 0.0);
  ElementMatrices em(s, mat);
  std::vector<double> lumped;
  for (int64_t c = 0; c < s.mesh->n_cells; ++c) {
    const int64_t *nodes = s.nodes_of(c);
    const int nb = s.basis_of(c).n;
    bool any = false;
    for (int i = 0; i < nb * d && !any; ++i) any = row_of[nodes[i / d] * d + i % d] >= 0;
    if (!any) continue;
    em.compute(c);
    if (contact_nodes) redistribute_element_mass(s, c, *contact_nodes, em.me);
    em.lump(lumped, contact_nodes != nullptr);  // as assemble_bulk
    for (int i = 0; i < nb; ++i)
      for (int a = 0; a < d; ++a) {
        const int64_t r = row_of[nodes[i] * d + a];
        if (r < 0) continue;
        cr.M_lumped[r] += lumped[i];
        for (int j = 0; j < nb; ++j)
          for (int b = 0; b < d; ++b) {
            const int64_t dof = nodes[j] * d + b, col = dofs.free[dof];
            Csr &K = col >= 0 ? cr.K : cr.Kcc;
            Csr &M = col >= 0 ? cr.M : cr.Mcc;
            const int64_t k = K.find(r, col >= 0 ? col : row_of[dof]);
            K.val[k] += em.ke[(i * d + a) * nb * d + j * d + b];
            if (a == b) M.val[k] += em.me[i * nb + j];
          }
      }
  }
  return cr;
}

std::vector<double> clamped_load(const Space &s, const ClampedRows &rows, const Definition &def) {
  const DofMap all(s, {});  // every DOF free: the load on all of them
  std::vector<double> full = assemble_load(s, all, def.has_body_force ? def.body_force : nullptr, def.neumann);
  if (full.empty() && def.nodal.empty()) return {};
  std::vector<double> F(rows.dofs.size(), 0.0);
  for (size_t r = 0; r < F.size(); ++r) {
    const int64_t k = rows.dofs[r];
    if (!full.empty()) F[r] += full[k];
    if (!def.nodal.empty()) F[r] += def.nodal[k];
  }
  return F;
}

std::vector<double> step_mean(const std::vector<double> &x_new, const std::vector<double> &x_old, double a) {
  if (x_new.empty() && x_old.empty()) return {};
  std::vector<double> m(std::max(x_new.size(), x_old.size()));
  for (size_t i = 0; i < m.size(); ++i)
    m[i] = (1 - a) * (x_new.empty() ? 0.0 : x_new[i]) + (a == 0 || x_old.empty() ? 0.0 : a * x_old[i]);
  return m;
}

std::vector<double> clamped_residual(const Discretization &d, const std::vector<double> &Abar,
                                     const std::vector<double> &Ubar, const std::vector<double> &phi,
                                     const std::vector<double> &Fbar_D, const std::vector<double> *phi_t,
                                     const std::vector<double> *Vbar) {
  const ClampedRows &cr = *d.clamped;
  const size_t nD = cr.dofs.size();
  std::vector<double> R(nD, 0.0), MA(nD, 0.0);
  cr.K.multiply(Ubar.data(), R.data());
  if (!d.lumped) {  // a lumped (diagonal) mass couples no clamped row to a free DOF
    cr.M.multiply(Abar.data(), MA.data());
    for (size_t r = 0; r < nD; ++r) R[r] += MA[r];
  }
  if (Vbar && d.damped()) {  // C_DF Vbar = alpha M_DF Vbar + beta K_DF Vbar
    std::vector<double> MV(nD, 0.0), KV(nD, 0.0);
    if (!d.lumped) cr.M.multiply(Vbar->data(), MV.data());
    cr.K.multiply(Vbar->data(), KV.data());
    for (size_t r = 0; r < nD; ++r) R[r] += d.damping_alpha * MV[r] + d.damping_beta * KV[r];
  }
  // the contact rows on clamped DOFs are keyed by full DOF index
  std::vector<int64_t> row_of_dof;
  if (!d.contact.a_fixed.empty()) {
    row_of_dof.assign(d.dofs.free.size(), -1);
    for (size_t r = 0; r < nD; ++r) row_of_dof[cr.dofs[r]] = static_cast<int64_t>(r);
  }
  const ContactPoints &cp = d.contact;
  const size_t mt = static_cast<size_t>(cp.m - 1);
  const bool tangential = phi_t && !phi_t->empty();
  for (size_t q = 0; q < cp.size(); ++q) {
    if (cp.a_fixed[q].idx.empty()) continue;
    // K_Theta's Nitsche part and the contact term N's b_q = a_q - Theta gamma_q s_q,
    // for the normal pair and (friction) each tangential pair of a frictional point
    for (size_t v = 0; v <= (cp.m > 1 && cp.friction[q] ? mt : 0); ++v) {
      const size_t j = q * mt + v - 1;
      const SparseRow &af = v ? cp.ta_fixed[j] : cp.a_fixed[q], &sf = v ? cp.ts_fixed[j] : cp.s_fixed[q];
      const double value = v ? (tangential ? (*phi_t)[j] : 0.0) : phi[q];
      const double sn = cp.s_row(q, static_cast<int>(v)).dot(Ubar.data()), f = cp.w[q] / cp.gamma[q] * value,
                   tg = d.theta * cp.gamma[q];
      for (size_t k = 0; k < af.idx.size(); ++k)
        R[row_of_dof[af.idx[k]]] +=
            -d.theta * cp.w[q] * cp.gamma[q] * sf.val[k] * sn + f * (af.val[k] - tg * sf.val[k]);
    }
  }
  if (!Fbar_D.empty())
    for (size_t r = 0; r < nD; ++r) R[r] -= Fbar_D[r];
  return R;
}

void contact_force_field(const Discretization &d, const State &s, double *full,
                         const std::vector<int64_t> *points) {
  const ContactPoints &cp = d.contact;
  const ContactLaw law = state_contact_law(d, s);
  std::vector<double> f(s.U.size(), 0.0);
  std::fill(full, full + d.dofs.free.size(), 0.0);
  std::vector<double> wl(cp.size(), 0.0);
  auto each = [&](auto &&visit) {  // ascending either way: the same sums
    if (points) {
      for (int64_t q : *points) visit(static_cast<size_t>(q));
    } else {
      for (size_t q = 0; q < cp.size(); ++q) visit(q);
    }
  };
  // friction: every value of the point, the law at the state (the tangential
  // traction -phi_t/gamma_q along each t_qk) added after the normal one
  const int m = cp.m;
  std::vector<double> P, wt(cp.size() * static_cast<size_t>(m - 1), 0.0);
  if (m > 1) law.P_all(s.U.data(), P);
  each([&](size_t q) {
    double phi, slope;  // the law at the state (friction: P_q from the pass above, the same bits)
    law_at(law.law_object(), m > 1 ? P[q] : law.P(q, s.U.data()), phi, slope);
    wl[q] = phi != 0 ? -cp.w[q] * phi / cp.gamma[q] : 0.0;         // w_q lambda_q (+0 where free)
    const SparseRow &a = cp.a[q];
    for (size_t k = 0; k < a.idx.size(); ++k) f[a.idx[k]] += wl[q] * a.val[k];
    if (m == 1) return;
    double value[3], J[9];
    law.law_m(q, P, value, J);
    for (int v = 1; v < m; ++v) {
      const size_t j = q * static_cast<size_t>(m - 1) + static_cast<size_t>(v - 1);
      wt[j] = value[v] != 0 ? -cp.w[q] * value[v] / cp.gamma[q] : 0.0;
      const SparseRow &t = cp.ta[j];
      for (size_t k = 0; k < t.idx.size(); ++k) f[t.idx[k]] += wt[j] * t.val[k];
    }
  });
  d.dofs.extend_to_full(f.data(), full);
  each([&](size_t q) {
    const SparseRow &af = cp.a_fixed[q];
    for (size_t k = 0; k < af.idx.size(); ++k) full[af.idx[k]] += wl[q] * af.val[k];
    for (size_t j = q * static_cast<size_t>(m - 1); j < (q + 1) * static_cast<size_t>(m - 1); ++j)
      for (size_t k = 0; k < cp.ta_fixed[j].idx.size(); ++k) full[cp.ta_fixed[j].idx[k]] += wt[j] * cp.ta_fixed[j].val[k];
  });
}

}  // namespace nd
