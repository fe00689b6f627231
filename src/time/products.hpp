// The step's products of a state: M U, M V, M A, K U, the energy's sums and
// its points' P_q. A cache, held beside the state (Problem::products_; a
// step's new ones beside its new state), never in State nor in a
// checkpoint: the same pass over the same U, V, A gives the same bits, so a
// change here changes no state format (solve/products.hpp makes them).
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

namespace nd {

struct Share;  // parallel/share.hpp

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
// guard reads the sums. Valid for the discretization whose id `of` holds
// (0: not computed), of the state they are held beside; whoever writes that
// state's U, V or A in place, or replaces it, resets them.
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

// The same for products (every field as Products{} has it, except that
// M U, M V, M A and K U keep their sizes too: their values are not read
// again, `of` = 0 says so, and the next pass writes every entry without
// filling them with zeros first): those of a state whose U changes again
// keep their memory for its next pass
Products reuse_storage(Products &&used);
// v as PointValues{} has it, its vectors' memory kept
void clear_keeping_memory(PointValues &v);

}  // namespace nd
