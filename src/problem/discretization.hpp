// The discretization (solve/operators.hpp) made from a definition: the DOF
// numbering, the operators M, K, K_Theta, the contact points with their rows,
// and the constant load. Built once; rebuilt only when an aspect it depends
// on changes.
#pragma once
#include <memory>
#include <vector>

#include "assembly/contact.hpp"
#include "fem/space.hpp"
#include "linalg/csr.hpp"
#include "linalg/factorization.hpp"
#include "linalg/node_blocks.hpp"
#include "parallel/ownership.hpp"
#include "problem/definition.hpp"
#include "solve/operators.hpp"
#include "time/state.hpp"

namespace nd {


// The automatic gamma0: this fraction of gamma0*/max(Theta, 1); with
// Theta <= 0 and the hybrid scheme, kAutomaticGamma0SkewHybrid of gamma0*
// (docs/design.md §3b.1: the energy the (Theta - 1) term of Theorem 2.8
// gains at impacts falls with gamma0 in that scheme; in Newmark's a stiffer
// penalty gains more, and the theta-scheme gains nothing).
constexpr double kAutomaticGamma0Fraction = 0.5;
constexpr double kAutomaticGamma0SkewHybrid = 0.02;
double automatic_gamma0_fraction(const Definition &def);

// With `own` (several ranks; null: one process) M, K and K_Theta hold the
// rows of own's nodes only, each entry with the bits of the whole operator's.
// frozen: the curved points' normals nu (3 per point, a state's), null: each
// the nearest obstacle's at its reference position, the obstacles as
// defined, unmoved (contact/obstacles.hpp);
// the automatic gamma0 is always from those (a refresh keeps it).
// pairing: with frozen, a pair's points' pairings (contact/pairing.hpp), the
// state's; null with frozen: none (no pair)
std::unique_ptr<Discretization> discretize(const Space &space, const Definition &def, Counters *counters,
                                           const Ownership *own = nullptr, const std::vector<double> *frozen = nullptr,
                                           const std::vector<double> *pairing = nullptr);
// The discretization `from` with other frozen normals (a refresh,
// contact/obstacles.hpp): its M, K, gamma0 and clamped rows, new contact
// rows and K_Theta; the same as discretize(..., &frozen) would make.
std::unique_ptr<Discretization> with_normals(const Space &space, const Definition &def, const Discretization &from,
                                             const std::vector<double> &frozen,
                                             const std::vector<double> *pairing = nullptr);
// Where the unknowns sit (g.x, g.component), which GAMG's near-null space
// reads: for every unknown, or with g.own_rows_only for the rows
// [g.row_begin, g.row_end) of g.row_of's numbering only (no array n long).
void locate_unknowns(const Space &space, const DofMap &dofs, DofGeometry &g);
// Can the operators hold a rank's rows only (discretize's `own`)? With a
// distributed solver on several ranks (which reads no other rows), and
// neither mass lumping nor redistribution (whose diagonal and massless rows
// the explicit steps read whole).
bool splits_rows(const Definition &def);

// The material of each cell: the definition's default and its cell regions'
// materials over the mesh's cell regions (one material: no per-cell index)
CellMaterials materials_of(const Space &space, const Definition &def);
// A rank's part of the step matrix A = c M + K_Theta:
// the contributions of its own cells, and of the contact points on them, on
// the pattern of those cells (all rows, most of them empty). Summed over the
// ranks it is A; a distributed solver assembles A from the parts
// (Factorization::factor_parts).
Csr assemble_own_step_matrix(const Space &space, const Discretization &d, const Definition &def, const Ownership &own,
                             double c);
// With Theta > 0 and Theta gamma0 above the element bound, the exact check:
// K_Theta + delta M must factor as positive definite (ND_ERR_NOT_COERCIVE).
// A_factor (may be null): the step matrix's factor, whose ordering the
// check's factorization reuses (the same pattern: no second METIS run)
void check_coercivity(Discretization &d, int solver, const Factorization *A_factor = nullptr);
// The constant load on the free DOFs: body force and tractions (empty: none).
std::vector<double> constant_load(const Space &space, const Discretization &d, const Definition &def);

}  // namespace nd
