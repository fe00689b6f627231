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
  if (!params || !std::isfinite(params[0]) || params[0] < 0)
    fail(ND_ERR_VALUE, "Coulomb friction: the coefficient F must be finite and >= 0" +
                           (params ? " (got " + num(params[0]) + ")" : std::string()));
  return std::make_shared<Coulomb>(dim, params[0]);
}

}  // namespace nd
