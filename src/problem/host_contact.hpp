// Contact on a host's operators (docs/design.md §10.4): the Nitsche term of
// §2 at a displacement a host code gives on the free DOFs — N(U), its
// generalized Jacobian N'(U) and the monitors' contact values — with the
// obstacle where it is at the problem's current time t^n and the law [P]_+
// (no scheme's time-discrete form); or, in the step form (U_old given: the
// host's U^n), the law by the problem's scheme's time rule over the step
// from P_q(U_old) to P_q(U) (TimeRule: the hybrid scheme's Phi_q,
// generalized-alpha's shifted point), both ends with the obstacle at t^n.
// A query: the problem's state, its products and its counters are not changed.
#pragma once
#include "linalg/csr.hpp"
#include "problem/problem.hpp"

namespace nd {

// r = N(U) (n_free values, overwritten); with U_old, the step form
void host_contact_residual(Problem &p, const double *U, const double *U_old, double *r);
// N'(U) on the pattern of every contact point's rows (a_q's index list
// squared, over all points: the same at every U, zeros where a point is
// inactive); with U null the pattern alone (values zero); with U_old the
// step form's generalized Jacobian in U
Csr host_contact_tangent(Problem &p, const double *U, const double *U_old);
// The contact values at U, in this order (the first `count`, 1 to
// kHostContactValues): the resultant sum_q w_q [P_q]_+/gamma_q, the active
// points, the Nitsche energy R, max_q (u_n - g0)_+ (those of nd_get_scalar
// for the state, here at U)
constexpr int kHostContactValues = 4;
void host_contact_values(Problem &p, const double *U, int count, double *values);

}  // namespace nd
