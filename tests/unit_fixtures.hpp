// Small meshes and spaces for the white-box unit tests.
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "assembly/bulk.hpp"
#include "fem/space.hpp"
#include "mesh/mesh.hpp"

namespace ndtest {

// (a, b) with n cells whose interior nodes are moved by up to 30% of h, so
// that no test passes only because the mesh is uniform.
inline std::shared_ptr<nd::Mesh> irregular_interval(int n, double a, double b) {
  std::vector<double> x(n + 1);
  std::vector<int64_t> c(2 * n);
  for (int i = 0; i <= n; ++i) {
    const double h = (b - a) / n, wobble = (i == 0 || i == n) ? 0 : 0.3 * h * std::sin(7.0 * i);
    x[i] = a + i * h + wobble;
  }
  for (int i = 0; i < n; ++i) c[2 * i] = i, c[2 * i + 1] = i + 1;
  return std::make_shared<nd::Mesh>(nd::make_mesh(1, n + 1, x.data(), n, c.data()));
}

// [0,2] x [0,1] in 2 n x n triangles (nd_mesh_create_rectangle), interior
// vertices moved by up to 5% of h: the boundary and the topology stay.
inline std::shared_ptr<nd::Mesh> irregular_rectangle(int n) {
  const double lo[2] = {0, 0}, hi[2] = {2, 1};
  auto m = std::make_shared<nd::Mesh>(nd::make_rectangle(n, n, lo, hi));
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) {
      double *x = &m->coords[2 * (j * (n + 1) + i)];
      x[0] += 0.05 / n * std::sin(3.0 * i + j);
      x[1] += 0.05 / n * std::cos(i + 5.0 * j);
    }
  return m;
}

// The unit cube in 6 tetrahedra (nd_mesh_create_box, one cell).
inline std::shared_ptr<nd::Mesh> cube_of_tets() {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  return std::make_shared<nd::Mesh>(nd::make_box(1, 1, 1, lo, hi));
}

// c M + K on a 2D P1 rectangle with every DOF free: SPD, n = 2 (nx + 1)^2.
// For nx = 10 (242 unknowns) CHOLMOD picks a simplicial LDL^T.
inline nd::Csr spd_matrix(int nx) {
  nd::Space s(irregular_rectangle(nx), 1);
  nd::DofMap dofs(s, {});
  nd::BulkOperators ops = nd::assemble_bulk(s, dofs, nd::Material{50, 0.25, 1});
  nd::Csr A;
  nd::csr_combine(1e4, ops.M, 1.0, ops.K, A);
  return A;
}

// ||a - b|| / ||b|| (2-norms)
inline double rel_diff(const std::vector<double> &a, const std::vector<double> &b) {
  double d = 0, s = 0;
  for (size_t i = 0; i < a.size(); ++i) d += (a[i] - b[i]) * (a[i] - b[i]), s += b[i] * b[i];
  return std::sqrt(d) / std::max(std::sqrt(s), 1e-300);
}

}  // namespace ndtest
