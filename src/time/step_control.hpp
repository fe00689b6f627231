// Adaptive time steps (docs/design.md §10.8): which step sizes a run may
// take, the error a step is judged by, and the next size. The schemes are
// one-step schemes: a step of any size starts from the state alone, so the
// control lives outside them (problem/adaptive_step.cpp drives it).
#pragma once
#include <vector>

namespace nd {

struct State;

// nd_problem_set_adaptive_timestep; tolerance 0: off (fixed steps)
struct AdaptiveOptions {
  double tolerance = 0, tau_min = 0, tau_max = 0;
  bool on() const { return tolerance > 0; }
};

// What the control carries from step to step (State::control; empty, all
// zero, with fixed steps): the size the next step tries, the last accepted
// step's size and its error ratio, the largest |U|_inf seen (the scale of
// the truncation error), and the last step's mean acceleration
// (V^{n+1} - V^n)/tau, from which the next estimates u'''.
struct StepControl {
  double tau_next = 0, tau_last = 0, ratio = 0, scale = 0;
  // the accepted steps left that may not grow (kHoldSteps after a step that
  // needed a retry): a size that just failed is not tried again at once
  double hold = 0;
  std::vector<double> a_mean;
};
constexpr int kHoldSteps = 8;

// Sizes are tau_max / 2^k (and tau_min): a run returns to the same few
// sizes, whose step operators' factors the problem keeps (kKeptSizes), and
// alternating between neighbours does not refactorize each time. The
// largest size of the ladder at most x, and not below tau_min.
double ladder_below(const AdaptiveOptions &o, double x);
constexpr int kKeptSizes = 3;

// The error of the step old -> next of size tau, relative to the
// tolerance (<= 1: accepted), the larger of
//  - the local truncation error of a second-order one-step scheme,
//    tau^3 |u'''| / 12 with u''' from the two last mean accelerations,
//    against tolerance times the largest |U|_inf seen (0 at a first step);
//  - the step's gain of the energy balance (balance_gain, >= 0) against
//    tolerance times the energy in motion `energy`.
// Fills next.control's a_mean and scale (tau_next is the caller's).
double step_error(const AdaptiveOptions &o, const State &old, State &next, double tau, double balance_gain,
                  double energy);

// The size after an accepted step with this error ratio (at most twice
// tau; the ladder's), and the size to retry a rejected one with (at most
// half of tau).
double size_after_accepted(const AdaptiveOptions &o, double tau, double ratio);
double size_after_rejected(const AdaptiveOptions &o, double tau, double ratio);

// Where a step that makes the first points active (none was) should have
// ended: the fraction s of the step (0 < s < 1) at which the first of them
// touched, u_n - g0 moving from un_old at the rate `rate` of t^n (a_q.V^n)
// over the step of size tau: exact for a rigid flight at constant
// velocity (the solved state is not: the contact already pushed there).
// 1 when no point became active, or one touched at the step's very start
// or end. P_old, P_new: P_q at t^n and t^{n+1} (> 0: active), their first
// un_old.size() entries (with friction the tangential values follow).
double first_touch(const std::vector<double> &P_old, const std::vector<double> &P_new,
                   const std::vector<double> &un_old, const std::vector<double> &rate, double tau);

}  // namespace nd
