// A rigid sphere (a circle in 2D): d = |x - c| - R outside, R - |x - c| inside.
#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"
#include "contact/obstacle.hpp"

namespace nd {
namespace {
class Sphere final : public Shape {
 public:
  Sphere(const double *c, double r, bool inside, int dim) : dim_(dim), r_(r), inside_(inside) {
    for (int k = 0; k < dim; ++k) c_[k] = c[k];
  }
  const char *kind() const override { return "sphere"; }
  void distance(double, const double *x, double &d, double *nu) const override {
    double v[3] = {0, 0, 0};
    for (int k = 0; k < dim_; ++k) v[k] = x[k] - c_[k];
    const double len = length(v, dim_);
    // at the centre every direction is a normal: one is chosen, the last axis
    const double s = inside_ ? -1 : 1;
    for (int k = 0; k < dim_; ++k) nu[k] = len > 0 ? s * v[k] / len : (k == dim_ - 1 ? s : 0);
    d = inside_ ? r_ - len : len - r_;
  }
  void fingerprint(Hash &h) const override {
    h.value(2), h.bytes(c_, sizeof c_), h.value(r_), h.value(int(inside_));
  }

 private:
  int dim_;
  double c_[3] = {0, 0, 0}, r_;
  bool inside_;
};
}  // namespace

std::shared_ptr<const Shape> make_sphere(const double *center, double radius, bool inside, int dim) {
  if (dim < 2)
    fail(ND_ERR_DIMENSION, "a sphere needs a 2D or 3D mesh (a circle in 2D); in 1D the obstacle is a plane "
                           "(nd_problem_set_contact_plane)");
  if (!(radius > 0) || !std::isfinite(radius))
    fail(ND_ERR_VALUE, "radius is " + num(radius) + "; it must be positive and finite");
  return std::make_shared<Sphere>(center, radius, inside, dim);
}

}  // namespace nd
