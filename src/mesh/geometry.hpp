// The Jacobian of a simplex and its determinant, shared by the mesh checks
// (orientation, zero volume), the Gmsh reader (reorienting cells) and the
// affine maps of src/fem.
#pragma once

namespace nd {

// J = dx/dxi of the affine map from the reference dim-simplex onto the simplex
// with vertices x[0..dim] (each of dim coordinates): dim x dim, row-major,
// column j = x[j+1] - x[0].
inline void simplex_jacobian(int dim, const double *const *x, double *J) {
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) J[i * dim + j] = x[j + 1][i] - x[0][i];
}

// The determinant of a dim x dim row-major matrix, dim = 1, 2 or 3. Of a
// simplex Jacobian: dim! times the signed volume, positive when the vertices
// go left to right (1D), counter-clockwise (2D) or right-handed (3D).
inline double determinant(int dim, const double *a) {
  if (dim == 1) return a[0];
  if (dim == 2) return a[0] * a[3] - a[1] * a[2];
  return a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
         a[2] * (a[3] * a[7] - a[4] * a[6]);
}

}  // namespace nd
