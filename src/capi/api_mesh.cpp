// nd_mesh_*: creation, regions, queries, destruction.
#include "capi/guard.hpp"
#include "capi/handles.hpp"

namespace {
nd_mesh_s &mesh_of(nd_mesh m) {
  nd::need(m, "mesh");
  return *m;
}
int publish(nd::Mesh &&mesh, nd_mesh *out) {
  *out = new nd_mesh_s{std::move(mesh)};
  return ND_OK;
}
}  // namespace

extern "C" {

ND_EXPORT int nd_mesh_create(int dim, int64_t n_nodes, const double *coords, int64_t n_cells,
                             const int64_t *cells, nd_mesh *out) {
  return nd::guarded("nd_mesh_create", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_mesh(dim, n_nodes, coords, n_cells, cells), out);
  });
}

ND_EXPORT int nd_mesh_create_interval(int64_t n_cells, double a, double b, nd_mesh *out) {
  return nd::guarded("nd_mesh_create_interval", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_interval(n_cells, a, b), out);
  });
}

ND_EXPORT int nd_mesh_create_rectangle(int64_t nx, int64_t ny, const double lo[2], const double hi[2],
                                       nd_mesh *out) {
  return nd::guarded("nd_mesh_create_rectangle", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_rectangle(nx, ny, lo, hi), out);
  });
}

ND_EXPORT int nd_mesh_create_box(int64_t nx, int64_t ny, int64_t nz, const double lo[3], const double hi[3],
                                 nd_mesh *out) {
  return nd::guarded("nd_mesh_create_box", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_box(nx, ny, nz, lo, hi), out);
  });
}

ND_EXPORT int nd_mesh_create_cells(int dim, int cell_type, int64_t n_nodes, const double *coords, int64_t n_cells,
                                   const int64_t *cells, nd_mesh *out) {
  return nd::guarded("nd_mesh_create_cells", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_mesh(dim, n_nodes, coords, n_cells, cells, {}, cell_type), out);
  });
}

ND_EXPORT int nd_mesh_create_mixed(int dim, int64_t n_nodes, const double *coords, int64_t n_cells,
                                   const int *cell_types, const int64_t *cells, nd_mesh *out) {
  return nd::guarded("nd_mesh_create_mixed", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_mixed_mesh(dim, n_nodes, coords, n_cells, cell_types, cells), out);
  });
}

ND_EXPORT int nd_mesh_create_rectangle_cells(int64_t nx, int64_t ny, const double lo[2], const double hi[2],
                                             int cell_type, nd_mesh *out) {
  return nd::guarded("nd_mesh_create_rectangle_cells", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_rectangle(nx, ny, lo, hi, cell_type), out);
  });
}

ND_EXPORT int nd_mesh_create_box_cells(int64_t nx, int64_t ny, int64_t nz, const double lo[3], const double hi[3],
                                       int cell_type, nd_mesh *out) {
  return nd::guarded("nd_mesh_create_box_cells", [&] {
    nd::need(out, "out");
    *out = nullptr;
    return publish(nd::make_box(nx, ny, nz, lo, hi, cell_type), out);
  });
}

ND_EXPORT int nd_mesh_read_gmsh(const char *path, nd_mesh *out) {
  return nd::guarded("nd_mesh_read_gmsh", [&] {
    nd::need(out, "out");
    *out = nullptr;
    nd::need(path, "path");
    return publish(nd::read_gmsh(path), out);
  });
}

ND_EXPORT int nd_mesh_set_region(nd_mesh m, int region, int64_t n_facets, const int64_t *facet_vertices) {
  return nd::guarded("nd_mesh_set_region", [&] {
    nd::add_region_facets(mesh_of(m).mesh, region, n_facets, facet_vertices);
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_mark_boundary_box(nd_mesh m, int region, const double *lo, const double *hi) {
  return nd::guarded("nd_mesh_mark_boundary_box", [&] {
    nd::add_region_box(mesh_of(m).mesh, region, lo, hi);
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_set_cell_region(nd_mesh m, int cell_region, int64_t n_cells, const int64_t *cells) {
  return nd::guarded("nd_mesh_set_cell_region", [&] {
    nd::set_cell_region(mesh_of(m).mesh, cell_region, n_cells, cells);
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_get_cell_regions(nd_mesh m, int64_t n_cells, int *region) {
  return nd::guarded("nd_mesh_get_cell_regions", [&] {
    const nd::Mesh &mesh = mesh_of(m).mesh;
    nd::need(region, "region");
    if (n_cells != mesh.n_cells)
      nd::fail(ND_ERR_SIZE, "n_cells is " + std::to_string(n_cells) + "; the mesh has " + std::to_string(mesh.n_cells));
    for (int64_t c = 0; c < n_cells; ++c) region[c] = mesh.cell_region.empty() ? 0 : mesh.cell_region[c];
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_get_dimension(nd_mesh m, int *dim) {
  return nd::guarded("nd_mesh_get_dimension", [&] {
    nd::need(dim, "dim");
    *dim = mesh_of(m).mesh.dim;
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_get_vertex_count(nd_mesh m, int64_t *n) {
  return nd::guarded("nd_mesh_get_vertex_count", [&] {
    nd::need(n, "n_vertices");
    *n = mesh_of(m).mesh.n_vertices;
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_get_cell_count(nd_mesh m, int64_t *n) {
  return nd::guarded("nd_mesh_get_cell_count", [&] {
    nd::need(n, "n_cells");
    *n = mesh_of(m).mesh.n_cells;
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_get_region_size(nd_mesh m, int region, int64_t *n) {
  return nd::guarded("nd_mesh_get_region_size", [&] {
    nd::need(n, "n_facets");
    if (region < 0) nd::fail(ND_ERR_REGION, "region is " + std::to_string(region) + "; regions are >= 0");
    const auto &regions = mesh_of(m).mesh.regions;
    auto it = regions.find(region);
    *n = it == regions.end() ? 0 : static_cast<int64_t>(it->second.size());
    return ND_OK;
  });
}

ND_EXPORT int nd_mesh_destroy(nd_mesh *m) {
  return nd::guarded("nd_mesh_destroy", [&] {
    if (m) {
      delete *m;
      *m = nullptr;
    }
    return ND_OK;
  });
}

}  // extern "C"
