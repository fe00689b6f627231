// The semi-smooth Newton of docs/design.md §3 condensed on the contact points
// (docs/design.md §4, the dense/sparse step). With A factored once per tau and
// Z_q = A^{-1} b_q, c_q = kappa w_q/gamma_q, every solution of
//   G(U) = A U + sum_q c_q phi_q(P_q(U)) b_q - r = 0
// is U = y0 - sum_{j in S} c_j phi_j Z_j, y0 = A^{-1} r, S the points where
// phi != 0. So P = P(U) solves, on S, the k equations
//   F(P) = P - P0 + G C phi(P) = 0,  P0_q = p_q.y0 - g_q,  G_qj = p_q.Z_j,
// and Newton runs on them: k unknowns, a k x k LU per iteration (kept while
// the active set and the slopes stay), no sparse product, one solve for y0
// and one column per point the first time it is in S. A point off S is
// checked through P_q = P0_q - sum_j G_qj c_j phi_j; a point that becomes
// active joins S (S only grows within a step: a point of S whose phi is 0
// has the row P_q = P0_q - ..., exact as well). On a fixed active set F is
// linear, so the iteration that keeps the set solves it exactly: the
// converged U is the full Newton's to round-off. At the end U is formed once
// and the full residual G(U) is checked against docs/design.md §3's tolerance; if it
// fails, or S outgrows max_rank, the caller runs the full Newton from U.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "linalg/factorization.hpp"
#include "fast/contact_columns.hpp"
#include "solve/newton.hpp"

namespace nd {

// What the condensed Newton keeps across iterations and steps: the columns
// and G (fast/contact_columns.hpp), and the LU of the last k x k Jacobian
// with the set and slopes it was made for (the same matrix gives the same
// LU: reusing it changes no bit).
class CondensedCache {
 public:
  explicit CondensedCache(ContactColumns &c);
  ~CondensedCache();
  ContactColumns &columns;  // the integrator's, shared with the low-rank tangent
  struct Lu;  // newton_condensed.cpp: LAPACK's types stay there
  Lu &lu();
  // a step's vectors, kept from step to step for their memory (their
  // values are not read again), so that a step allocates none of them
  struct Work {
    std::vector<double> P, y0, P0, c, F, phi, slope, dP, Ut, off_S, f, G;
    std::vector<int64_t> S;
    std::vector<char> active, previous, in_S;
  } work;

 private:
  std::unique_ptr<Lu> lu_;
};

struct CondensedResult {
  NewtonResult newton;   // iterations, converged (the full residual checked), residual, tolerance
  bool too_large = false;  // S outgrew the column limit: the caller takes over from U
};

// U: the predictor on entry (its active points start S); the solution on exit
// when converged, else the last iterate (the caller may continue from it).
// max_rank: the most points S may hold (negative: no limit), past which the
// caller's tangent solver (refactoring) takes over; with more than half of it
// active at the predictor the condensed Newton does not start (too_large).
// points: as newton_solve's, from the full residual's check
// products_at (if given): the new state's products at the formed U (the
// integrator's: its update and pass, one for both), from which the full
// residual is checked (newton_residual_from_products) instead of a pass over
// A and M of its own; points is then left as it is
CondensedResult newton_condensed(const NewtonSystem &sys, const Factorization &A_factor, CondensedCache &cache,
                                 int64_t max_rank, const std::vector<double> &r, const NewtonOptions &opt,
                                 std::vector<double> &U, PointValues *points = nullptr,
                                 const std::function<const Products &()> *products_at = nullptr);

}  // namespace nd
