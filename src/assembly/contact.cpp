#include "assembly/contact.hpp"

#include "fem/facet.hpp"

namespace nd {

ContactPoints assemble_contact(const Space &sp, const DofMap &dofs, const Material &mat,
                               const std::vector<ContactPlane> &planes, double gamma0) {
  ContactPoints cp;
  const int d = sp.dim, nb = sp.basis.n;
  const double lam = mat.lambda(d), mu = mat.mu(d);
  // sigma_n sigma_n is of degree 2(p-1) and u_n u_n of degree 2p: the rule is
  // exact for the polynomial part of every contact integrand.
  const int degree = 2 * sp.degree;
  std::vector<double> phi(nb), gref(nb * d), g(nb * d);
  for (const ContactPlane &pl : planes) {
    double n[3];
    for (int k = 0; k < 3; ++k) n[k] = -pl.normal[k];
    for (int64_t b : sp.mesh->regions.at(pl.region)) {
      const Facet &f = sp.mesh->boundary[b];
      const AffineMap map(*sp.mesh, f.cell);
      const double h = sp.mesh->cell_diameter(f.cell);
      const int64_t *nodes = sp.nodes_of(f.cell);
      for (const FacetPoint &fp : facet_quadrature(*sp.mesh, f, degree)) {
        sp.basis.values(fp.xi, phi.data());
        sp.basis.gradients(fp.xi, gref.data());
        for (int i = 0; i < nb; ++i) map.physical_gradient(&gref[i * d], &g[i * d]);
        SparseRow a, s;
        for (int i = 0; i < nb; ++i) {
          double gn = 0;  // grad phi_i . n
          for (int k = 0; k < d; ++k) gn += g[i * d + k] * n[k];
          for (int c = 0; c < d; ++c) {
            const int64_t r = dofs.free[nodes[i] * d + c];
            if (r < 0) continue;
            // u = phi_i e_c: u_n = phi_i n_c; sigma_n = lambda d_c phi_i + 2 mu n_c (grad phi_i . n)
            a.idx.push_back(r);
            a.val.push_back(phi[i] * n[c]);
            s.idx.push_back(r);
            s.val.push_back(lam * g[i * d + c] + 2 * mu * n[c] * gn);
          }
        }
        double gap = 0;
        for (int k = 0; k < d; ++k) gap += (fp.x[k] - pl.point[k]) * pl.normal[k];
        cp.a.push_back(std::move(a));
        cp.s.push_back(std::move(s));
        cp.w.push_back(fp.weight);
        cp.gamma.push_back(gamma0 * h);
        cp.h.push_back(h);
        cp.gap.push_back(gap);
        cp.facet.push_back(b);
        for (int k = 0; k < d; ++k) cp.x.push_back(fp.x[k]);
      }
    }
  }
  return cp;
}

}  // namespace nd
