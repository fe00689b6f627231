// Isotropic linear elasticity. In 1D, sigma = E u_x (lambda = 0, 2 mu = E,
// Poisson's ratio unused); in 2D plane strain and in 3D the usual Lame
// coefficients. sigma(u) = lambda tr(eps) I + 2 mu eps in every dimension.
#pragma once

namespace nd {

struct Material {
  double young = 0, poisson = 0, density = 0;
  double lambda(int dim) const {
    return dim == 1 ? 0.0 : young * poisson / ((1 + poisson) * (1 - 2 * poisson));
  }
  double mu(int dim) const { return dim == 1 ? 0.5 * young : young / (2 * (1 + poisson)); }
};

}  // namespace nd
