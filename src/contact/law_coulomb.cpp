// Coulomb friction (docs/design.md §10.2): the disk's radius r = F phi_n,
// F >= 0 the friction coefficient; the tangential traction at most F
// times the normal one the step applies. Not symmetric (r moves with P_n).
#include <cmath>
#include <string>

#include "common/error.hpp"
#include "common/format.hpp"
#include "contact/friction.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

class Coulomb final : public FrictionLaw {
 public:
  Coulomb(int dim, double F) : FrictionLaw(dim, F, F == 0) {}
  const char *name() const override { return "Coulomb"; }
  void radius(double phi_n, double, double &r, double &dr) const override {
    r = parameter() * phi_n;
    dr = parameter();
  }
};

}  // namespace

std::shared_ptr<const PointLaw> make_coulomb_law(const double *params, int dim) {
  if (!params) fail(ND_ERR_NULL, "params is NULL: Coulomb friction takes the coefficient F");
  if (!std::isfinite(params[0])) fail(ND_ERR_NONFINITE, "params[0], the coefficient F, is " + num(params[0]));
  if (params[0] < 0) fail(ND_ERR_VALUE, "params[0], the coefficient F, is " + num(params[0]) + "; it must be >= 0");
  return std::make_shared<Coulomb>(dim, params[0]);
}

}  // namespace nd
