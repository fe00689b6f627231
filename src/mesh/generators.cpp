// Structured meshes of a rectangle and of a box: simplices, or the
// rectangles and boxes themselves.
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

void check_cell_type(int cell_type, int whole) {
  if (cell_type != ND_CELL_SIMPLEX && cell_type != whole)
    fail(ND_ERR_VALUE, "cell_type is " + std::to_string(cell_type) + ", not ND_CELL_SIMPLEX (0) or " +
                           (whole == ND_CELL_QUADRILATERAL ? "ND_CELL_QUADRILATERAL (1)" : "ND_CELL_HEXAHEDRON (2)"));
}

}  // namespace

Mesh make_rectangle(int64_t nx, int64_t ny, const double *lo, const double *hi, int cell_type) {
  const int64_t n[2] = {nx, ny};
  check_cell_type(cell_type, ND_CELL_QUADRILATERAL);
  check_box(2, n, lo, hi);
  const bool whole = cell_type == ND_CELL_QUADRILATERAL;
  const int64_t n_nodes = checked_mul(checked_add(nx, 1, "nx + 1"), checked_add(ny, 1, "ny + 1"), "(nx + 1) * (ny + 1)");
  const int64_t n_cells = checked_mul(checked_mul(nx, ny, "nx * ny"), whole ? 1 : 2, "2 * nx * ny");
  checked_count<double>(checked_mul(n_nodes, 2, "the number of coordinates"), "the number of coordinates");
  checked_count<int64_t>(checked_mul(n_cells, whole ? 4 : 3, "the number of cell vertices"), "the number of cell vertices");
  std::vector<double> x;
  x.reserve(static_cast<size_t>(2 * n_nodes));
  for (int64_t j = 0; j <= ny; ++j)
    for (int64_t i = 0; i <= nx; ++i) {
      x.push_back(grid_coord(lo[0], hi[0], i, nx));
      x.push_back(grid_coord(lo[1], hi[1], j, ny));
    }
  auto id = [nx](int64_t i, int64_t j) { return j * (nx + 1) + i; };
  std::vector<int64_t> c;
  c.reserve(static_cast<size_t>((whole ? 4 : 3) * n_cells));
  for (int64_t j = 0; j < ny; ++j)
    for (int64_t i = 0; i < nx; ++i) {
      if (whole) {  // counter-clockwise
        c.insert(c.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
        continue;
      }
      // both triangles counter-clockwise, same diagonal
      c.insert(c.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      c.insert(c.end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return make_mesh(2, n_nodes, x.data(), n_cells, c.data(), {}, cell_type);
}

Mesh make_box(int64_t nx, int64_t ny, int64_t nz, const double *lo, const double *hi, int cell_type) {
  const int64_t n[3] = {nx, ny, nz};
  check_cell_type(cell_type, ND_CELL_HEXAHEDRON);
  check_box(3, n, lo, hi);
  const bool whole = cell_type == ND_CELL_HEXAHEDRON;
  const int64_t n_nodes =
      checked_mul(checked_mul(checked_add(nx, 1, "nx + 1"), checked_add(ny, 1, "ny + 1"), "(nx + 1) * (ny + 1)"),
                  checked_add(nz, 1, "nz + 1"), "(nx + 1) * (ny + 1) * (nz + 1)");
  const int64_t n_cells = checked_mul(checked_mul(checked_mul(nx, ny, "nx * ny"), nz, "nx * ny * nz"), whole ? 1 : 6, "6 * nx * ny * nz");
  checked_count<double>(checked_mul(n_nodes, 3, "the number of coordinates"), "the number of coordinates");
  checked_count<int64_t>(checked_mul(n_cells, whole ? 8 : 4, "the number of cell vertices"), "the number of cell vertices");
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
  // a whole box: the hexahedron's vertex order, as corner bits
  static const int hexahedron[8] = {0, 1, 3, 2, 4, 5, 7, 6};
  std::vector<int64_t> c;
  c.reserve(static_cast<size_t>((whole ? 8 : 4) * n_cells));
  auto corner_id = [&](int64_t i, int64_t j, int64_t k, int corner) {
    return id(i + (corner & 1), j + ((corner >> 1) & 1), k + ((corner >> 2) & 1));
  };
  for (int64_t k = 0; k < nz; ++k)
    for (int64_t j = 0; j < ny; ++j)
      for (int64_t i = 0; i < nx; ++i) {
        if (whole) {
          for (int corner : hexahedron) c.push_back(corner_id(i, j, k, corner));
          continue;
        }
        for (const auto &path : paths)
          for (int corner : path) c.push_back(corner_id(i, j, k, corner));
      }
  return make_mesh(3, n_nodes, x.data(), n_cells, c.data(), {}, cell_type);
}

}  // namespace nd
