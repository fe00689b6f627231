#include "problem/definition.hpp"

namespace nd {

void require_complete(unsigned missing) {
  static const AspectName kWhat[] = {{kMaterial, "the material"},
                                     {kNitsche, "the Nitsche parameters of the contact"},
                                     {kScheme, "the time scheme"},
                                     {kTimestep, "the time step"}};
  if (missing) throw Incomplete(missing, aspect_names(missing, kWhat));
}

}  // namespace nd
