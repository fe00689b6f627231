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
// V: the mean velocity (1-a) V_c^{n+1} + a V_c^n, which the damping's
// coupling C_fc reads (empty: none)
struct ClampedMean {
  std::vector<double> U, A, V;
};

// next.Vc, next.Ac from next.Uc (set) and old's (empty: at rest at 0), by the
// scheme's update applied to the clamped DOFs as to a state of their own. An
// explicit scheme's update takes A^{n+1} from the equation of motion, which
// the clamped DOFs do not have, and any A^{n+1} read into its velocity
// update keeps an error forever (central difference: a period-4 oscillation
// after a sudden start); they take backward differences,
// V^{n+1} = (U^{n+1} - U^n)/tau, A^{n+1} = (V^{n+1} - V^n)/tau: exact for a
// motion linear in t, a sudden start's impulse exactly the momentum it
// gives. Returns the step's mean.
ClampedMean prescribed_update(const TimeScheme &scheme, double tau, const State &old, State &next);

}  // namespace nd
