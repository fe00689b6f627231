// The friction state of a step (docs/design.md §10.2): each contact point's
// slip reference (State::slip, m - 1 values: the tangential values' gaps),
// updated as a return mapping at the end of every step, and the energy the
// friction dissipated. With P_t the tangential values at the step's point
// Y_t (the end of the step; generalized-alpha: its shifted point) and phi_t
// = Pi_{B(0,r)}(Y_t) what the step applied,
//   slip <- slip + (Y_t - phi_t)          (the new state's P_t at U^{n+1}: phi_t)
//   D_f  <- D_f + sum_q (w_q/gamma_q) phi_t . (Y_t - phi_t)   (>= 0: r (|Y_t| - r) or 0)
// A point free of the obstacle (r = 0) takes phi_t = 0: its reference
// follows the body, and it touches down without a stored traction.
#pragma once
#include <array>

#include "assembly/contact.hpp"
#include "contact/friction.hpp"
#include "solve/contact_law.hpp"
#include "solve/operators.hpp"
#include "time/state.hpp"

namespace nd {

// The contact regions in the order their points first appear (assemble_contact
// groups a region's points): the slots of State::by_region, 3 values each
std::vector<int> friction_regions(const ContactPoints &cp);

// s.slip such that the tangential values at s.U are 0 (no frictional
// traction stored: the initial state), for a problem with friction; else empty
void start_slip(const Discretization &d, State &s);

// to.slip for to.U such that its tangential values are from's at from.U:
// a state overwritten (nd_problem_set_state) keeps its frictional traction
void carry_slip(const Discretization &d, const State &from, State &to);

// The slip references for new rows at the same U (a re-pairing, docs/design.md
// §10.3 "Friction between bodies"): a point whose rows changed (its normal or
// pairing) keeps its tangential value vector sum_k P_t,k t_k at U, projected
// on its new tangent plane (|P_t| does not grow: the traction stays in the
// disk of the step that applied it); a point whose rows did not change keeps
// its references bit for bit. The change of R goes to W_geometry.
std::vector<double> transport_slip(const ContactPoints &from, const ContactPoints &to, const std::vector<double> &U,
                                   const std::vector<double> &slip);

// Friction against a moving obstacle (docs/design.md §10.2): slip is
// relative, so over a step each point's reference moves with the obstacle's
// tangential displacement there, t_qk . (x_o^{n+1} - x_o^n) for a point of
// a plane region (its plane's translation; a plane does not rotate). before:
// the state's positions (contact/obstacles.hpp: the planes' points first),
// now: the planes at t^{n+1}. Empty when no plane moved (or before has no
// positions): the references stay, bit for bit.
std::vector<double> obstacle_slip(const ContactPoints &cp, int dim, const std::vector<double> &before,
                                  const std::vector<ContactPlane> &now);

// The end of a step with friction: `law` the step's (its rule and P^n),
// P the values at U^{n+1} with the step's reference (next's products')
// (next.slip): phi_t, the new reference, D_f, the sliding and sticking
// points; then the new state's tangential values with the new reference
// (the bits a restart's products have). phi: the step's normal values.
// shift: the step's obstacle_slip (null: none); the tangential traction
// does the work -sum (w_q/gamma_q) phi_t . shift on the body, added to
// next.W_obstacle (the obstacle's velocity times the whole contact force).
void end_friction_step(const ContactLaw &law, const Discretization &d, const std::vector<double> &phi,
                       const std::vector<double> *shift, State &next, std::vector<double> &P);

// sum_q w_q lambda_t,q: the tangential contact force the last step applied
// (obstacle on body), lambda_t = -phi_t/gamma_q along the t_qk; zeros
// without friction or before a step. region >= 0: that region's points alone
std::array<double, 3> tangential_resultant(const Discretization &d, const State &s, int region = -1);

}  // namespace nd
