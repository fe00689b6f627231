// Isotropic linear elasticity. In 1D, sigma = E u_x (lambda = 0, 2 mu = E,
// Poisson's ratio unused); in 2D plane strain (or plane stress on request)
// and in 3D the usual Lame coefficients. sigma(u) = lambda tr(eps) I + 2 mu eps in every dimension.
#pragma once
#include <cstdint>
#include <map>
#include <vector>

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
  bool operator==(const Material &o) const {
    return young == o.young && poisson == o.poisson && density == o.density;
  }
};

// The material of each cell (docs/design.md §10.6): the distinct materials,
// list[0] the default (nd_problem_set_material), and each cell's index into
// the list. One material for every cell keeps no index: the single-material
// path, the same bits as before cells had materials.
struct CellMaterials {
  std::vector<Material> list;
  std::vector<int> index;  // per cell, or empty: every cell list[0]
  CellMaterials(const Material &m) : list{m} {}  // NOLINT: one material converts implicitly
  CellMaterials() = default;
  bool uniform() const { return index.empty(); }
  const Material &of(int64_t cell) const { return index.empty() ? list[0] : list[index[cell]]; }
  // gamma_q / gamma0 of a point of `cell` with diameter h: h_K E / E_K, E the
  // default's Young's modulus (just h_K for one material), so that gamma0
  // (and gamma0*, the automatic gamma0) means the same in every material
  double gamma_length(int64_t cell, double h) const {
    return index.empty() ? h : h * (list[0].young / list[index[cell]].young);
  }
};

// The default material, the materials of cell regions and each cell's region
// (empty: all 0); a region without a material of its own takes the default.
CellMaterials cell_materials(const Material &fallback, const std::map<int, Material> &by_region,
                             const std::vector<int> &cell_region);

}  // namespace nd
