// Small meshes and spaces for the white-box unit tests.
#pragma once
#include <cmath>
#include <memory>
#include <vector>

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

// [0,2] x [0,1] split into 2 n x n counter-clockwise triangles, slightly distorted
inline std::shared_ptr<nd::Mesh> irregular_rectangle(int n) {
  std::vector<double> x;
  std::vector<int64_t> c;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool inner = i > 0 && i < n && j > 0 && j < n;
      x.push_back(2.0 * i / n + (inner ? 0.05 / n * std::sin(3.0 * i + j) : 0));
      x.push_back(1.0 * j / n + (inner ? 0.05 / n * std::cos(i + 5.0 * j) : 0));
    }
  auto id = [n](int i, int j) { return static_cast<int64_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      c.insert(c.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      c.insert(c.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return std::make_shared<nd::Mesh>(
      nd::make_mesh(2, static_cast<int64_t>(x.size() / 2), x.data(), static_cast<int64_t>(c.size() / 3), c.data()));
}

// One tetrahedron-split unit cube (6 tetrahedra around the main diagonal).
inline std::shared_ptr<nd::Mesh> cube_of_tets() {
  std::vector<double> x;
  for (int k = 0; k < 8; ++k) x.insert(x.end(), {double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
  // paths 0 -> 7 through the cube's vertices; each gives a positive tetrahedron
  const int64_t t[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  std::vector<int64_t> c;
  for (auto &tet : t) c.insert(c.end(), tet, tet + 4);
  return std::make_shared<nd::Mesh>(nd::make_mesh(3, 8, x.data(), 6, c.data()));
}

}  // namespace ndtest
