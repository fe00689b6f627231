// The user's obstacle: a signed-distance callback (nd_distance_fn). Its
// answers are checked: a failure or a bad value fails the step, which is
// then not taken (ND_ERR_CALLBACK, ND_ERR_NONFINITE, ND_ERR_VALUE).
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "common/format.hpp"
#include "contact/obstacle.hpp"

namespace nd {
namespace {
// |nu| = 1 to this: a normal the user normalized in double precision
constexpr double kUnitTolerance = 1e-10;

class DistanceShape final : public Shape {
 public:
  DistanceShape(nd_distance_fn f, void *user, int dim) : f_(f), user_(user), dim_(dim) {}
  const char *kind() const override { return "distance"; }
  void distance(double t, const double *x, double &d, double *nu) const override {
    double xx[3] = {0, 0, 0}, n[3] = {0, 0, 0}, dd = 0;
    for (int k = 0; k < dim_; ++k) xx[k] = x[k];
    const int rc = f_(t, xx, &dd, n, user_);
    const std::string at = " at t = " + num(t) + ", x = (" + num(x[0]) + (dim_ > 1 ? ", " + num(x[1]) : "") +
                           (dim_ > 2 ? ", " + num(x[2]) : "") + ")";
    if (rc != 0)
      fail(ND_ERR_CALLBACK, "the distance callback returned " + std::to_string(rc) + at + "; the step was not taken");
    if (!std::isfinite(dd))
      fail(ND_ERR_NONFINITE, "the distance callback gave a distance that is not finite" + at);
    double nn = 0;
    for (int k = 0; k < dim_; ++k) {
      if (!std::isfinite(n[k])) fail(ND_ERR_NONFINITE, "the distance callback gave a normal that is not finite" + at);
      nn += n[k] * n[k];
    }
    if (!(std::fabs(nn - 1) <= kUnitTolerance))
      fail(ND_ERR_VALUE, "the distance callback gave a normal of length " + num(std::sqrt(nn)) + at +
                             "; it must be a unit vector");
    d = dd;
    for (int k = 0; k < dim_; ++k) nu[k] = n[k];
  }
  // a callback is a function of the host's: its address says nothing across
  // ranks or runs, so only its kind enters the digests
  void fingerprint(Hash &h) const override { h.value(4); }

 private:
  nd_distance_fn f_;
  void *user_;
  int dim_;
};
}  // namespace

std::shared_ptr<const Shape> make_distance(nd_distance_fn f, void *user, int dim) {
  return std::make_shared<DistanceShape>(f, user, dim);
}

}  // namespace nd
