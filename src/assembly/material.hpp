// Isotropic linear elasticity. In 1D, sigma = E u_x (lambda = 0, 2 mu = E,
// Poisson's ratio unused); in 2D plane strain (or plane stress on request)
// and in 3D the usual Lame coefficients. sigma(u) = lambda tr(eps) I + 2 mu eps in every dimension.
#pragma once

namespace nd {

struct Material {
  double young = 0, poisson = 0, density = 0;
  // 2D only: plane stress (sigma_zz = 0) instead of plane strain (eps_zz = 0)
  bool plane_stress = false;
  // plane stress: lambda* = 2 lambda mu/(lambda + 2 mu) = E nu/(1 - nu^2), mu unchanged
  double lambda(int dim) const {
    if (dim == 1) return 0.0;
    if (dim == 2 && plane_stress) return young * poisson / (1 - poisson * poisson);
    return young * poisson / ((1 + poisson) * (1 - 2 * poisson));
  }
  double mu(int dim) const { return dim == 1 ? 0.5 * young : young / (2 * (1 + poisson)); }
};

}  // namespace nd
