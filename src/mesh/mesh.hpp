// Meshes in 1D (intervals), 2D (triangles, quadrilaterals, or both mixed)
// and 3D (tetrahedra or hexahedra), with their boundary facets and numbered
// boundary regions.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace nd {

// A facet of a cell, named by the cell and its local facet index: for a
// simplex the local vertex opposite to it, for a quadrilateral or hexahedron
// 2 axis + side (mesh/cell_shape.hpp).
struct Facet {
  int64_t cell;
  int local;
};

struct BoundaryIndex;  // mesh.cpp: a boundary facet's index from its vertices

// Mesh::cell_type of a mesh mixing triangles and quadrilaterals
inline constexpr int kMixedCells = -1;

// A uniform mesh (one cell type) stores its type once and its cells packed;
// a mixed one (2D: triangles and quadrilaterals) each cell's type and its
// cells padded to 4 entries, a triangle's last -1, so that cell(c) stays one
// multiplication and a uniform mesh pays neither memory nor a lookup.
struct Mesh {
  int dim = 0;
  int cell_type = 0;                   // ND_CELL_SIMPLEX, _QUADRILATERAL, _HEXAHEDRON, or kMixedCells
  int64_t n_vertices = 0;
  int64_t n_cells = 0;
  std::vector<double> coords;          // n_vertices * dim
  std::vector<int64_t> cells;          // n_cells * stride
  int stride = 0;                      // entries a cell in `cells`: its vertices; mixed: 4
  std::vector<signed char> types;      // a mixed mesh's cell types; empty when uniform
  std::vector<Facet> boundary;         // facets owned by exactly one cell
  std::map<int, std::set<int64_t>> regions;  // region -> indices into boundary
  // each cell's region (>= 0; 0: in none), or empty: every cell in region 0
  std::vector<int> cell_region;
  // built by the first call that names facets by their vertices, then kept
  // (the boundary does not change): adding facets one call at a time costs
  // O(log n) per facet, not a pass over the boundary per call
  std::shared_ptr<const BoundaryIndex> boundary_lookup;

  const double *x(int64_t v) const { return &coords[v * dim]; }
  bool mixed() const { return cell_type == kMixedCells; }
  int type(int64_t c) const { return mixed() ? types[c] : cell_type; }
  bool simplicial(int64_t c) const { return type(c) == 0; }
  // every cell a simplex (1D always; a mixed mesh not)
  bool all_simplices() const { return cell_type == 0; }
  // vertices of a cell (dim + 1, or 2^dim), facets of a cell, vertices of a
  // facet (the same for every cell: a mix is 2D, where facets are segments)
  int cell_vertices(int64_t c) const { return simplicial(c) ? dim + 1 : 1 << dim; }
  int cell_facets(int64_t c) const { return simplicial(c) ? dim + 1 : 2 * dim; }
  int facet_size() const { return cell_type == 2 ? 4 : dim; }
  const int64_t *cell(int64_t c) const { return &cells[c * stride]; }
  // The facet_size() vertices of a facet (the rest -1): a simplex's in the
  // cell's local order, a quadrilateral's or hexahedron's turning about the
  // outward normal (mesh/cell_shape.hpp).
  std::array<int64_t, 4> facet_vertices(const Facet &f) const;
  double cell_diameter(int64_t c) const;
  // The Jacobian of the affine map from the reference simplex onto cell c
  // (dim x dim, row-major; see mesh/geometry.hpp); of a quadrilateral's or
  // hexahedron's multilinear map, at its first vertex.
  void cell_jacobian(int64_t c, double *J) const;
};

// Validates and copies; computes the boundary facets. Error messages start
// with `where` (a file reader passes "PATH: ").
// cell_type: ND_CELL_SIMPLEX (dim + 1 vertices a cell), ND_CELL_QUADRILATERAL
// (dim 2) or ND_CELL_HEXAHEDRON (dim 3), 2^dim vertices a cell in the VTK and
// Gmsh order (counter-clockwise; the bottom face, then the top one above it).
Mesh make_mesh(int dim, int64_t n_vertices, const double *coords, int64_t n_cells,
               const int64_t *cells, const std::string &where = {}, int cell_type = 0);
// A mesh whose cells have their own types (ND_CELL_SIMPLEX or
// ND_CELL_QUADRILATERAL in 2D; in 1D and 3D one type only, ND_ERR_DIMENSION
// naming the mix: a conforming tetrahedron/hexahedron mix needs pyramids or
// prisms). cells: each cell's vertices in turn, as many as its type has.
// All of one type: the uniform mesh make_mesh makes.
Mesh make_mixed_mesh(int dim, int64_t n_vertices, const double *coords, int64_t n_cells, const int *types,
                     const int64_t *cells, const std::string &where = {});
// ND_ERR_DEGENERATE naming both when two of the n vertices (dim coordinates
// each, finite) of one connected component are at exactly the same position
// (two bodies may touch there: docs/design.md §10.3); O(n log n). names:
// what to call vertex i in the message (null: i; a file reader passes its
// node tags); component: each vertex's (vertex_components; null: one body).
void refuse_duplicate_vertices(int dim, int64_t n, const double *coords, const std::string &where,
                               const int64_t *names = nullptr, const std::vector<int64_t> *component = nullptr);
// The connected component of each of n vertices (the smallest vertex index
// in it) through the cells, per_cell entries each (-1: padding, skipped)
std::vector<int64_t> vertex_components(int64_t n, int64_t n_cells, const int64_t *cells, int per_cell);
Mesh make_interval(int64_t n_cells, double a, double b);
// nx*ny rectangles split into 2 triangles; nx*ny*nz boxes into 6 tetrahedra;
// or kept whole (cell_type ND_CELL_QUADRILATERAL, ND_CELL_HEXAHEDRON)
Mesh make_rectangle(int64_t nx, int64_t ny, const double *lo, const double *hi, int cell_type = 0);
Mesh make_box(int64_t nx, int64_t ny, int64_t nz, const double *lo, const double *hi, int cell_type = 0);
// Gmsh MSH 4.1 / 2.2 ASCII; physical groups of facets become regions, those
// of cells cell regions (a cell in several: the largest tag).
Mesh read_gmsh(const char *path);

// Adds boundary facets given by their vertices (dim per facet) to a region;
// error messages start with `where` (a file reader passes "PATH: ...: ").
void add_region_facets(Mesh &m, int region, int64_t n_facets, const int64_t *facet_vertices,
                       const std::string &where = {});
// Adds facets to many regions at once (region -> dim vertices per facet),
// the boundary indexed once: linear in the number of facets, whatever the
// number of regions. Messages start with `where` followed by the region.
void add_region_groups(Mesh &m, const std::map<int64_t, std::vector<int64_t>> &groups, const std::string &where);
// Puts n cells (indices) in cell region `region` (>= 0; 0: in none), taking
// them out of the region they were in.
void set_cell_region(Mesh &m, int region, int64_t n, const int64_t *cells);
// Adds the boundary facets whose vertices all lie in [lo, hi].
void add_region_box(Mesh &m, int region, const double *lo, const double *hi);

}  // namespace nd
