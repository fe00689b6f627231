// The discretization a step computes with: the DOF numbering, the operators
// M, K, K_Theta, the contact points with their rows and law, and the mass
// solve and equilibrium acceleration they make. Built by problem/
// discretization.hpp from a definition; read by the monitors and the step.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "assembly/contact.hpp"
#include "common/counters.hpp"
#include "contact/law.hpp"
#include "fem/space.hpp"
#include "linalg/csr.hpp"
#include "linalg/factorization.hpp"
#include "linalg/node_blocks.hpp"
#include "parallel/share.hpp"
#include "time/products.hpp"
#include "time/state.hpp"

namespace nd {

// The clamped DOFs and their rows of K and of the consistent mass on the free
// columns (problem/forces.hpp): what the reactions need.
// Prescribed motion (docs/design.md §10.5) reads also their block among
// themselves (Kcc, Mcc: columns in row order) and their lumped (HRZ) mass.
struct ClampedRows {
  std::vector<int64_t> dofs;  // full DOF indices, in row order
  Csr K, M;
  Csr Kcc, Mcc;
  std::vector<double> M_lumped;
};

// the penetration guard's length at a point is min(h_K, L / this), L the
// body's length across its contact region (docs/design.md §3b.5)
constexpr double kPenetrationBodyDivisor = 8;

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
  // Rayleigh damping C = alpha M + beta K on their pattern (empty: none)
  double damping_alpha = 0, damping_beta = 0;
  Csr C;
  bool damped() const { return !C.val.empty(); }
  ContactPoints contact;
  std::shared_ptr<const PointLaw> contact_law;  // the contact law (the definition's), never null
  double theta = 1;
  double gamma0 = 0;        // in use (chosen here when the definition asks for it)
  double gamma0_limit = 0;  // gamma0* at Theta = 1 (docs/design.md §3b.1); +inf without contact
  bool coercive = false;    // K_Theta checked positive semi-definite
  double omega_max = 0;     // the explicit schemes' highest frequency, once estimated
  // the free motion's (no contact point active), a lower bound: the
  // critical-step check's (docs/design.md §3b.4), once estimated
  double omega_free = 0;
  // sum_K E_K |K| over every cell (Young's modulus times volume, an energy):
  // the penetration guard's strain scale sqrt(2 E_in / this) (docs/design.md §3b)
  double stiffness_volume = 0;
  // the penetration guard's lengths: min(h_K, L/8) at each contact point,
  // L = |Omega| / |Gamma_C| the body's length across its contact region
  // (docs/design.md §3b.5); empty without contact points
  std::vector<double> penetration_length;
  std::unique_ptr<Factorization> M_factor;  // consistent mass, factored on first use
  std::unique_ptr<ClampedRows> clamped;     // when there are clamped DOFs
  Counters *counters = nullptr;             // the problem's (ND_STAT_*)
  DofGeometry geometry;                     // the solvers' ranks and rows; the unknowns' coordinates for AMG
  // with several ranks: which rank computes which row of the step's products
  // (the rank of its node; solve/products.cpp); null: this process, all
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
  // (solve/products.cpp): 4 bytes per entry of the rank's rows (falling
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
  // With damping it solves (M + slope C) A = F - K_Theta U - N(U) - C V_known,
  // V_known and slope from `damped` (an explicit step: V^{n+1} = V_known +
  // slope A^{n+1}), else M A = ... - C V (the state's V).
  // A new A leaves the state's products' M A stale: whoever holds them drops it.
  struct DampedVelocity {
    const std::vector<double> *V_known;
    double slope;
    const Factorization *factor;  // M + slope C factored (beta > 0, slope > 0), else null
  };
  void equilibrium_acceleration(State &s, int solver, bool once = true, bool in_step = false,
                                PointValues *at_U = nullptr, const DampedVelocity *damped = nullptr);
};

// The rows a process computes with d's operators: its own when they are
// split (or `in_step`: every rank at the same point of a step), else all.
const Share *own_rows_of(const Discretization &d, bool in_step);

}  // namespace nd
