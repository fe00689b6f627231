// The state at t^n, in free DOFs: what a step reads and the next step writes.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "time/step_control.hpp"

namespace nd {

struct Share;  // parallel/share.hpp

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

// P_q(U) and u_n - g0 = a_q.U - g_q at every contact point of a state, with
// its gaps, from one pass over the points (ContactLaw::P_all).
// With a distributed state on the refactoring tangent (Integrator::points)
// they are right only at the points a rank holds, NaN elsewhere (partial),
// and the monitors' sums over the points are those of the step, each rank's
// own points added rank after rank (summed): what a query on one rank reads.
struct PointSums {
  double nitsche = 0;        // sum_q w_q (gamma_q (s_q.U)^2 - [P_q]_+^2/gamma_q) / 2
  double force = 0;          // sum_q w_q [P_q]_+/gamma_q
  double force_applied = 0;  // sum_q w_q phi_q/gamma_q
  double active = 0;         // the points with P_q > 0
  double penetration = 0;    // max_q (u_n - g0)_+
};
// Where a state's points were last evaluated, for the states after it whose
// own were not: a step shown contact-free by ContactLaw::certainly_free's
// bound from here (every law and slope zero, so phi = 0) leaves its points
// unevaluated and this in their place, and the next step's bound and the
// penetration guard's (monitor/guards.cpp) are made from it. U whole, P_q
// and u_n - g0 there, its gaps (empty: the assembled ones).
struct PointReference {
  std::vector<double> U, P, un, gap;
  // The bounds' tests over every point made once, for the gaps the
  // reference has (set_reference_reach, solve/contact_law.hpp): from here a
  // check at the same gaps (a static obstacle) reads only U's reach.
  // -infinity: not made. within_reach is for the penetration limit within_limit.
  double free_reach = -std::numeric_limits<double>::infinity();
  double within_reach = -std::numeric_limits<double>::infinity(), within_limit = 0;
};
struct PointValues {
  std::vector<double> P, un;
  bool partial = false;
  bool summed = false;
  PointSums sums;
  // non-null: P and un not evaluated (empty), the state contact-free by
  // the bound from *ref; a reader evaluates them (state_points)
  std::shared_ptr<const PointReference> ref;
};

// M U, M V, M A (when A is valid), K U and the two sums of the mechanical
// energy (V.MV, U.KU) of one state, from one fused pass over the pattern M
// and K share, and P_q(U) from one pass over the contact points
// (compute_products, src/solve/products.hpp). The next step's
// right-hand side is formed from them (no product of its own) and the energy
// guard reads the sums. A cache, not checkpointed: the same pass over the
// same U, V, A gives the same bits after a restart. Valid for the
// discretization whose id `of` holds (0: not computed); whoever writes U, V
// or A in place resets it.
struct Products {
  uint64_t of = 0;
  // With the operators split over the ranks (Discretization::rows_split) the
  // products stay on this rank's rows, rows[k] the row of entry k: every
  // solve of a right-hand side made from them reads those rows only, so they
  // are neither gathered nor held whole (null: all n rows, entry i row i).
  std::shared_ptr<const Share> rows;
  int64_t n = 0;                       // the rows of the whole vectors
  std::vector<double> MU, MV, MA, KU;  // MA empty when A is not valid
  double kinetic = 0, strain = 0;      // V.MV and U.KU
  // P_q(U) with the state's gaps (the next step's P^n) and u_n - g0 (the
  // penetration guard's), from one pass over the points
  PointValues points;
  // Which pass made these products (unique in the process: products_of_state;
  // 0: none), and the sums over the points a query made at them
  // (state_sums): the state's next queries read those instead of passing
  // over every point again (a coupling code reads the contact force after
  // every step). queried_nitsche: the Nitsche energy's sum among them.
  uint64_t pass = 0;
  mutable uint64_t queried_pass = 0;
  mutable bool queried_nitsche = false;
  mutable PointSums queried;
};

// The history that fixes the bits of the Newton tangent's updated factor
// (solve/tangent_updown.cpp): a base set of contact points with their
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
  int last_iterations = 0;
  int64_t total_iterations = 0;
  GuardState guard;
  // adaptive time steps (time/step_control.hpp): all zero, empty, with fixed steps
  StepControl control;
  TangentLog tangent_log;
  Products products;
};

// A new state (every field as State{} has it) that holds `used`'s vectors'
// memory, emptied: their values are not read again, their allocations are
// reused.
State reuse_storage(State &&used);
// The same for products (every field as Products{} has it, except that
// M U, M V, M A and K U keep their sizes too: their values are not read
// again, `of` = 0 says so, and the next pass writes every entry without
// filling them with zeros first): those of a state whose U changes again
// keep their memory for its next pass
Products reuse_storage(Products &&used);
// v as PointValues{} has it, its vectors' memory kept
void clear_keeping_memory(PointValues &v);

}  // namespace nd
