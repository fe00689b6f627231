// A rigid circular cylinder (3D), infinite along its axis: the sphere's
// distance measured across the axis.
#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"
#include "contact/obstacle.hpp"

namespace nd {
namespace {
class Cylinder final : public Shape {
 public:
  Cylinder(const double *p, const double *axis, double r, bool inside) : r_(r), inside_(inside) {
    const double len = length(axis, 3);
    for (int k = 0; k < 3; ++k) p_[k] = p[k], a_[k] = axis[k] / len;
  }
  const char *kind() const override { return "cylinder"; }
  void distance(double, const double *x, double &d, double *nu) const override {
    double v[3], along = 0;
    for (int k = 0; k < 3; ++k) v[k] = x[k] - p_[k], along += v[k] * a_[k];
    for (int k = 0; k < 3; ++k) v[k] -= along * a_[k];
    const double len = length(v, 3);
    const double s = inside_ ? -1 : 1;
    // on the axis every radial direction is a normal: one across it is chosen
    double e[3] = {0, 0, 0};
    if (!(len > 0)) {
      const int k = std::fabs(a_[0]) < 0.9 ? 0 : 1;
      e[k] = 1;
      double ea = e[0] * a_[0] + e[1] * a_[1] + e[2] * a_[2];
      for (int j = 0; j < 3; ++j) e[j] -= ea * a_[j];
      ea = length(e, 3);
      for (int j = 0; j < 3; ++j) e[j] /= ea;
    }
    for (int k = 0; k < 3; ++k) nu[k] = s * (len > 0 ? v[k] / len : e[k]);
    d = inside_ ? r_ - len : len - r_;
  }
  void fingerprint(Hash &h) const override {
    h.value(3), h.bytes(p_, sizeof p_), h.bytes(a_, sizeof a_), h.value(r_), h.value(int(inside_));
  }

 private:
  double p_[3], a_[3], r_;
  bool inside_;
};
}  // namespace

std::shared_ptr<const Shape> make_cylinder(const double *point, const double *axis, double radius, bool inside,
                                           int dim) {
  if (dim != 3)
    fail(ND_ERR_DIMENSION, "a cylinder needs a 3D mesh (this one is " + std::to_string(dim) +
                               "D); in 2D its cross-section is a circle: nd_problem_add_contact_sphere");
  if (!(length(axis, 3) > 0)) fail(ND_ERR_VALUE, "axis has zero length");
  if (!(radius > 0) || !std::isfinite(radius))
    fail(ND_ERR_VALUE, "radius is " + num(radius) + "; it must be positive and finite");
  return std::make_shared<Cylinder>(point, axis, radius, inside);
}

}  // namespace nd
