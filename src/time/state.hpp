// The state at t^n, in free DOFs: what a step reads and the next step writes.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "time/step_control.hpp"

namespace nd {

// What the energy guard carries from step to step (src/monitor/guards.hpp).
struct GuardState {
  double E0 = 0;      // mechanical energy at t^0
  double budget = 0;  // E^0 + max_k (W^k + W_obstacle^k): the most energy loads and obstacle put in
  // The energy-balance guard (docs/design.md §3b): the balance
  // L = E_Theta - W - W_obstacle - W_prescribed - W_geometry + D_damping +
  // D_friction - exchange at the last state it was evaluated at (NaN: none yet), its
  // lowest value so far, and the largest mechanical energy seen. Not in the
  // checkpoint: a resumed run starts them again at its first contact step.
  double balance = std::numeric_limits<double>::quiet_NaN();
  double balance_low = std::numeric_limits<double>::quiet_NaN();
  double E_top = 0;
  // the contact term of Theorem 2.8 the steps put in since t = 0,
  // (Theta - 1) sum_q (w_q/gamma_q) phi_q a_q.(U^{n+1} - U^n) with the
  // contact term phi_q each step applied (0 with Theta = 1)
  double exchange = 0;
  bool in_contact = false;  // the last state the balance was evaluated at had a point in contact
};

// The history that fixes the bits of the Newton tangent's updated factor
// (fast/tangent_updown.cpp): a base set of contact points with their
// coefficients (the factorization of A + sum_q d_q p_q p_q^T), then the rank
// updates applied to it since, in order. Replaying it on A gives the factor
// bit for bit, so a run resumed from a checkpoint, or a step retried after a
// failed one, is bitwise the uninterrupted run. Layout:
//   i = [nb, q_1 .. q_nb, then per update: +-m (+ update, - downdate), q_1 .. q_m]
//   x = [d_1 .. d_nb, then per update its m coefficients c_j (column sqrt(c_j) p_q)]
// Empty: no such factor.
struct TangentLog {
  std::vector<int64_t> i;
  std::vector<double> x;
  bool operator==(const TangentLog &o) const { return i == o.i && x == o.x; }
  bool operator!=(const TangentLog &o) const { return !(*this == o); }
};

struct State {
  double t = 0;
  int64_t n = 0;
  // t = t_ref + (n - n_ref) tau_ref: times as products, not running sums
  // (8e-06, not 7.9999999999999962e-06), from the last change of tau
  double t_ref = 0, tau_ref = 0;
  int64_t n_ref = 0;
  std::vector<double> U, V, A;
  // U, V and A are right only on the rows the steps read (Integrator::held:
  // a rank's rows, their columns, the contact points' and the clamped rows'
  // DOFs), elsewhere any value (NaN): a distributed state
  // (Definition::distributed_state). Problem::complete_state gathers the rest.
  bool partial = false;
  // the load F^n of the last step (null or empty: no load), immutable: the
  // problem's load and the states of the steps it does not change share one
  // array, not a copy each
  std::shared_ptr<const std::vector<double>> F;
  const std::vector<double> &load() const {
    static const std::vector<double> none;
    return F ? *F : none;
  }
  std::vector<double> F_fixed;  // its part on the clamped DOFs (ClampedRows order)
  bool A_valid = false;   // schemes without acceleration (hybrid) compute it on demand
  double W = 0;
  // the obstacle at t^n: its gaps g_q (empty: the assembled ones) and the work
  // it has done on the body since t = 0 (a moving plane pushes)
  std::vector<double> gap;
  // curved obstacles (contact/obstacles.hpp), else empty: each point's frozen
  // normal nu (3 per point), which its rows hold, and where the planes and
  // obstacles were at t^n (contact/obstacles.hpp: positions)
  std::vector<double> normal, positions;
  // contact pairs (contact/pairing.hpp), else empty: each point's frozen
  // pairing (kPairingValues per point), which its rows hold with `normal`
  std::vector<double> pairing;
  double W_obstacle = 0;
  // curved obstacles: what the steps' re-linearisations (gaps measured
  // anew from the current positions, normals refreshed) changed E_Theta by
  // at the states they started from, since t = 0: -Theta (R_new - R_old)
  // at U^n (docs/design.md §10.1), so that E_Theta - W - W_obstacle -
  // W_geometry is the hybrid scheme's non-increasing ledger with them
  double W_geometry = 0;
  // the energy the Rayleigh damping dissipated since t = 0: per step
  // dU . C Vbar, C V taken where the scheme takes it (docs/design.md §10.5)
  double D_damping = 0;
  // prescribed motion (docs/design.md §10.5): the clamped DOFs' displacement,
  // velocity and acceleration at t^n (ClampedRows order; empty: at rest at 0,
  // no motion prescribed yet), and the work the supports have done on the
  // body since t = 0 moving them
  std::vector<double> Uc, Vc, Ac;
  double W_prescribed = 0;
  // the reactions on the clamped DOFs of the step that led here (docs/design.md §8;
  // empty: not computed yet, e.g. at t^0)
  std::vector<double> reaction;
  // the contact term phi_q that step applied (TimeScheme::mean_weight's
  // equation; empty: none yet): the applied pressure is -phi_q/gamma_q
  std::vector<double> phi;
  // Friction (docs/design.md §10.2; empty without): each point's slip
  // reference, m - 1 values (the tangential values' gaps: P_t = ta.U -
  // gamma ts.U - slip), and the tangential values phi_t the step applied;
  // the energy friction dissipated since t = 0, and the points in contact
  // sliding and sticking at the step that led here
  std::vector<double> slip, phi_t;
  double D_friction = 0;
  int64_t sliding = 0, sticking = 0;
  // the same three per contact region (solve/friction.hpp: friction_regions'
  // order): its D_f, sliding and sticking points (a count as a double, exact)
  std::vector<double> by_region;
  int last_iterations = 0;
  int64_t total_iterations = 0;
  GuardState guard;
  // adaptive time steps (time/step_control.hpp): all zero, empty, with fixed steps
  StepControl control;
  TangentLog tangent_log;
  // (no products: the step's products of a state are a cache held beside
  // it, time/products.hpp, never in it nor in a checkpoint)
};

// A new state (every field as State{} has it) that holds `used`'s vectors'
// memory, emptied: their values are not read again, their allocations are
// reused.
State reuse_storage(State &&used);

}  // namespace nd
