// The plane as a shape: for a region with other obstacles too (a region
// with its plane alone keeps the closed form of contact_gaps, exact).
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
    d = 0;
    for (int k = 0; k < dim_; ++k) d += (x[k] - p_[k]) * n_[k], nu[k] = n_[k];
  }
  void fingerprint(Hash &h) const override {
    h.value(1), h.bytes(p_, sizeof p_), h.bytes(n_, sizeof n_);
  }

 private:
  int dim_;
  double p_[3] = {0, 0, 0}, n_[3] = {0, 0, 0};
};
}  // namespace

std::shared_ptr<const Shape> make_plane_shape(const double *point, const double *normal, int dim) {
  return std::make_shared<PlaneShape>(point, normal, dim);
}

}  // namespace nd
