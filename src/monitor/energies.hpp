// The monitors of the analysis (DESIGN §2): energies, contact pressure and
// contact statistics of a state. They read the discretization and the state
// and change neither.
#pragma once
#include <vector>

#include "problem/discretization.hpp"
#include "solve/contact_law.hpp"
#include "time/state.hpp"

namespace nd {

// [P]_+ with the obstacle where it is at the state's time
ContactLaw state_contact_law(const Discretization &d, const State &s);
// s.products: M U, M V, M A (when s.A_valid), K U and the energy's sums, in
// one pass over the pattern M and K share (one ND_STAT_SPMV), and P_q(U)
// (one contact evaluation, none without contact points; none with `known`:
// P_q(s.U) and u_n - g0 that the step evaluated there with the state's gaps,
// moved in: the same bits)
void compute_products(const Discretization &d, State &s, PointValues *known = nullptr);
// s.products if they are valid for d, else the same pass into `scratch`
const Products &products_of(const Discretization &d, const State &s, Products &scratch);
// E = 1/2 V'MV + 1/2 U'KU (the sums of s.products when valid: the same bits)
double mechanical_energy(const Discretization &d, const State &s);
// R = 1/2 sum_q w_q (gamma_q (s_q.U)^2 - [P_q]_+^2/gamma_q)
double nitsche_energy(const Discretization &d, const State &s);
// sum_q w_q [P_q]_+/gamma_q
double contact_force(const Discretization &d, const State &s);
int64_t active_points(const Discretization &d, const State &s);
// P_q(U) and u_n - g0 of the state at every point: its products' (in a
// step, each evaluated by its point's rank) when they are valid, else
// evaluated here into `scratch` (counted in `counters` as a pass over the
// points); the same bits either way. Not collective: a query.
const PointValues &state_points(const Discretization &d, const State &s, PointValues &scratch,
                                Counters *counters = nullptr);
// max_q (u_n - g0)_+
double max_penetration(const Discretization &d, const State &s);
// lambda_q = -[P_q]_+/gamma_q
std::vector<double> contact_pressure(const Discretization &d, const State &s);

}  // namespace nd
