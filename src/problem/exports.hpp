// Operators out (docs/design.md §10.4): what a host code that keeps its own
// time loop reads of a problem — the matrices on the free DOFs, the DOF
// map, the load at t^n, the cells' FE nodes — and the momenta of the state.
// Reads only: the problem's definition and state are not changed (the
// discretization and the initial state are built if not yet there, as any
// query does).
#pragma once
#include <cstdint>
#include <vector>

#include "linalg/csr.hpp"
#include "problem/problem.hpp"

namespace nd {

// The discretization, refused (ND_ERR_STATE, naming `what`) when its
// operators hold this rank's rows only (split over several ranks).
const Discretization &whole_operators(Problem &p, const char *what);

// An ND_MATRIX_* operator on the free DOFs, on the pattern the operators
// share (ND_MATRIX_LUMPED_MASS: its diagonal only). ND_MATRIX_STEP needs a
// complete problem with an implicit scheme (ND_ERR_STATE for an explicit one).
Csr exported_matrix(Problem &p, int which);
// For each free DOF its FE node and component (either may be null).
void exported_dof_map(Problem &p, int64_t *node, int *component);
// F^n on the free DOFs (zeros when there is no load).
std::vector<double> exported_load(Problem &p);

// ND_MOMENTUM_* and ND_ANGULAR_MOMENTUM_* (nd_get_scalar): whether key is
// one, and its value at the state: sums of M V over every row, clamped rows
// included (V vanishes there, not M's coupling to them), and of x_i x (M V)_i
// with x_i the reference position of DOF i's node.
bool is_momentum_key(int key);
double momentum(Problem &p, int key);

}  // namespace nd
