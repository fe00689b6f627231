// Prescribed motion on the clamped DOFs (docs/design.md §10.5): their
// velocity and acceleration at t^{n+1} follow from their displacement by the
// scheme's own update, and the step's equation reads them at the scheme's
// mean point (TimeScheme::mean_weight, mean_acceleration).
#pragma once
#include <vector>

#include "time/scheme.hpp"

namespace nd {

// The clamped DOFs over one step: Ubar = (1-a) U_c^{n+1} + a U_c^n and Abar,
// the scheme's mean acceleration there, at which the free rows' coupling
// (the lifting) and the reactions read them.
struct ClampedMean {
  std::vector<double> U, A;
};

// next.Vc, next.Ac from next.Uc (set) and old's (empty: at rest at 0), by the
// scheme's update applied to the clamped DOFs as to a state of their own; an
// explicit scheme, whose update takes A^{n+1} as given, gets the one its
// Taylor step U^{n+1} = U^n + tau V^n + tau^2/2 A needs to reach U_c^{n+1}
// (exact for a motion quadratic in t). Returns the step's mean.
ClampedMean prescribed_update(const TimeScheme &scheme, double tau, const State &old, State &next);

}  // namespace nd
