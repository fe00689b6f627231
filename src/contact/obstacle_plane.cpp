// The plane as a shape, and its distance for a region's plane among other
// obstacles (a region with its plane alone keeps the closed form of
// contact_gaps, assembly/contact.cpp: the same formula, bitwise as before).
#include "common/error.hpp"
#include "contact/obstacle.hpp"

namespace nd {
namespace {
class PlaneShape final : public Shape {
 public:
  PlaneShape(const double *point, const double *normal, int dim) : dim_(dim) {
    for (int k = 0; k < dim; ++k) p_[k] = point[k], n_[k] = normal[k];
  }
  const char *kind() const override { return "plane"; }
  void distance(double, const double *x, double &d, double *nu) const override {
    plane_distance(p_, n_, dim_, x, d, nu);
  }
  void fingerprint(Hash &h) const override {
    h.value(1), h.bytes(p_, sizeof p_), h.bytes(n_, sizeof n_);
  }

 private:
  int dim_;
  double p_[3] = {0, 0, 0}, n_[3] = {0, 0, 0};
};
}  // namespace

void plane_distance(const double *point, const double *normal, int dim, const double *x, double &d, double *nu) {
  d = 0;
  for (int k = 0; k < dim; ++k) d += (x[k] - point[k]) * normal[k], nu[k] = normal[k];
}

std::shared_ptr<const Shape> make_plane_shape(const double *point, const double *normal, int dim) {
  return std::make_shared<PlaneShape>(point, normal, dim);
}

}  // namespace nd
