// The step's products of a state (time/products.hpp): M U, M V, M A, K U and
// the energy's sums in one pass, and P_q(U) at the contact points. A step
// makes them for the state it leaves, and the next step's right-hand side
// and the monitors (monitor/energies.hpp) read them.
#pragma once
#include <memory>

#include "solve/contact_law.hpp"
#include "solve/operators.hpp"
#include "time/products.hpp"
#include "time/state.hpp"

namespace nd {

// [P]_+ with the obstacle where it is at the state's time
ContactLaw state_contact_law(const Discretization &d, const State &s);
// p, the products of s: M U, M V, M A (when s.A_valid), K U and the energy's sums, in
// one pass over the pattern M and K share (one ND_STAT_SPMV), and P_q(U)
// (one contact evaluation, none without contact points; none with `known`:
// P_q(s.U) and u_n - g0 that the step evaluated there with the state's gaps,
// moved in: the same bits)
// With `held` (a distributed state's points, HeldPoints) P_q(U) is
// evaluated at those points only (PointValues::partial), by this rank.
void compute_products(const Discretization &d, const State &s, Products &p, PointValues *known = nullptr,
                      const HeldPoints *held = nullptr);
// The same for a state shown contact-free by the bound from `ref` (its
// points not evaluated: PointValues::ref)
void compute_products_bounded(const Discretization &d, const State &s, Products &p,
                              std::shared_ptr<const PointReference> ref);
// The reference of a state's points for the bound of the steps after it:
// where they were evaluated, the state itself (its U, points and gaps,
// copied), else its own reference. Null if its points are not every
// point's (a distributed state's), or not there. A new one has its bounds'
// tests made (set_reference_reach) for the penetration guard's limit.
std::shared_ptr<const PointReference> point_reference(const Discretization &d, const State &s, const Products &p,
                                                      double penetration_limit);
// Whether p (s's products) are d's and, where a reader takes M A (with_acceleration)
// and s has A, hold it: a query of the hybrid scheme's acceleration makes A
// without touching U or V and drops M A only (Discretization::
// equilibrium_acceleration), so that the next hybrid step, which reads no
// M A, does not pass over M and K again
bool products_current(const Discretization &d, const State &s, const Products &p, bool with_acceleration);
// p (s's products) if they are current for d, else the same pass into `scratch`
const Products &products_of(const Discretization &d, const State &s, const Products &p, Products &scratch,
                            bool with_acceleration = false);
// P_q(U) and u_n - g0 of the state at every point: its products p's (in a
// step, each evaluated by its point's rank) when they are valid and were
// evaluated, else evaluated here into `scratch` (counted in `counters` as a
// pass over the points); the same bits either way. Not collective: a query.
const PointValues &state_points(const Discretization &d, const State &s, const Products &p, PointValues &scratch,
                                Counters *counters = nullptr);
// The energy's sums of s (Products::kinetic, strain) by the same pass with
// nothing stored (monitor/energies.hpp: the energy of a state without products)
Products product_sums(const Discretization &d, const State &s);

}  // namespace nd
