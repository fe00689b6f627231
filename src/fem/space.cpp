#include "fem/space.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <utility>

#include "common/checked.hpp"
#include "common/error.hpp"
#include "mesh/cell_shape.hpp"
#include "nitschedyn.h"

namespace nd {

// The vertices, then per cell in turn its new edges, faces (3D hexahedra)
// and (Q2) its centre: one numbering for every cell type, so that a P2
// triangle and a Q2 quadrilateral share their common edge's node. A node's
// position is the mean of its edge's, face's or cell's vertices (the map's
// value at its reference position).
Space::Space(std::shared_ptr<const Mesh> m, int p)
    : mesh(std::move(m)),
      dim(mesh->dim),
      degree(p),
      bases_{Lagrange(dim, p, ND_CELL_SIMPLEX), Lagrange(dim, p, dim == 1 ? ND_CELL_SIMPLEX : dim - 1)} {
  const Mesh &msh = *mesh;
  basis = basis_of(0);
  stride = msh.mixed() ? bases_[1].n : basis.n;
  cell_nodes.assign(checked_count<int64_t>(checked_mul(msh.n_cells, stride, "n_cells * nodes per cell"),
                                           "n_cells * nodes per cell"),
                    -1);
  std::map<std::array<int64_t, 4>, int64_t> shared;  // sorted vertices (edges padded with -1) -> node
  int64_t next = msh.n_vertices;
  auto node_of = [&](std::array<int64_t, 4> key, int n_vertices) {
    std::sort(key.begin(), key.begin() + n_vertices);
    auto it = shared.emplace(key, next);
    if (it.second) {
      ++next;
      double x[3] = {0, 0, 0};
      for (int i = 0; i < n_vertices; ++i)
        for (int k = 0; k < dim; ++k) x[k] += msh.x(key[i])[k];
      for (int k = 0; k < dim; ++k) edge_coords_.push_back(x[k] / n_vertices);
    }
    return it.first->second;
  };
  for (int64_t c = 0; c < msh.n_cells; ++c) {
    const int64_t *v = msh.cell(c);
    int64_t *out = &cell_nodes[c * stride];
    const int nv = msh.cell_vertices(c);
    for (int i = 0; i < nv; ++i) out[i] = v[i];
    if (degree == 1) continue;
    int at = nv;
    if (msh.simplicial(c)) {
      for (int e = 0; e < Lagrange::n_edges(dim); ++e) {
        int a, b;
        Lagrange::edge_vertices(dim, e, a, b);
        out[at++] = node_of({v[a], v[b], -1, -1}, 2);
      }
      continue;
    }
    for (int e = 0; e < cube::n_edges(dim); ++e)
      out[at++] = node_of({v[cube::kEdge[e][0]], v[cube::kEdge[e][1]], -1, -1}, 2);
    if (dim == 3)
      for (int f = 0; f < cube::n_facets(dim); ++f) {
        std::array<int64_t, 4> face;
        for (int k = 0; k < 4; ++k) face[k] = v[cube::facet_vertex(dim, f, k)];
        out[at++] = node_of(face, 4);
      }
    double x[3] = {0, 0, 0};  // the centre: the cell's own node
    for (int i = 0; i < nv; ++i)
      for (int k = 0; k < dim; ++k) x[k] += msh.x(v[i])[k];
    for (int k = 0; k < dim; ++k) edge_coords_.push_back(x[k] / nv);
    out[at] = next++;
  }
  n_nodes = next;
}

std::vector<int64_t> Space::facet_nodes(const Facet &f) const {
  std::vector<int64_t> out;
  const int64_t *nodes = nodes_of(f.cell);
  const Lagrange &lb = basis_of(f.cell);
  if (!mesh->simplicial(f.cell)) {  // facet 2 axis + side: the nodes at xi_axis = side
    for (int i = 0; i < lb.n; ++i)
      if (lb.tensor_index(i, f.local / 2) == f.local % 2) out.push_back(nodes[i]);
    return out;
  }
  for (int i = 0; i < lb.n; ++i) {
    // a vertex node lies on the facet unless it is the opposite vertex; an
    // edge node unless its edge touches the opposite vertex
    bool on = true;
    if (i <= dim) {
      on = i != f.local;
    } else {
      int a, b;
      Lagrange::edge_vertices(dim, i - dim - 1, a, b);
      on = a != f.local && b != f.local;
    }
    if (on) out.push_back(nodes[i]);
  }
  return out;
}

DofMap::DofMap(const Space &s, const std::vector<int> &clamped_regions) {
  free.assign(static_cast<size_t>(s.n_dofs()), 0);
  for (int r : clamped_regions) {
    auto it = s.mesh->regions.find(r);
    if (it == s.mesh->regions.end()) continue;
    for (int64_t b : it->second)
      for (int64_t node : s.facet_nodes(s.mesh->boundary[b]))
        for (int k = 0; k < s.dim; ++k) free[node * s.dim + k] = -1;
  }
  for (auto &f : free) f = f == 0 ? n_free++ : -1;
  // Nothing left to solve for: LAPACK and SuiteSparse reject an empty system
  // (LAPACK printing to stderr), so say what is wrong here.
  if (n_free == 0)
    fail(ND_ERR_SIZE, "every degree of freedom is clamped (the Dirichlet regions cover all nodes): "
                      "the problem has no unknowns");
}

void DofMap::restrict_to_free(const double *full, double *u) const {
  for (size_t d = 0; d < free.size(); ++d)
    if (free[d] >= 0) u[free[d]] = full[d];
}

void DofMap::extend_to_full(const double *u, double *full) const {
  for (size_t d = 0; d < free.size(); ++d) full[d] = free[d] >= 0 ? u[free[d]] : 0.0;
}

}  // namespace nd
