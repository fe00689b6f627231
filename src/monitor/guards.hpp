// The guards of docs/design.md §3b: a step that would silently blow up, sink into the
// obstacle or start inside it is refused with its own code and a message
// saying what to change. They read the state and the discretization only.
#pragma once
#include "solve/operators.hpp"
#include "time/state.hpp"

namespace nd {

// What the library checks (docs/design.md §3b); nd_problem_set_guard sets them.
struct Guards {
  double energy = 2;         // E <= f (E^0 + max_k (W^k + W_obstacle^k)); 0: off
  double penetration = 0.5;  // u_n - g0 <= f h_K; 0: off
  bool critical_timestep = true, unstable_scheme = true, coercivity = true, initial_penetration = true;
};

// At t^0: the initial penetration (beyond round-off, 1e-10 h_K) and the
// energy reference E^0. Throws ND_ERR_PENETRATION.
void guard_initial_state(const Discretization &d, const Guards &g, State &s);

// After a step old -> next: penetration deeper than the guard's fraction of
// h_K (ND_ERR_PENETRATION); mechanical energy above f (E^0 + max_k (W^k + W_obstacle^k))
// (ND_ERR_ENERGY_GROWTH) or not finite (ND_ERR_NONFINITE_STATE), evaluated
// at every step: a sparser schedule (when |U| or |V| grew by 10 %, and every
// 16 steps) let the stability suite accept steps up to x2.4 past the limit.
// Updates next.guard.
void guard_step(const Discretization &d, const Guards &g, const State &old, State &next);

}  // namespace nd
