// The vector P1/P2 (Q1/Q2) Lagrange space on a mesh, each cell with its
// type's basis: FE nodes (vertices, then one node per edge for P2; per edge,
// face and cell for Q2), DOFs (node * dim + component) and the numbering of
// the free DOFs left after eliminating the clamped (Dirichlet) ones.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "fem/simplex.hpp"
#include "mesh/mesh.hpp"

namespace nd {

struct Space {
  std::shared_ptr<const Mesh> mesh;
  int dim = 0, degree = 0;
  int64_t n_nodes = 0;
  // entries a cell in cell_nodes: its basis' n; a mixed mesh's largest
  // (a P2 triangle's last entries -1 next to Q2 quadrilaterals: Mesh::cells)
  int stride = 0;
  std::vector<int64_t> cell_nodes;  // n_cells * stride

  // a uniform mesh's basis (every cell's); a mixed mesh's cells: basis_of
  Lagrange basis{1, 1};

  Space(std::shared_ptr<const Mesh> m, int degree);
  // cell c's basis: its type's (P or Q)
  const Lagrange &basis_of(int64_t c) const { return bases_[mesh->simplicial(c) ? 0 : 1]; }
  // a node's dim coordinates: a vertex's are the mesh's (not copied), an
  // edge node's (P2) its edge's midpoint (Q2: a face's, a cell's centre)
  const double *node_x(int64_t node) const {
    return node < mesh->n_vertices ? mesh->x(node) : &edge_coords_[(node - mesh->n_vertices) * dim];
  }
  const int64_t *nodes_of(int64_t c) const { return &cell_nodes[c * stride]; }
  int64_t n_dofs() const { return n_nodes * dim; }
  // The FE nodes lying on a boundary facet (vertices and, for P2, edges).
  std::vector<int64_t> facet_nodes(const Facet &f) const;

 private:
  Lagrange bases_[2];                // the simplex's and the quadrilateral's or hexahedron's
  std::vector<double> edge_coords_;  // (n_nodes - n_vertices) * dim
};

// Free DOFs: free[dof] = index in the unknown vector U, or -1 if clamped.
struct DofMap {
  std::vector<int64_t> free;
  int64_t n_free = 0;
  DofMap(const Space &s, const std::vector<int> &clamped_regions);
  // full (n_dofs) <-> free (n_free) vectors; clamped DOFs are 0
  void restrict_to_free(const double *full, double *u) const;
  void extend_to_full(const double *u, double *full) const;
};

}  // namespace nd
