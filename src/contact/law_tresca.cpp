// Tresca friction (docs/design.md §10.2): the disk's radius r = gamma s,
// s >= 0 the threshold (a stress), at every point of the region, in contact
// or not (the model of Duvaut and Lions: the contact zone known, as on a
// block resting on its face). Symmetric with Theta = 1 (r does not move
// with P_n), convex, continuous. (A threshold only where P_n > 0 jumps with
// the contact and makes Newton alternate.)
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "common/format.hpp"
#include "contact/friction.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

class Tresca final : public FrictionLaw {
 public:
  Tresca(int dim, double s) : FrictionLaw(dim, s, true) {}
  const char *name() const override { return "Tresca"; }
  void radius(double, double gamma, double &r, double &dr) const override {
    r = gamma * parameter();
    dr = 0;
  }
};

}  // namespace

std::shared_ptr<const PointLaw> make_tresca_law(const double *params, int dim) {
  if (!params) fail(ND_ERR_NULL, "params is NULL: Tresca friction takes the threshold s");
  if (!std::isfinite(params[0])) fail(ND_ERR_NONFINITE, "params[0], the threshold s, is " + num(params[0]));
  if (params[0] < 0) fail(ND_ERR_VALUE, "params[0], the threshold s, is " + num(params[0]) + "; it must be >= 0");
  return std::make_shared<Tresca>(dim, params[0]);
}

}  // namespace nd
