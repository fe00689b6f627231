#include "assembly/contact.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "fem/facet.hpp"

namespace nd {

ContactPoints assemble_contact(const Space &sp, const DofMap &dofs, const CellMaterials &mat,
                               const std::vector<ContactPlane> &planes, double gamma0) {
  std::vector<int> regions, plane_of;
  for (size_t ip = 0; ip < planes.size(); ++ip) regions.push_back(planes[ip].region), plane_of.push_back(int(ip));
  ContactPoints cp = assemble_contact(sp, dofs, mat, regions, plane_of,
                                      [&](size_t r, int64_t, const double *, double *nu) {
                                        for (int k = 0; k < sp.dim; ++k) nu[k] = planes[r].normal[k];
                                      },
                                      gamma0);
  cp.gap = contact_gaps(cp, planes);
  return cp;
}

ContactPoints assemble_contact(const Space &sp, const DofMap &dofs, const CellMaterials &mat, const std::vector<int> &regions,
                               const std::vector<int> &plane_of, const NormalOf &normal_of, double gamma0,
                               bool tangential) {
  ContactPoints cp;
  const int d = sp.dim;
  if (tangential && d > 1) cp.m = d;
  const int mt = cp.m - 1;  // tangential values per point
  // sigma_n sigma_n is of degree 2(p-1) and u_n u_n of degree 2p: the rule is
  // exact for the polynomial part of every contact integrand.
  const int degree = 2 * sp.degree;
  // (phi has sp.stride values, a cell with fewer basis functions padded with 0:
  // cp.phi's stride is the space's)
  std::vector<double> phi(static_cast<size_t>(sp.stride)), gref(static_cast<size_t>(sp.stride * d)),
      g(static_cast<size_t>(sp.stride * d));
  for (size_t ir = 0; ir < regions.size(); ++ir) {
    for (int64_t b : sp.mesh->regions.at(regions[ir])) {
      const Facet &f = sp.mesh->boundary[b];
      CellMap map(*sp.mesh, f.cell);
      const double h = sp.mesh->cell_diameter(f.cell), length = mat.gamma_length(f.cell, h);
      const Material &m = mat.of(f.cell);
      const double lam = m.lambda(d), mu = m.mu(d);
      const int64_t *nodes = sp.nodes_of(f.cell);
      const Lagrange &basis = sp.basis_of(f.cell);
      const int nb = basis.n;
      for (const FacetPoint &fp : facet_quadrature(*sp.mesh, f, degree)) {
        double nu[3] = {0, 0, 0}, n[3] = {0, 0, 0};
        normal_of(ir, b, fp.x, nu);
        for (int k = 0; k < 3; ++k) n[k] = -nu[k];
        basis.values(fp.xi, phi.data());
        std::fill(phi.begin() + nb, phi.end(), 0.0);
        basis.gradients(fp.xi, gref.data());
        map.at(fp.xi);
        for (int i = 0; i < nb; ++i) map.physical_gradient(&gref[i * d], &g[i * d]);
        SparseRow a, s, af, sf;
        double t[6] = {0, 0, 0, 0, 0, 0};
        if (mt > 0) tangent_basis(d, n, t);
        std::vector<SparseRow> ta(mt), ts(mt), taf(mt), tsf(mt);
        for (int i = 0; i < nb; ++i) {
          double gn = 0;  // grad phi_i . n
          for (int k = 0; k < d; ++k) gn += g[i * d + k] * n[k];
          for (int c = 0; c < d; ++c) {
            const int64_t dof = nodes[i] * d + c, r = dofs.free[dof];
            const int64_t at = r < 0 ? dof : r;
            SparseRow &ar = r < 0 ? af : a, &sr = r < 0 ? sf : s;
            // u = phi_i e_c: u_n = phi_i n_c; sigma_n = lambda d_c phi_i + 2 mu n_c (grad phi_i . n)
            ar.idx.push_back(at);
            ar.val.push_back(phi[i] * n[c]);
            sr.idx.push_back(at);
            sr.val.push_back(lam * g[i * d + c] + 2 * mu * n[c] * gn);
            // t . u = phi_i t_c; t . sigma(u) n = mu (t_c (grad phi_i . n) + n_c (grad phi_i . t)), t . n = 0
            for (int k = 0; k < mt; ++k) {
              const double *tk = t + 3 * k;
              double gt = 0;
              for (int j = 0; j < d; ++j) gt += g[i * d + j] * tk[j];
              SparseRow &tar = r < 0 ? taf[k] : ta[k], &tsr = r < 0 ? tsf[k] : ts[k];
              tar.idx.push_back(at);
              tar.val.push_back(phi[i] * tk[c]);
              tsr.idx.push_back(at);
              tsr.val.push_back(mu * (tk[c] * gn + n[c] * gt));
            }
          }
        }
        cp.a.push_back(std::move(a));
        cp.s.push_back(std::move(s));
        cp.a_fixed.push_back(std::move(af));
        cp.s_fixed.push_back(std::move(sf));
        for (int k = 0; k < mt; ++k) {
          cp.ta.push_back(std::move(ta[k]));
          cp.ts.push_back(std::move(ts[k]));
          cp.ta_fixed.push_back(std::move(taf[k]));
          cp.ts_fixed.push_back(std::move(tsf[k]));
          cp.tangent.insert(cp.tangent.end(), t + 3 * k, t + 3 * k + 3);
        }
        cp.plane.push_back(plane_of[ir]);
        cp.region.push_back(regions[ir]);
        cp.normal.insert(cp.normal.end(), nu, nu + 3);
        cp.phi.insert(cp.phi.end(), phi.begin(), phi.end());
        cp.w.push_back(fp.weight);
        cp.gamma.push_back(gamma0 * length);
        cp.h.push_back(h);
        cp.gamma_length.push_back(length);
        cp.facet.push_back(b);
        for (int k = 0; k < d; ++k) cp.x.push_back(fp.x[k]);
      }
    }
  }
  cp.gap.assign(cp.size(), 0.0);
  return cp;
}

void append_counterpart(const Space &sp, const DofMap &dofs, ContactPoints &cp, size_t q, int64_t cell,
                        const double *xi) {
  const int d = sp.dim, nb = sp.basis_of(cell).n, mt = cp.m - 1, stride = sp.stride;
  std::vector<double> phi(static_cast<size_t>(stride), 0.0);
  sp.basis_of(cell).values(xi, phi.data());
  cp.counterpart_phi.resize(cp.size() * static_cast<size_t>(stride));
  std::copy(phi.begin(), phi.end(), cp.counterpart_phi.begin() + static_cast<std::ptrdiff_t>(q * stride));
  const double *nu = &cp.normal[q * 3];
  const int64_t *nodes = sp.nodes_of(cell);
  // rows: a (the normal), then ta k; each with its stress row of zeros
  auto add = [](SparseRow &a, SparseRow &s, int64_t at, double v) {
    const auto it = std::find(a.idx.begin(), a.idx.end(), at);
    if (it != a.idx.end()) {
      a.val[static_cast<size_t>(it - a.idx.begin())] += v;
      return;
    }
    a.idx.push_back(at), a.val.push_back(v);
    s.idx.push_back(at), s.val.push_back(0.0);
  };
  for (int i = 0; i < nb; ++i)
    for (int c = 0; c < d; ++c) {
      const int64_t dof = nodes[i] * d + c, r = dofs.free[dof];
      const int64_t at = r < 0 ? dof : r;
      // -phi_i n_c, n = -nu
      add(r < 0 ? cp.a_fixed[q] : cp.a[q], r < 0 ? cp.s_fixed[q] : cp.s[q], at, phi[i] * nu[c]);
      for (int k = 0; k < mt; ++k) {
        const size_t row = q * static_cast<size_t>(mt) + static_cast<size_t>(k);
        add(r < 0 ? cp.ta_fixed[row] : cp.ta[row], r < 0 ? cp.ts_fixed[row] : cp.ts[row], at,
            -phi[i] * cp.tangent[row * 3 + static_cast<size_t>(c)]);
      }
    }
}

void set_bounds(ContactPoints &cp) {
  cp.nu.assign(cp.size(), 0.0);
  cp.a_sum.assign(cp.size(), 0.0);
  cp.dofs.clear();
  for (size_t q = 0; q < cp.size(); ++q) {
    double sum = 0, a_sum = 0;
    for (size_t k = 0; k < cp.a[q].val.size(); ++k) {
      sum += std::fabs(cp.a[q].val[k]) + cp.gamma[q] * std::fabs(cp.s[q].val[k]);
      a_sum += std::fabs(cp.a[q].val[k]);
    }
    cp.nu[q] = sum;
    cp.a_sum[q] = a_sum;
    cp.dofs.insert(cp.dofs.end(), cp.a[q].idx.begin(), cp.a[q].idx.end());
  }
  std::sort(cp.dofs.begin(), cp.dofs.end());
  cp.dofs.erase(std::unique(cp.dofs.begin(), cp.dofs.end()), cp.dofs.end());
  cp.runs.clear();
  cp.run_shares_s.clear();
  for (size_t q = 0; q < cp.size(); ++q) {
    if (q == 0 || cp.a[q].idx != cp.a[q - 1].idx) {
      cp.runs.push_back(static_cast<int64_t>(q));
      cp.run_shares_s.push_back(1);
    } else if (!cp.s[q].val.empty() &&  // (every DOF of the cell clamped: no row, and no pointer for memcmp)
               std::memcmp(cp.s[q].val.data(), cp.s[q - 1].val.data(), cp.s[q].val.size() * sizeof(double))) {
      cp.run_shares_s.back() = 0;
    }
  }
  cp.runs.push_back(static_cast<int64_t>(cp.size()));
  cp.run_rows.clear();
  cp.run_row_at.clear();
  for (size_t r = 0; r + 1 < cp.runs.size(); ++r) {
    cp.run_row_at.push_back(static_cast<int64_t>(cp.run_rows.size()));
    const size_t first = static_cast<size_t>(cp.runs[r]), n = static_cast<size_t>(cp.runs[r + 1]) - first;
    for (const std::vector<SparseRow> *rows : {&cp.a, &cp.s}) {
      if (rows == &cp.s && cp.run_shares_s[r]) continue;
      for (size_t k = 0; k < cp.a[first].idx.size(); ++k)
        for (size_t p = 0; p < n; ++p) cp.run_rows.push_back((*rows)[first + p].val[k]);
    }
  }
}

void tangent_basis(int dim, const double *n, double *t) {
  if (dim == 2) {
    t[0] = -n[1], t[1] = n[0], t[2] = 0;
    return;
  }
  if (dim != 3) return;
  int e = 0;  // the axis least aligned with n
  for (int k = 1; k < 3; ++k)
    if (std::fabs(n[k]) < std::fabs(n[e])) e = k;
  double u[3] = {0, 0, 0};  // e x n
  const int e1 = (e + 1) % 3, e2 = (e + 2) % 3;
  u[e1] = -n[e2];
  u[e2] = n[e1];
  const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (int k = 0; k < 3; ++k) t[k] = u[k] / len;
  t[3] = n[1] * t[2] - n[2] * t[1];  // n x t_1
  t[4] = n[2] * t[0] - n[0] * t[2];
  t[5] = n[0] * t[1] - n[1] * t[0];
}

std::vector<double> contact_gaps(const ContactPoints &cp, const std::vector<ContactPlane> &planes) {
  const size_t nq = cp.size();
  const size_t d = nq ? cp.x.size() / nq : 0;
  std::vector<double> gap(nq);
  for (size_t q = 0; q < nq; ++q) {
    if (cp.plane[q] < 0) continue;  // a curved region's point (contact/obstacles.hpp)
    const ContactPlane &pl = planes[cp.plane[q]];
    double g = 0;
    for (size_t k = 0; k < d; ++k) g += (cp.x[q * d + k] - pl.point[k]) * pl.normal[k];
    gap[q] = g;
  }
  return gap;
}

}  // namespace nd
