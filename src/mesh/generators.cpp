// Structured simplicial meshes of a rectangle and of a box.
#include <cmath>
#include <string>
#include <vector>

#include "common/checked.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "mesh/mesh.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

void check_box(int dim, const int64_t *n, const double *lo, const double *hi) {
  if (!lo || !hi) fail(ND_ERR_NULL, std::string(!lo ? "lo" : "hi") + " is NULL");
  for (int k = 0; k < dim; ++k) {
    const std::string K = std::to_string(k);
    if (n[k] <= 0) fail(ND_ERR_SIZE, "the number of cells in direction " + K + " must be positive");
    if (!std::isfinite(lo[k]) || !std::isfinite(hi[k]) || !std::isfinite(hi[k] - lo[k]))
      fail(ND_ERR_NONFINITE, "lo and hi must be finite (lo[" + K + "] = " + num(lo[k]) + ", hi[" + K + "] = " + num(hi[k]) + ")");
    if (!(hi[k] > lo[k]))
      fail(ND_ERR_DEGENERATE, "hi[" + K + "] must exceed lo[" + K + "] (lo[" + K + "] = " + num(lo[k]) + ", hi[" + K + "] = " + num(hi[k]) + ")");
  }
}

double grid_coord(double lo, double hi, int64_t i, int64_t n) {
  return i == n ? hi : lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(n);
}

}  // namespace

Mesh make_rectangle(int64_t nx, int64_t ny, const double *lo, const double *hi) {
  const int64_t n[2] = {nx, ny};
  check_box(2, n, lo, hi);
  const int64_t n_nodes = checked_mul(checked_add(nx, 1, "nx + 1"), checked_add(ny, 1, "ny + 1"), "(nx + 1) * (ny + 1)");
  const int64_t n_cells = checked_mul(checked_mul(nx, ny, "nx * ny"), 2, "2 * nx * ny");
  checked_count<double>(checked_mul(n_nodes, 2, "the number of coordinates"), "the number of coordinates");
  checked_count<int64_t>(checked_mul(n_cells, 3, "the number of cell vertices"), "the number of cell vertices");
  std::vector<double> x;
  x.reserve(static_cast<size_t>(2 * n_nodes));
  for (int64_t j = 0; j <= ny; ++j)
    for (int64_t i = 0; i <= nx; ++i) {
      x.push_back(grid_coord(lo[0], hi[0], i, nx));
      x.push_back(grid_coord(lo[1], hi[1], j, ny));
    }
  auto id = [nx](int64_t i, int64_t j) { return j * (nx + 1) + i; };
  std::vector<int64_t> c;
  c.reserve(static_cast<size_t>(3 * n_cells));
  for (int64_t j = 0; j < ny; ++j)
    for (int64_t i = 0; i < nx; ++i) {  // both triangles counter-clockwise, same diagonal
      c.insert(c.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      c.insert(c.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return make_mesh(2, n_nodes, x.data(), n_cells, c.data());
}

Mesh make_box(int64_t nx, int64_t ny, int64_t nz, const double *lo, const double *hi) {
  const int64_t n[3] = {nx, ny, nz};
  check_box(3, n, lo, hi);
  const int64_t n_nodes =
      checked_mul(checked_mul(checked_add(nx, 1, "nx + 1"), checked_add(ny, 1, "ny + 1"), "(nx + 1) * (ny + 1)"),
                  checked_add(nz, 1, "nz + 1"), "(nx + 1) * (ny + 1) * (nz + 1)");
  const int64_t n_cells = checked_mul(checked_mul(checked_mul(nx, ny, "nx * ny"), nz, "nx * ny * nz"), 6, "6 * nx * ny * nz");
  checked_count<double>(checked_mul(n_nodes, 3, "the number of coordinates"), "the number of coordinates");
  checked_count<int64_t>(checked_mul(n_cells, 4, "the number of cell vertices"), "the number of cell vertices");
  std::vector<double> x;
  x.reserve(static_cast<size_t>(3 * n_nodes));
  for (int64_t k = 0; k <= nz; ++k)
    for (int64_t j = 0; j <= ny; ++j)
      for (int64_t i = 0; i <= nx; ++i) {
        x.push_back(grid_coord(lo[0], hi[0], i, nx));
        x.push_back(grid_coord(lo[1], hi[1], j, ny));
        x.push_back(grid_coord(lo[2], hi[2], k, nz));
      }
  auto id = [nx, ny](int64_t i, int64_t j, int64_t k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  // Kuhn split: the 6 monotone paths from corner 0 to corner 7 of each cube
  // (corner bits: x = 1, y = 2, z = 4) give positive, conforming tetrahedra.
  static const int paths[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  std::vector<int64_t> c;
  c.reserve(static_cast<size_t>(4 * n_cells));
  for (int64_t k = 0; k < nz; ++k)
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i)
        for (const auto &path : paths)
          for (int corner : path) c.push_back(id(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1)));
  return make_mesh(3, n_nodes, x.data(), n_cells, c.data());
}

}  // namespace nd
