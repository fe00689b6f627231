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
                                      [&](size_t r, const double *, double *nu) {
                                        for (int k = 0; k < sp.dim; ++k) nu[k] = planes[r].normal[k];
                                      },
                                      gamma0);
  cp.gap = contact_gaps(cp, planes);
  return cp;
}

ContactPoints assemble_contact(const Space &sp, const DofMap &dofs, const CellMaterials &mat, const std::vector<int> &regions,
                               const std::vector<int> &plane_of, const NormalOf &normal_of, double gamma0) {
  ContactPoints cp;
  const int d = sp.dim, nb = sp.basis.n;
  // sigma_n sigma_n is of degree 2(p-1) and u_n u_n of degree 2p: the rule is
  // exact for the polynomial part of every contact integrand.
  const int degree = 2 * sp.degree;
  std::vector<double> phi(nb), gref(nb * d), g(nb * d);
  for (size_t ir = 0; ir < regions.size(); ++ir) {
    for (int64_t b : sp.mesh->regions.at(regions[ir])) {
      const Facet &f = sp.mesh->boundary[b];
      const AffineMap map(*sp.mesh, f.cell);
      const double h = sp.mesh->cell_diameter(f.cell), length = mat.gamma_length(f.cell, h);
      const Material &m = mat.of(f.cell);
      const double lam = m.lambda(d), mu = m.mu(d);
      const int64_t *nodes = sp.nodes_of(f.cell);
      for (const FacetPoint &fp : facet_quadrature(*sp.mesh, f, degree)) {
        double nu[3] = {0, 0, 0}, n[3] = {0, 0, 0};
        normal_of(ir, fp.x, nu);
        for (int k = 0; k < 3; ++k) n[k] = -nu[k];
        sp.basis.values(fp.xi, phi.data());
        sp.basis.gradients(fp.xi, gref.data());
        for (int i = 0; i < nb; ++i) map.physical_gradient(&gref[i * d], &g[i * d]);
        SparseRow a, s, af, sf;
        for (int i = 0; i < nb; ++i) {
          double gn = 0;  // grad phi_i . n
          for (int k = 0; k < d; ++k) gn += g[i * d + k] * n[k];
          for (int c = 0; c < d; ++c) {
            const int64_t dof = nodes[i] * d + c, r = dofs.free[dof];
            SparseRow &ar = r < 0 ? af : a, &sr = r < 0 ? sf : s;
            // u = phi_i e_c: u_n = phi_i n_c; sigma_n = lambda d_c phi_i + 2 mu n_c (grad phi_i . n)
            ar.idx.push_back(r < 0 ? dof : r);
            ar.val.push_back(phi[i] * n[c]);
            sr.idx.push_back(r < 0 ? dof : r);
            sr.val.push_back(lam * g[i * d + c] + 2 * mu * n[c] * gn);
          }
        }
        cp.a.push_back(std::move(a));
        cp.s.push_back(std::move(s));
        cp.a_fixed.push_back(std::move(af));
        cp.s_fixed.push_back(std::move(sf));
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
