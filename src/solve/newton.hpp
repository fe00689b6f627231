// Semi-smooth Newton for G(U) = A U + kappa N(U) - r = 0 (docs/design.md §3).
// Converged when the active set did not change in the last iteration and
// either ||G|| <= rtol (||r|| + ||cMU||) + atol or the update is at the
// round-off level of U; or when both hold (points at P_q = 0 to round-off
// may flip forever without moving U).
#pragma once
#include <vector>

#include "linalg/node_blocks.hpp"
#include "solve/contact_law.hpp"
#include "solve/tangent_solver.hpp"

namespace nd {

struct NewtonOptions {
  double rtol = 1e-10, atol = 0;
  int max_iter = 50;
};

// Newton's n-long and point-long vectors, kept by the caller from step to
// step for their memory (their values are not read again), so that a
// contact step's Newton allocates none of them
struct NewtonWork {
  std::vector<double> G, MU;
  std::vector<char> active, previous;
  PointValues at;  // the points at the iterate (exchanged with newton_solve's `points`)
  std::vector<double> direction, from;  // the line search's (friction): the update and where it starts
};

struct NewtonSystem {
  const Csr *A;             // c M + K_Theta
  TangentSolver *tangent;   // solves with A + kappa N'(U)
  const Csr *M;
  double c, kappa;
  const ContactLaw *law;
  // with several ranks: each computes its rows of A U and M U, gathered
  // (parallel/share.hpp); null: this process computes them all
  const Share *rows = nullptr;
  // the operators are split over the ranks (every solve reads a rank's rows
  // only): r, G and M U are right on this rank's rows alone, nothing is
  // gathered, and their norms are the ranks' sums (norm2_rows)
  bool split = false;
  // the solve with A is iterative (Factorization::starts_from_guess): the
  // linear step starts it from the predictor
  bool guess = false;
  // false: a solve that kept the tangent's held rows leaves U so (a
  // distributed state, Definition::distributed_state), not gathered at the end
  bool complete = true;
  // A and M by nodes (Integrator::A_blocks), or null: the CSR pattern
  const NodeBlocks *blocks = nullptr;
  // where Newton keeps its vectors, or null: its own
  NewtonWork *work = nullptr;
  // the rows r, G and M U are right on: this rank's when split, else all (null)
  const Share *held_rows() const { return split ? rows : nullptr; }
};

struct NewtonResult {
  int iterations = 0;
  bool converged = false;
  double residual = 0, tolerance = 0;
  // the solution shown contact-free by ContactLaw::certainly_free's bound
  // (every law and slope zero there), no point evaluated at it
  bool bounded = false;
};

// G = A U + kappa N(U) - r; returns ||G||, fills the active set (if given)
// and MU = M U from the same pass over the pattern A and M share (split: on
// this rank's rows; collective with rows); points (if given): P_q(U) as
// ContactLaw::add_force leaves it, for the tangent solve at U, and u_n - g0
// from the same pass where that pass is every point's (else un empty);
// with known, points->P is P_q(U) already (ContactLaw::contact_free's): not
// evaluated again, and un left empty
double newton_residual(const NewtonSystem &sys, const std::vector<double> &r, const std::vector<double> &U,
                       std::vector<double> &G, std::vector<char> *active, std::vector<double> &MU,
                       PointValues *points = nullptr, bool known = false);
// ||G||, G = c M U + K_Theta U + kappa N(U) - r from the products of a
// state at U (M U, K U and P_q(U): time/state.hpp's Products, whole, one
// process): newton_residual's to round-off (A = c M + K_Theta), without a
// pass over A and M (the condensed Newton's check, from the products the new
// state makes anyway)
// G: a workspace (its values are not read)
double newton_residual_from_products(const NewtonSystem &sys, const Products &p, const std::vector<double> &U,
                                     const std::vector<double> &r, std::vector<double> &G);
// rtol (||r|| + c ||M U||) + atol
double newton_tolerance(const NewtonSystem &sys, const NewtonOptions &opt, double r_norm,
                        const std::vector<double> &MU);
// the norm of a right-hand side or residual over the rows it is right on (collective when split)
double rhs_norm(const NewtonSystem &sys, const std::vector<double> &r);

// The rows Newton reads of its iterate on split operators (sys.split): this
// rank's rows of A, their columns (A U and M U there) and the DOFs of every
// contact point's rows (P_q of the rank's points; the bound of
// ContactLaw::certainly_free reads the same DOFs). Ascending. A solve that keeps these rows
// (make_refactoring_tangent) receives only their values from other ranks.
// `points` (null: every point) limits the contact points (HeldPoints).
std::vector<int64_t> newton_held_rows(const Csr &A, const Share &rows, const ContactPoints &cp,
                                      const std::vector<const Csr *> &also = {},
                                      const std::vector<int64_t> *points = nullptr);

// U holds the initial guess on entry and the solution on exit (on every row:
// when the tangent keeps only its held rows, the others are gathered from
// their ranks at the end, unless !sys.complete). points (if given): set to
// P_q and u_n - g0 at the solution when its last residual evaluated every
// point at every row (else left as it was; exchanged with sys.work's, whose
// memory *points then holds), for the new state's products.
NewtonResult newton_solve(const NewtonSystem &sys, const std::vector<double> &r,
                          const NewtonOptions &opt, std::vector<double> &U, PointValues *points = nullptr);

}  // namespace nd
