#include "assembly/stress.hpp"

#include <vector>

#include "fem/simplex.hpp"

namespace nd {

void cell_stress(const Space &s, const CellMaterials &mat, const double *U_full, int64_t c, const double *xi,
                 double sigma[9]) {
  const int d = s.dim, n = s.basis_of(c).n;
  CellMap map(*s.mesh, c);
  map.at(xi);
  std::vector<double> gref(static_cast<size_t>(n * d));
  s.basis_of(c).gradients(xi, gref.data());
  double G[9] = {0};  // G[i][j] = du_i/dx_j
  const int64_t *nodes = s.nodes_of(c);
  for (int a = 0; a < n; ++a) {
    double gx[3];
    map.physical_gradient(&gref[a * d], gx);
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j) G[i * 3 + j] += U_full[nodes[a] * d + i] * gx[j];
  }
  const double lambda = mat.of(c).lambda(d), mu = mat.of(c).mu(d);
  const double tr = G[0] + G[4] + G[8];  // 1D: lambda = 0; 2D: sigma_zz = lambda tr
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      sigma[i * 3 + j] = mu * (G[i * 3 + j] + G[j * 3 + i]) + (i == j ? lambda * tr : 0.0);
}

}  // namespace nd
