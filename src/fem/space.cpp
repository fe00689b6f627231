#include "fem/space.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

Space::Space(std::shared_ptr<const Mesh> m, int p)
    : mesh(std::move(m)), dim(mesh->dim), degree(p), basis(mesh->dim, p) {
  const Mesh &msh = *mesh;
  const int nv = dim + 1;
  cell_nodes.resize(static_cast<size_t>(msh.n_cells) * basis.n);
  std::map<std::pair<int64_t, int64_t>, int64_t> edge_id;
  int64_t next = msh.n_vertices;
  for (int64_t c = 0; c < msh.n_cells; ++c) {
    const int64_t *v = msh.cell(c);
    int64_t *out = &cell_nodes[c * basis.n];
    for (int i = 0; i < nv; ++i) out[i] = v[i];
    if (degree == 2)
      for (int e = 0; e < Lagrange::n_edges(dim); ++e) {
        int a, b;
        Lagrange::edge_vertices(dim, e, a, b);
        auto key = std::minmax(v[a], v[b]);
        auto it = edge_id.emplace(std::make_pair(key.first, key.second), next);
        if (it.second) ++next;
        out[nv + e] = it.first->second;
      }
  }
  n_nodes = next;
  edge_coords_.assign(static_cast<size_t>(n_nodes - msh.n_vertices) * dim, 0.0);
  for (int64_t c = 0; c < msh.n_cells && degree == 2; ++c)
    for (int e = 0; e < Lagrange::n_edges(dim); ++e) {
      int a, b;
      Lagrange::edge_vertices(dim, e, a, b);
      const int64_t node = nodes_of(c)[nv + e];
      for (int k = 0; k < dim; ++k)
        edge_coords_[(node - msh.n_vertices) * dim + k] = 0.5 * (msh.x(msh.cell(c)[a])[k] + msh.x(msh.cell(c)[b])[k]);
    }
}

std::vector<int64_t> Space::facet_nodes(const Facet &f) const {
  std::vector<int64_t> out;
  const int64_t *nodes = nodes_of(f.cell);
  for (int i = 0; i < basis.n; ++i) {
    // a vertex node lies on the facet unless it is the opposite vertex; an
    // edge node unless its edge touches the opposite vertex
    bool on = true;
    if (i <= dim) {
      on = i != f.opposite;
    } else {
      int a, b;
      Lagrange::edge_vertices(dim, i - dim - 1, a, b);
      on = a != f.opposite && b != f.opposite;
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
