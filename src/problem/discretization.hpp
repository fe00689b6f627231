// The discretization derived from a definition: the DOF numbering, the
// operators M, K, K_Theta, the contact points with their rows, and the
// constant load. Built once; rebuilt only when an aspect it depends on changes.
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
#include "time/state.hpp"

namespace nd {

// The clamped DOFs and their rows of K and of the consistent mass on the free
// columns (problem/forces.hpp): what the reactions need.
struct ClampedRows {
  std::vector<int64_t> dofs;  // full DOF indices, in row order
  Csr K, M;
};

struct Discretization {
  Discretization(DofMap d, bool lump);
  // unique per discretization made in this process: what a State's Products are valid for
  const uint64_t id;
  DofMap dofs;
  Csr M;  // the scheme's mass: consistent, or lumped (diagonal) on the same pattern
  bool lumped;
  std::vector<double> M_lumped;  // the lumped diagonal (empty when consistent)
  // mass redistribution: 1 for the free DOFs of the contact nodes, whose rows
  // and columns of M are zero (empty when off)
  std::vector<char> massless;
  Csr K, K_theta;                // K_Theta = K - Theta sum_q w_q gamma_q s_q^T s_q
  ContactPoints contact;
  std::shared_ptr<const PointLaw> contact_law;  // the contact law (the definition's), never null
  double theta = 1;
  double gamma0 = 0;        // in use (chosen here when the definition asks for it)
  double gamma0_limit = 0;  // gamma0* at Theta = 1 (docs/design.md §3b.1); +inf without contact
  bool coercive = false;    // K_Theta checked positive semi-definite
  double omega_max = 0;     // the explicit schemes' highest frequency, once estimated
  std::unique_ptr<Factorization> M_factor;  // consistent mass, factored on first use
  std::unique_ptr<ClampedRows> clamped;     // when there are clamped DOFs
  Counters *counters = nullptr;             // the problem's (ND_STAT_*)
  DofGeometry geometry;                     // the solvers' ranks and rows; the unknowns' coordinates for AMG
  // with several ranks: which rank computes which row of the step's products
  // (the rank of its node; monitor/energies.cpp); null: this process, all
  std::shared_ptr<const Share> rows;
  // K and M by nodes, for the products pass (made when the rows are not
  // split; null where they have no such form: linalg/node_blocks.hpp)
  std::shared_ptr<const NodeBlocks> node_blocks;
  // K_Theta and M so, for the explicit steps' K_Theta U (made at the first)
  std::shared_ptr<const NodeBlocks> k_theta_blocks;
  // M, K and K_Theta hold this rank's rows only, and
  // store no others (Csr::part: their row pointers fall with the ranks), so
  // every product with them is the ranks' rows, gathered: collective
  // (own_rows_of)
  bool rows_split = false;
  // With split rows: the columns this rank's rows of M and K read (they
  // share a pattern), ascending, and for each entry of K (those rows'
  // entries, row after row), its column's place among them. The products
  // pass packs U, V, A at these columns only, not n long
  // (monitor/energies.cpp): 4 bytes per entry of the rank's rows (falling
  // with P) for four whole-length arrays. Made on first use; dropped with
  // `rows`.
  struct OwnColumns {
    std::vector<int64_t> cols;
    std::vector<int32_t> place;  // (half the memory of a column index)
  };
  const OwnColumns &own_columns() const;
  mutable std::shared_ptr<const OwnColumns> own_columns_;

  // x <- M^-1 x; on massless DOFs the result is 0 (M restricted to the others).
  // once: the caller expects no more solves with M (the initial acceleration
  // of an implicit scheme); then, with no factor yet, a large M held whole
  // is solved by conjugate gradients (linalg/pcg.hpp) instead of being
  // factored and its factor kept, whatever the solver: a factor of M, as
  // large as A's, would stay for the whole run and raise its peak memory.
  void mass_solve(double *x, int solver, bool once = false);
  // M A = F - K_Theta U - N(U): Remark 3.2 at t^0, and every explicit step
  // (once: as in mass_solve). in_step: called by every rank at the same point
  // of a set-up or a step, so each may compute its own rows of K_Theta U and
  // evaluate its own contact points, then gather (parallel/share.hpp); a
  // query computes them all on its own. at_U (if given): the pass's P_q and
  // u_n - g0, for compute_products.
  void equilibrium_acceleration(State &s, int solver, bool once = true, bool in_step = false,
                                PointValues *at_U = nullptr);
};

// The automatic gamma0: this fraction of gamma0*/max(Theta, 1).
constexpr double kAutomaticGamma0Fraction = 0.5;

// With `own` (several ranks; null: one process) M, K and K_Theta hold the
// rows of own's nodes only, each entry with the bits of the whole operator's.
// frozen: the curved points' normals nu (3 per point, a state's), null: each
// the nearest obstacle's at its reference position, the obstacles as
// defined, unmoved (contact/obstacles.hpp);
// the automatic gamma0 is always from those (a refresh keeps it).
std::unique_ptr<Discretization> discretize(const Space &space, const Definition &def, Counters *counters,
                                           const Ownership *own = nullptr, const std::vector<double> *frozen = nullptr);
// The discretization `from` with other frozen normals (a refresh,
// contact/obstacles.hpp): its M, K, gamma0 and clamped rows, new contact
// rows and K_Theta; the same as discretize(..., &frozen) would make.
std::unique_ptr<Discretization> with_normals(const Space &space, const Definition &def, const Discretization &from,
                                             const std::vector<double> &frozen);
// Where the unknowns sit (g.x, g.component), which GAMG's near-null space
// reads: for every unknown, or with g.own_rows_only for the rows
// [g.row_begin, g.row_end) of g.row_of's numbering only (no array n long).
void locate_unknowns(const Space &space, const DofMap &dofs, DofGeometry &g);
// Can the operators hold a rank's rows only (discretize's `own`)? With a
// distributed solver on several ranks (which reads no other rows), and
// neither mass lumping nor redistribution (whose diagonal and massless rows
// the explicit steps read whole).
bool splits_rows(const Definition &def);
// The rows a process computes with d's operators: its own when they are
// split (or `in_step`: every rank at the same point of a step), else all.
const Share *own_rows_of(const Discretization &d, bool in_step);
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
