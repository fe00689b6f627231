// Forces out (docs/design.md §8): the nodal contact force and the reactions on the
// clamped DOFs. Both cover every DOF of the space, clamped ones included.
#pragma once
#include <vector>

#include "problem/definition.hpp"
#include "problem/discretization.hpp"
#include "time/state.hpp"

namespace nd {

// The clamped DOFs' rows of K and of the consistent mass, on the free
// columns (U and A vanish on the clamped DOFs): n = number of clamped DOFs.
// contact_nodes (mass redistribution, nullptr: off): the mass is the
// redistributed one, as in the free rows (assembly/bulk.hpp).
ClampedRows clamped_rows(const Space &s, const DofMap &dofs, const CellMaterials &mat,
                         const std::vector<char> *contact_nodes = nullptr);

// The load on the clamped DOFs (body force, tractions, nodal forces), in
// ClampedRows::dofs order; empty when there is no load.
std::vector<double> clamped_load(const Space &s, const ClampedRows &rows, const Definition &def);

// (1-a) x_new + a x_old; an empty vector counts as zeros (empty if both are)
std::vector<double> step_mean(const std::vector<double> &x_new, const std::vector<double> &x_old, double a);

// The residual of the clamped rows of the equation a step satisfies
// (TimeScheme::mean_weight): R = M_DF Abar + K_Theta,DF Ubar + Nbar_D - Fbar_D,
// with Nbar = sum_q (w_q/gamma_q) phi_q b_q. phi: the step's contact term per
// point; phi_t (friction, m - 1 per point; null or empty: none) its tangential values.
// With damping, + C_DF Vbar (Vbar where the scheme takes C V, docs/design.md §10.5).
std::vector<double> clamped_residual(const Discretization &d, const std::vector<double> &Abar,
                                     const std::vector<double> &Ubar, const std::vector<double> &phi,
                                     const std::vector<double> &Fbar_D, const std::vector<double> *phi_t = nullptr,
                                     const std::vector<double> *Vbar = nullptr);

// sum_q w_q lambda_q a_q over all DOFs (n_dofs values): the force the
// obstacle exerts on the body at the state's time. With `points` (a
// distributed state's, HeldPoints) from those only: right, with the same
// bits, at the DOFs whose every point is among them (a rank's own nodes).
void contact_force_field(const Discretization &d, const State &s, double *full,
                         const std::vector<int64_t> *points = nullptr);

}  // namespace nd
