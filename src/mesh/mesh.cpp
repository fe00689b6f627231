#include "mesh/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "common/checked.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "mesh/cell_shape.hpp"
#include "mesh/geometry.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

using FacetKey = std::array<int64_t, 4>;  // sorted vertices, padded with -1

struct FacetKeyHash {
  size_t operator()(const FacetKey &k) const {
    size_t h = 1469598103934665603ull;
    for (int64_t v : k) h = (h ^ static_cast<size_t>(v)) * 1099511628211ull;
    return h;
  }
};

// The key of a facet with n (1..4) vertices: the first n entries of v
// sorted, the rest -1. Straight-line code (a fixed four-element sorting
// network, padding by fixed indices): no loop whose bound the optimizer
// cannot prove, which GCC 12 at -O3 reported as a false -Warray-bounds.
FacetKey key_of(std::array<int64_t, 4> v, int n) {
  if (n < 4) v[3] = -1;
  if (n < 3) v[2] = -1;
  if (n < 2) v[1] = -1;
  auto order = [&v](size_t a, size_t b) {
    if (v[a] > v[b]) std::swap(v[a], v[b]);
  };
  order(0, 1);
  order(2, 3);
  order(0, 2);
  order(1, 3);
  order(1, 2);
  return v;
}

}  // namespace

struct BoundaryIndex : std::unordered_map<FacetKey, int64_t, FacetKeyHash> {};

namespace {

// the mesh's index, made once (Mesh::boundary_lookup)
const BoundaryIndex &boundary_index(Mesh &m) {
  if (!m.boundary_lookup) {
    auto index = std::make_shared<BoundaryIndex>();
    index->reserve(m.boundary.size());
    for (size_t i = 0; i < m.boundary.size(); ++i)
      index->emplace(key_of(m.facet_vertices(m.boundary[i]), m.facet_size()), static_cast<int64_t>(i));
    m.boundary_lookup = std::move(index);
  }
  return *m.boundary_lookup;
}

void find_boundary(Mesh &m, const std::string &where) {
  // A facet is on the boundary when exactly one cell owns it.
  std::unordered_map<FacetKey, std::pair<Facet, int>, FacetKeyHash> seen;
  seen.reserve(static_cast<size_t>(m.n_cells) * (2 * m.dim));
  for (int64_t c = 0; c < m.n_cells; ++c)
    for (int f = 0; f < m.cell_facets(c); ++f) {
      Facet facet{c, f};
      auto it = seen.emplace(key_of(m.facet_vertices(facet), m.facet_size()), std::make_pair(facet, 0));
      if (++it.first->second.second > 2)
        fail(ND_ERR_DEGENERATE, where + "a facet of cell " + std::to_string(c) +
                                       " is shared by more than two cells");
    }
  for (auto &kv : seen)
    if (kv.second.second == 1) m.boundary.push_back(kv.second.first);
  std::sort(m.boundary.begin(), m.boundary.end(), [](const Facet &a, const Facet &b) {
    return a.cell != b.cell ? a.cell < b.cell : a.local < b.local;
  });
}

}  // namespace

std::array<int64_t, 4> Mesh::facet_vertices(const Facet &f) const {
  std::array<int64_t, 4> v{-1, -1, -1, -1};
  const int64_t *c = cell(f.cell);
  if (!simplicial(f.cell)) {
    for (int k = 0; k < facet_size(); ++k) v[k] = c[cube::facet_vertex(dim, f.local, k)];
    return v;
  }
  int k = 0;
  for (int i = 0; i <= dim; ++i)
    if (i != f.local) v[k++] = c[i];
  return v;
}

double Mesh::cell_diameter(int64_t c) const {
  const int64_t *v = cell(c);
  const int nv = cell_vertices(c);
  double h2 = 0;
  for (int i = 0; i < nv; ++i)
    for (int j = i + 1; j < nv; ++j) {
      double d2 = 0;
      for (int k = 0; k < dim; ++k) d2 += std::pow(x(v[i])[k] - x(v[j])[k], 2);
      h2 = std::max(h2, d2);
    }
  return std::sqrt(h2);
}

void Mesh::cell_jacobian(int64_t c, double *J) const {
  const int64_t *v = cell(c);
  const double *corners[8];
  for (int i = 0; i < cell_vertices(c); ++i) corners[i] = x(v[i]);
  if (simplicial(c)) {
    simplex_jacobian(dim, corners, J);
  } else {
    const double xi[3] = {0, 0, 0};
    cube::jacobian(dim, corners, xi, J);
  }
}

namespace {

// The smallest determinant of a quadrilateral's or hexahedron's map over its
// vertices: positive at every vertex for a convex quadrilateral, and a
// hexahedron's map is taken as valid when it is (the usual check).
double smallest_corner_determinant(const Mesh &m, int64_t c) {
  const int64_t *v = m.cell(c);
  const double *corners[8];
  for (int i = 0; i < m.cell_vertices(c); ++i) corners[i] = m.x(v[i]);
  double lowest = 0;
  for (int i = 0; i < m.cell_vertices(c); ++i) {
    const double xi[3] = {1.0 * cube::kCorner[i][0], 1.0 * cube::kCorner[i][1], 1.0 * cube::kCorner[i][2]};
    double J[9];
    cube::jacobian(m.dim, corners, xi, J);
    const double det = determinant(m.dim, J);
    if (i == 0 || !(det >= lowest)) lowest = det;
  }
  return lowest;
}

}  // namespace

namespace {

const char *kTypeNames = "ND_CELL_SIMPLEX (0), ND_CELL_QUADRILATERAL (1) or ND_CELL_HEXAHEDRON (2)";

// The cell type's vertex count in dim, refused when the type is unknown or
// not of this dimension (`what` names it in the message)
int checked_vertices(int dim, int cell_type, const std::string &where, const std::string &what) {
  if (cell_type != ND_CELL_SIMPLEX && cell_type != ND_CELL_QUADRILATERAL && cell_type != ND_CELL_HEXAHEDRON)
    fail(ND_ERR_VALUE, where + what + " is " + std::to_string(cell_type) + ", not " + kTypeNames);
  if (cell_type != ND_CELL_SIMPLEX && dim != cell_type + 1)
    fail(ND_ERR_DIMENSION, where + what + ": " + (cell_type == ND_CELL_QUADRILATERAL ? "quadrilaterals" : "hexahedra") +
                               " need dim " + std::to_string(cell_type + 1) + ", not " + std::to_string(dim));
  return cell_type == ND_CELL_SIMPLEX ? dim + 1 : 1 << dim;
}

void check_sizes(int dim, int64_t n_vertices, const double *coords, int64_t n_cells, const int64_t *cells,
                 const std::string &where) {
  if (dim < 1 || dim > 3) fail(ND_ERR_DIMENSION, where + "dim is " + std::to_string(dim) + ", not 1, 2 or 3");
  if (n_vertices <= dim) fail(ND_ERR_SIZE, where + "n_nodes must be at least dim + 1");
  if (n_cells <= 0) fail(ND_ERR_SIZE, where + "n_cells must be positive");
  if (!coords) fail(ND_ERR_NULL, where + "coords is NULL");
  if (!cells) fail(ND_ERR_NULL, where + "cells is NULL");
}

// A mesh's sizes, before its cells
Mesh sized(int dim, int cell_type, int64_t n_vertices, int64_t n_cells, int stride) {
  Mesh m;
  m.dim = dim;
  m.cell_type = cell_type;
  m.n_vertices = n_vertices;
  m.n_cells = n_cells;
  m.stride = stride;
  return m;
}

// The checks and the boundary of a mesh whose cells, types and stride are
// set (m.cells padded to m.stride entries a cell)
Mesh finish_mesh(Mesh m, const double *coords, const std::string &where) {
  const int dim = m.dim;
  const int64_t n_vertices = m.n_vertices, n_cells = m.n_cells;
  const int64_t n_coords = checked_mul(n_vertices, dim, "n_nodes * dim");
  checked_count<double>(n_coords, "n_nodes * dim");
  m.coords.assign(coords, coords + n_coords);
  for (int64_t i = 0; i < n_coords; ++i)
    if (!std::isfinite(m.coords[i]))
      fail(ND_ERR_NONFINITE, where + "coords[" + std::to_string(i) + "] (coordinate " +
                                 std::to_string(i % dim) + " of node " + std::to_string(i / dim) +
                                 ") is not finite");
  // Every index before any geometry: 1-based connectivity (a common slip
  // from Fortran or Gmsh) would otherwise surface as an inverted or flat cell.
  int64_t lowest = n_vertices, highest = -1;
  for (int64_t c = 0; c < n_cells; ++c)
    for (int i = 0; i < m.cell_vertices(c); ++i)
      lowest = std::min(lowest, m.cell(c)[i]), highest = std::max(highest, m.cell(c)[i]);
  for (int64_t c = 0; c < n_cells; ++c) {
    const int64_t *v = m.cell(c);
    for (int i = 0; i < m.cell_vertices(c); ++i) {
      if (v[i] < 0 || v[i] >= n_vertices)
        fail(ND_ERR_INDEX, where + "cell " + std::to_string(c) + " names vertex " + std::to_string(v[i]) +
                               ", outside [0, " + std::to_string(n_vertices) + "): vertex indices are 0-based" +
                               (lowest == 1 && highest == n_vertices
                                    ? " (the indices run from 1 to n_nodes: 1-based? subtract 1)"
                                    : ""));
      for (int j = 0; j < i; ++j)
        if (v[j] == v[i])
          fail(ND_ERR_INDEX, where + "cell " + std::to_string(c) + " repeats vertex " + std::to_string(v[i]));
    }
  }
  const std::vector<int64_t> component = vertex_components(n_vertices, n_cells, m.cells.data(), m.stride);
  refuse_duplicate_vertices(dim, n_vertices, m.coords.data(), where, nullptr, &component);
  for (int64_t c = 0; c < n_cells; ++c) {
    double J[9];
    m.cell_jacobian(c, J);
    const bool simplex = m.simplicial(c);
    const double det = simplex ? determinant(dim, J) : smallest_corner_determinant(m, c);
    const double h = m.cell_diameter(c);
    if (!std::isfinite(det) || !std::isfinite(std::pow(h, dim)))
      fail(ND_ERR_VALUE, where + "cell " + std::to_string(c) + ": its size overflows (diameter " + num(h) +
                             "): the coordinates are too large, rescale the units");
    // Relative to h^dim so that the test does not depend on the unit of length.
    if (std::fabs(det) <= 1e-13 * std::pow(h, dim))
      fail(ND_ERR_DEGENERATE, where + "cell " + std::to_string(c) + " has zero " +
                                  (dim == 1 ? "length" : dim == 2 ? "area" : "volume"));
    if (det < 0)
      fail(ND_ERR_DEGENERATE, where + "cell " + std::to_string(c) +
                                  (simplex ? " is inverted (negative orientation): order its vertices " +
                                                 std::string(dim == 1   ? "left to right"
                                                             : dim == 2 ? "counter-clockwise"
                                                                        : "with positive volume")
                                  : dim == 2 ? " is inverted or not convex: order its vertices "
                                               "counter-clockwise"
                                             : " is inverted or too distorted: order its vertices "
                                               "counter-clockwise on the bottom face, then the "
                                               "top face above them"));
  }
  // An orphan vertex would carry unknowns with no mass and no stiffness.
  std::vector<char> used(static_cast<size_t>(n_vertices), 0);
  for (int64_t v : m.cells)
    if (v >= 0) used[v] = 1;
  for (int64_t v = 0; v < n_vertices; ++v)
    if (!used[v])
      fail(ND_ERR_INDEX, where + "vertex " + std::to_string(v) + " belongs to no cell; every vertex must belong to one");
  find_boundary(m, where);
  return m;
}

}  // namespace

Mesh make_mesh(int dim, int64_t n_vertices, const double *coords, int64_t n_cells,
               const int64_t *cells, const std::string &where, int cell_type) {
  if (dim < 1 || dim > 3) fail(ND_ERR_DIMENSION, where + "dim is " + std::to_string(dim) + ", not 1, 2 or 3");
  const int nv = checked_vertices(dim, cell_type, where, "cell_type");
  check_sizes(dim, n_vertices, coords, n_cells, cells, where);
  // sizes from the caller: checked before any arithmetic on pointers
  const int64_t n_indices = checked_mul(n_cells, nv, "n_cells * vertices per cell");
  checked_count<int64_t>(n_indices, "n_cells * vertices per cell");
  Mesh m = sized(dim, cell_type, n_vertices, n_cells, nv);
  m.cells.assign(cells, cells + n_indices);
  return finish_mesh(std::move(m), coords, where);
}

Mesh make_mixed_mesh(int dim, int64_t n_vertices, const double *coords, int64_t n_cells, const int *types,
                     const int64_t *cells, const std::string &where) {
  check_sizes(dim, n_vertices, coords, n_cells, cells, where);
  if (!types) fail(ND_ERR_NULL, where + "cell_types is NULL");
  checked_count<int64_t>(n_cells, "n_cells");
  int64_t first_of[3] = {-1, -1, -1};  // each type's first cell
  for (int64_t c = 0; c < n_cells; ++c) {
    checked_vertices(dim, types[c], where, "cell_types[" + std::to_string(c) + "]");
    if (first_of[types[c]] < 0) first_of[types[c]] = c;
  }
  const int first = static_cast<int>(types[0]);
  const bool uniform = std::all_of(types, types + n_cells, [&](int t) { return t == first; });
  if (uniform) return make_mesh(dim, n_vertices, coords, n_cells, cells, where, first);
  if (dim == 3)  // (1D has one type: refused above)
    fail(ND_ERR_DIMENSION, where + "cell " + std::to_string(first_of[ND_CELL_SIMPLEX]) + " is a tetrahedron and cell " +
                               std::to_string(first_of[ND_CELL_HEXAHEDRON]) +
                               " a hexahedron: a conforming mix of the two needs pyramids or prisms, which this "
                               "library does not have; mixed meshes are 2D (triangles and quadrilaterals)");
  Mesh m = sized(dim, kMixedCells, n_vertices, n_cells, 4);
  m.types.assign(types, types + n_cells);
  m.cells.assign(checked_count<int64_t>(checked_mul(n_cells, 4, "n_cells * 4"), "n_cells * 4"), -1);
  for (int64_t c = 0, at = 0; c < n_cells; ++c)
    for (int i = 0; i < m.cell_vertices(c); ++i) m.cells[c * 4 + i] = cells[at++];
  return finish_mesh(std::move(m), coords, where);
}

std::vector<int64_t> vertex_components(int64_t n, int64_t n_cells, const int64_t *cells, int per_cell) {
  std::vector<int64_t> root(static_cast<size_t>(n));
  for (int64_t v = 0; v < n; ++v) root[v] = v;
  auto find = [&](int64_t v) {
    while (root[v] != v) v = root[v] = root[root[v]];  // (path halving)
    return v;
  };
  for (int64_t c = 0; c < n_cells; ++c)
    for (int i = 1; i < per_cell && cells[c * per_cell + i] >= 0; ++i) {
      const int64_t a = find(cells[c * per_cell]), b = find(cells[c * per_cell + i]);
      if (a != b) root[std::max(a, b)] = std::min(a, b);  // the smaller index names the component
    }
  for (int64_t v = 0; v < n; ++v) root[v] = find(v);
  return root;
}

void refuse_duplicate_vertices(int dim, int64_t n, const double *coords, const std::string &where,
                               const int64_t *names, const std::vector<int64_t> *component) {
  auto at = [&](int64_t v) { return coords + v * dim; };
  for (int64_t i = 0; i < n * dim; ++i)
    if (!std::isfinite(coords[i])) return;  // (refused as not finite by the caller; no order to sort by)
  std::vector<int64_t> order(static_cast<size_t>(n));
  for (int64_t v = 0; v < n; ++v) order[v] = v;
  // lexicographic by coordinates (finite: a strict weak order; -0 == 0), then by index
  std::sort(order.begin(), order.end(), [&](int64_t a, int64_t b) {
    for (int k = 0; k < dim; ++k)
      if (at(a)[k] != at(b)[k]) return at(a)[k] < at(b)[k];
    return a < b;
  });
  for (size_t i = 1; i < order.size(); ++i) {
    int64_t a = order[i - 1];
    const int64_t b = order[i];
    // (of two bodies: where they touch. Equal positions sort together, and
    // any two of one body among them meet as neighbours or with one of
    // another body between: checked pairwise over the run of equals)
    if (std::equal(at(a), at(a) + dim, at(b))) {
      if (component) {
        size_t first = i - 1;
        while (first > 0 && std::equal(at(order[first - 1]), at(order[first - 1]) + dim, at(b))) --first;
        bool same = false;
        int64_t other = a;
        for (size_t j = first; j < i && !same; ++j)
          if ((*component)[order[j]] == (*component)[b]) same = true, other = order[j];
        if (!same) continue;
        a = other;
      }
      std::string position;
      for (int k = 0; k < dim; ++k) position += (k ? ", " : "") + num(at(a)[k]);
      fail(ND_ERR_DEGENERATE, where + (names ? "nodes " : "vertices ") + std::to_string(names ? names[a] : a) + " and " +
                                  std::to_string(names ? names[b] : b) + " are at the same position (" + position +
                                  "): merge them (a body holds each point once; two bodies, connected components of the mesh, "
                                  "may touch)");
    }
  }
}

Mesh make_interval(int64_t n_cells, double a, double b) {
  if (n_cells <= 0) fail(ND_ERR_SIZE, "n_cells must be positive");
  if (!std::isfinite(a) || !std::isfinite(b))
    fail(ND_ERR_NONFINITE, "a and b must be finite (a = " + num(a) + ", b = " + num(b) + ")");
  if (!(b > a)) fail(ND_ERR_DEGENERATE, "b must be greater than a (a = " + num(a) + ", b = " + num(b) + ")");
  if (!std::isfinite(b - a)) fail(ND_ERR_NONFINITE, "b - a overflows");
  const int64_t n_nodes = checked_add(n_cells, 1, "n_cells + 1");
  std::vector<double> x(checked_count<double>(n_nodes, "n_cells + 1"));
  std::vector<int64_t> cells(checked_count<int64_t>(checked_mul(n_cells, 2, "2 * n_cells"), "2 * n_cells"));
  for (int64_t i = 0; i <= n_cells; ++i)
    x[i] = i == n_cells ? b : a + (b - a) * static_cast<double>(i) / static_cast<double>(n_cells);
  for (int64_t c = 0; c < n_cells; ++c) {
    cells[2 * c] = c;
    cells[2 * c + 1] = c + 1;
  }
  return make_mesh(1, n_nodes, x.data(), n_cells, cells.data());
}

namespace {

// Adds facets to a region with the strong guarantee: when an insertion runs
// out of memory, the ones made are taken back (erasing does not allocate).
void insert_facets(Mesh &m, int region, const std::vector<int64_t> &facets) {
  const bool existed = m.regions.count(region) != 0;
  std::set<int64_t> &set = m.regions[region];
  std::vector<int64_t> added;
  try {
    added.reserve(facets.size());
    for (int64_t f : facets)
      if (set.insert(f).second) added.push_back(f);
  } catch (...) {
    for (int64_t f : added) set.erase(f);
    if (!existed) m.regions.erase(region);
    throw;
  }
}


void add_facets_indexed(Mesh &m, const BoundaryIndex &index, int region, int64_t n_facets,
                        const int64_t *facet_vertices, const std::string &where) {
  if (region < 0) fail(ND_ERR_REGION, where + "region must be >= 0");
  if (n_facets <= 0) fail(ND_ERR_SIZE, where + "n_facets must be positive");
  if (!facet_vertices) fail(ND_ERR_NULL, where + "facet_vertices is NULL");
  checked_count<int64_t>(checked_mul(n_facets, m.facet_size(), "n_facets * vertices per facet"),
                         "n_facets * vertices per facet");
  std::vector<int64_t> found;
  for (int64_t f = 0; f < n_facets; ++f) {
    std::array<int64_t, 4> v{-1, -1, -1, -1};
    const int n = m.facet_size();
    for (int i = 0; i < n; ++i) {
      v[i] = facet_vertices[f * n + i];
      if (v[i] < 0 || v[i] >= m.n_vertices)
        fail(ND_ERR_INDEX, where + "facet " + std::to_string(f) + " names vertex " + std::to_string(v[i]) +
                               ", outside [0, " + std::to_string(m.n_vertices) + ")");
    }
    auto it = index.find(key_of(v, n));
    if (it == index.end())
      fail(ND_ERR_REGION, where + "facet " + std::to_string(f) + " is not a boundary facet of the mesh");
    found.push_back(it->second);
  }
  insert_facets(m, region, found);
}

}  // namespace

void add_region_facets(Mesh &m, int region, int64_t n_facets, const int64_t *facet_vertices,
                       const std::string &where) {
  if (region < 0) fail(ND_ERR_REGION, where + "region must be >= 0");
  if (n_facets <= 0) fail(ND_ERR_SIZE, where + "n_facets must be positive");
  if (!facet_vertices) fail(ND_ERR_NULL, where + "facet_vertices is NULL");
  add_facets_indexed(m, boundary_index(m), region, n_facets, facet_vertices, where);
}

void add_region_groups(Mesh &m, const std::map<int64_t, std::vector<int64_t>> &groups, const std::string &where) {
  if (groups.empty()) return;
  const BoundaryIndex &index = boundary_index(m);
  for (const auto &g : groups) {
    if (g.first < 0 || g.first > 2147483647) fail(ND_ERR_REGION, where + std::to_string(g.first) + ": not a valid region");
    add_facets_indexed(m, index, static_cast<int>(g.first), static_cast<int64_t>(g.second.size()) / m.facet_size(),
                       g.second.data(), where + std::to_string(g.first) + ": ");
  }
}

void set_cell_region(Mesh &m, int region, int64_t n, const int64_t *cells) {
  if (region < 0) fail(ND_ERR_REGION, "cell_region must be >= 0 (0: in no region)");
  if (n <= 0) fail(ND_ERR_SIZE, "n_cells must be positive");
  if (!cells) fail(ND_ERR_NULL, "cells is NULL");
  for (int64_t i = 0; i < n; ++i)  // all checked before any is moved: a refused call changes nothing
    if (cells[i] < 0 || cells[i] >= m.n_cells)
      fail(ND_ERR_INDEX, "cells[" + std::to_string(i) + "] = " + std::to_string(cells[i]) + " is not a cell (0 to " +
                             std::to_string(m.n_cells - 1) + ")");
  if (m.cell_region.empty()) m.cell_region.assign(static_cast<size_t>(m.n_cells), 0);
  for (int64_t i = 0; i < n; ++i) m.cell_region[cells[i]] = region;
}

void add_region_box(Mesh &m, int region, const double *lo, const double *hi) {
  if (region < 0) fail(ND_ERR_REGION, "region must be >= 0");
  if (!lo || !hi) fail(ND_ERR_NULL, std::string(!lo ? "lo" : "hi") + " is NULL");
  for (int k = 0; k < m.dim; ++k)
    if (std::isnan(lo[k]) || std::isnan(hi[k]))
      fail(ND_ERR_NONFINITE, std::string(std::isnan(lo[k]) ? "lo" : "hi") + "[" + std::to_string(k) + "] is NaN");
  // A tolerance relative to the mesh size, so that a box drawn through
  // vertices computed in floating point catches them.
  double extent = 0;
  for (int k = 0; k < m.dim; ++k) {
    double a = m.coords[k], b = m.coords[k];
    for (int64_t v = 0; v < m.n_vertices; ++v) {
      a = std::min(a, m.x(v)[k]);
      b = std::max(b, m.x(v)[k]);
    }
    extent = std::max(extent, b - a);
  }
  const double tol = 1e-10 * extent;
  std::vector<int64_t> found;
  for (size_t i = 0; i < m.boundary.size(); ++i) {
    const auto v = m.facet_vertices(m.boundary[i]);
    bool inside = true;
    for (int j = 0; j < m.facet_size() && inside; ++j)
      for (int k = 0; k < m.dim; ++k)
        if (m.x(v[j])[k] < lo[k] - tol || m.x(v[j])[k] > hi[k] + tol) inside = false;
    if (inside) found.push_back(static_cast<int64_t>(i));
  }
  insert_facets(m, region, found);
}

}  // namespace nd
