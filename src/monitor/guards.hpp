// The guards of docs/design.md §3b: a step that would silently blow up, sink into the
// obstacle or start inside it is refused with its own code and a message
// saying what to change. They read the state and the discretization only.
#pragma once
#include "solve/operators.hpp"
#include "time/products.hpp"
#include "time/state.hpp"

namespace nd {

// What the library checks (docs/design.md §3b); nd_problem_set_guard sets them.
struct Guards {
  double energy = 2;         // E <= f (E^0 + max_k (W^k + W_obstacle^k)); 0: off
  // u_n - g0 <= f h_K eps*, eps* = sqrt(2 E_in / sum_K E_K |K|) the strain
  // of the energy put in (docs/design.md §3b.5); 0: off
  double penetration = 4;
  // the balance L = E_Theta - W - W_obstacle - W_prescribed - W_geometry +
  // D_damping + D_friction (Theta < 0: with min(E, E_Theta) for E_Theta;
  // in contact, Theta > 0: without the penalty's energy) may rise above its
  // lowest value out of contact by at most tol max(E^0 + max W, max_k E^k)
  // (docs/design.md §3b); 0: off
  double balance = 0.05;
  bool critical_timestep = true, unstable_scheme = true, coercivity = true, initial_penetration = true;
};

// eps* f of the guard's test u_n - g0 <= eps* f h_K at a state with this
// guard state: 0 when the guard is off or no energy was put in (then no
// point may sink at all)
double penetration_limit(const Discretization &d, const Guards &g, const GuardState &s);

// At t^0: the initial penetration (beyond round-off, 1e-10 h_K) and the
// energy reference E^0 (p: s's products). Throws ND_ERR_PENETRATION.
void guard_initial_state(const Discretization &d, const Guards &g, State &s, const Products &p);

// After a step old -> next: penetration deeper than penetration_limit times
// h_K (ND_ERR_PENETRATION); mechanical energy above f (E^0 + max_k (W^k + W_obstacle^k))
// (ND_ERR_ENERGY_GROWTH) or not finite (ND_ERR_NONFINITE_STATE), evaluated
// at every step: a sparser schedule (when |U| or |V| grew by 10 %, and every
// 16 steps) let the stability suite accept steps up to x2.4 past the limit.
// Updates next.guard. p: next's products (time/products.hpp).
// balance: whether the scheme's energy is E_Theta (every scheme but
// generalized-alpha, whose end states' E oscillates while it damps: the
// energy-balance guard then leaves it to the factor guard)
void guard_step(const Discretization &d, const Guards &g, const State &old, State &next, const Products &p,
                bool balance = true);

}  // namespace nd
