#include "problem/definition.hpp"

namespace nd {

void require_complete(unsigned missing) {
  if (!missing) return;
  static const struct {
    unsigned aspect;
    const char *what;
  } kNames[] = {{kMaterial, "the material"},
                {kNitsche, "the Nitsche parameters of the contact"},
                {kScheme, "the time scheme"},
                {kTimestep, "the time step"}};
  std::string what;
  for (const auto &n : kNames)
    if (missing & n.aspect) what += (what.empty() ? "" : ", ") + std::string(n.what);
  throw Incomplete(missing, what);
}

}  // namespace nd
