// Prescribed motion (docs/design.md §10.5) in the operators: the coupling of
// the free rows to the moving clamped DOFs (the lifting, -A_fc U_c in the
// step's equation, made of M and K's clamped columns), the clamped rows' own
// block for the reactions, and the clamped DOFs' part of the energy.
#pragma once
#include <vector>

#include "solve/operators.hpp"
#include "time/prescribed.hpp"

namespace nd {

// r -= scale (M_fc Abar_c + K_fc Ubar_c + C_fc Vbar_c) on the free rows (a
// lumped mass couples none of them to a clamped DOF; C_fc with damping and m.V).
void subtract_clamped_coupling(const Discretization &d, const ClampedMean &m, double scale, double *r);

// R += M_cc Abar_c + K_cc Ubar_c + C_cc Vbar_c: the clamped rows' terms in their own DOFs.
void add_clamped_block(const Discretization &d, const ClampedMean &m, std::vector<double> &R);

// The damping's work over a step in the terms that read a clamped DOF,
// dU_f . C_fc Vbar_c + dU_c . (C_cf Vbar_f + C_cc Vbar_c): with dU_f . C_ff
// Vbar_f, the whole body's dU . C Vbar (docs/design.md §10.5).
double clamped_damping_work(const Discretization &d, const ClampedMean &m, const double *dU_f, const double *Vbar_f,
                            const std::vector<double> &dU_c);

// kinetic += 2 V_c.(M_cf V_f) + V_c.M_cc V_c and strain likewise with K and
// U: the whole body's V.MV and U.KU from the free DOFs' (nothing without motion).
void add_clamped_energy(const Discretization &d, const State &s, double &kinetic, double &strain);

// Prescribed motion needs whole operators (not split over ranks), a state
// held whole, no massless DOFs with an explicit scheme, and contact points
// whose rows read no clamped DOF that moves: else ND_ERR_STATE naming it.
void require_motion_supported(const Discretization &d, const State &next, bool distributed, bool explicit_scheme);

}  // namespace nd
