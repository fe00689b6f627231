// The reference quadrilateral [0,1]^2 and hexahedron [0,1]^3: their vertices
// (in the VTK and Gmsh order), facets, edges, and the multilinear map onto a
// mesh cell. Facet f = 2 axis + side is the face xi_axis = side.
#pragma once

namespace nd {
namespace cube {

// reference coordinates of vertex v: counter-clockwise on the bottom face
// (xi_2 = 0), then the top face above it
inline constexpr int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                      {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
// the facets' vertices, turning about the outward normal (a quadrilateral's
// segment with the cell on its left)
inline constexpr int kQuadFacet[4][2] = {{3, 0}, {1, 2}, {0, 1}, {2, 3}};
inline constexpr int kHexFacet[6][4] = {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4},
                                        {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};
// the edges in VTK's order (a quadrilateral has the first four)
inline constexpr int kEdge[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                     {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};

inline int n_vertices(int dim) { return 1 << dim; }
inline int n_edges(int dim) { return dim == 2 ? 4 : 12; }
inline int n_facets(int dim) { return 2 * dim; }
inline int facet_size(int dim) { return 1 << (dim - 1); }
// vertex k (< facet_size) of facet f (a quadrilateral's k taken mod 2: the
// same for k < 2, and within its row for an optimiser that cannot see the bound)
inline int facet_vertex(int dim, int f, int k) { return dim == 2 ? kQuadFacet[f][k & 1] : kHexFacet[f][k]; }

// J = dx/dxi (dim x dim, row-major) at xi of the multilinear map
// x = sum_v N_v(xi) x[v], N_v = prod_k (xi_k or 1 - xi_k), of the cell with
// vertices x[0..2^dim) (dim coordinates each).
inline void jacobian(int dim, const double *const *x, const double *xi, double *J) {
  for (int i = 0; i < dim * dim; ++i) J[i] = 0;
  for (int v = 0; v < n_vertices(dim); ++v)
    for (int k = 0; k < dim; ++k) {
      double dN = kCorner[v][k] ? 1.0 : -1.0;  // dN_v/dxi_k
      for (int l = 0; l < dim; ++l)
        if (l != k) dN *= kCorner[v][l] ? xi[l] : 1 - xi[l];
      for (int i = 0; i < dim; ++i) J[i * dim + k] += dN * x[v][i];
    }
}

// x at xi of the same map
inline void to_physical(int dim, const double *const *x, const double *xi, double *out) {
  for (int i = 0; i < dim; ++i) out[i] = 0;
  for (int v = 0; v < n_vertices(dim); ++v) {
    double N = 1;
    for (int l = 0; l < dim; ++l) N *= kCorner[v][l] ? xi[l] : 1 - xi[l];
    for (int i = 0; i < dim; ++i) out[i] += N * x[v][i];
  }
}

}  // namespace cube
}  // namespace nd
