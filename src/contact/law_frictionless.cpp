// The frictionless law phi(P) = [P]_+ (docs/design.md §2): one value per
// point, rank one, symmetric with Theta = 1, zero where free, nondecreasing,
// slope at most 1. Every fast path applies; the passes inline it.
#include "contact/law.hpp"

namespace nd {
namespace {

class Frictionless final : public PointLaw {
 public:
  Frictionless() : PointLaw(LawTraits{}) {}
  const char *name() const override { return "frictionless"; }
  static void positive_part(double x, double &value, double &slope) {
    value = x > 0 ? x : 0;
    slope = x > 0 ? 1 : 0;  // the slope of [.]_+ at 0 is taken as 0
  }
  void at(double x, double &value, double &slope) const override { positive_part(x, value, slope); }
  void over_step(const TimeRule &r, double P, double Pn, double &value, double &slope) const override {
    apply_rule(r, P, Pn, positive_part, value, slope);
  }
};

}  // namespace

std::shared_ptr<const PointLaw> make_frictionless_law() { return std::make_shared<Frictionless>(); }

}  // namespace nd
