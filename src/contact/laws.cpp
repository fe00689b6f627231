// The registry of contact laws: an id (ND_FRICTION_* once issue 56 makes
// them public) to its law. A new law: its file and one line in kLaws.
#include <string>

#include "common/error.hpp"
#include "contact/law.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

struct Entry {
  int id;
  std::shared_ptr<const PointLaw> (*make)();
};
const Entry kLaws[] = {
    {kFrictionNone, make_frictionless_law},
};

}  // namespace

std::shared_ptr<const PointLaw> make_law(int id) {
  for (const Entry &e : kLaws)
    if (e.id == id) return e.make();
  fail(ND_ERR_VALUE, "contact law " + std::to_string(id) + " is not one of the registered laws");
}

const PointLaw &frictionless_law() {
  // (made once, never destroyed: no destructor at exit for a pass to outlive)
  static const std::shared_ptr<const PointLaw> *const law =
      new std::shared_ptr<const PointLaw>(make_frictionless_law());
  return **law;
}

}  // namespace nd
