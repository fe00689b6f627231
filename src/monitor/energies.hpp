// The monitors of the analysis (docs/design.md §2): energies, contact pressure and
// contact statistics of a state. They read the discretization and the state
// and change neither, except sum_points, with which a step leaves its sums
// in the products of the state it makes. Each takes the state's products p
// (a cache held beside it, time/products.hpp): read when current for d,
// else the same values are computed from the state (the same bits).
#pragma once
#include <vector>

#include "solve/operators.hpp"
#include "solve/products.hpp"
#include "time/state.hpp"

namespace nd {

// The step's sums over the points (PointValues::sums) of s, from its
// products' P_q and u_n - g0 and its phi: each rank adds its own points and
// the ranks' sums are added rank after rank (collective with several
// ranks). Also adds the obstacle's work, sum_q dW[q], to s.W_obstacle.
void sum_points(const Discretization &d, State &s, Products &p, const std::vector<double> &dW);
// E = 1/2 V'MV + 1/2 U'KU (the sums of p when valid: the same bits)
double mechanical_energy(const Discretization &d, const State &s, const Products &p);
// R = 1/2 sum_q w_q (gamma_q (s_q.U)^2 - [P_q]_+^2/gamma_q)
double nitsche_energy(const Discretization &d, const State &s, const Products &p);
// sum_q w_q [P_q]_+/gamma_q
double contact_force(const Discretization &d, const State &s, const Products &p);
// sum_q w_q phi_q/gamma_q with the contact term phi_q the step applied (before a step: the force)
double contact_force_applied(const Discretization &d, const State &s, const Products &p);
int64_t active_points(const Discretization &d, const State &s, const Products &p);
// max_q (u_n - g0)_+
double max_penetration(const Discretization &d, const State &s, const Products &p);
// The sums of the points of one contact region alone (a pair's: its slave
// region): R's part, the force, the applied force, the active points and
// the deepest penetration (PointSums), from the state's P_q as the whole's
PointSums region_sums(const Discretization &d, const State &s, const Products &p, int region);
// lambda_q = -[P_q]_+/gamma_q
std::vector<double> contact_pressure(const Discretization &d, const State &s, const Products &p);

}  // namespace nd
