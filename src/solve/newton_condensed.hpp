// The semi-smooth Newton of DESIGN §3 condensed on the contact points
// (DESIGN §4, the dense/sparse step). With A factored once per tau and
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
// and the full residual G(U) is checked against DESIGN §3's tolerance; if it
// fails, or S outgrows max_rank, the caller runs the full Newton from U.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "linalg/factorization.hpp"
#include "solve/newton.hpp"

namespace nd {

// What the condensed Newton keeps across iterations and steps: the columns
// Z_q = A^{-1} b_q, computed one solve each on first need (a column's bits do
// not depend on which others were computed with it: a run resumed from a
// checkpoint, whose cache starts empty, is bitwise the uninterrupted one),
// held for the factor's lifetime, at most max_columns (past that the columns
// of the points outside the current set are dropped); and the LU of the last
// k x k Jacobian with the set and slopes it was made for (the same matrix
// gives the same LU: reusing it changes no bit).
class CondensedCache {
 public:
  CondensedCache(const Factorization &A_factor, int64_t n, int64_t max_columns);
  // binds to one set of contact rows and one Theta (a new set clears the cache)
  void bind(const ContactPoints &cp, double theta);
  // Z_q for every q of S (the columns off S may be dropped for them)
  void require(const std::vector<int64_t> &S);
  const double *column(int64_t q) const { return Z_[static_cast<size_t>(q)].data(); }
  int64_t computed() const { return computed_; }  // columns computed (each one solve)
  // G_ij = p_i . Z_j for i, j in S (the columns of S required)
  const std::vector<double> &G(const std::vector<int64_t> &S);
  struct Lu;  // the last Jacobian's LU (newton_condensed.cpp: LAPACK's types stay there)
  Lu &lu();
  ~CondensedCache();

 private:
  const Factorization &A_factor_;
  int64_t n_, max_columns_, held_ = 0, computed_ = 0;
  const ContactPoints *cp_ = nullptr;
  double theta_ = 0;
  std::vector<std::vector<double>> Z_;
  std::unique_ptr<Lu> lu_;
  std::vector<int64_t> G_S_, position_;  // the S that G_ was built for; a point's place in it (-1: none)
  std::vector<double> G_;
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
CondensedResult newton_condensed(const NewtonSystem &sys, const Factorization &A_factor, CondensedCache &columns,
                                 int64_t max_rank, const std::vector<double> &r, const NewtonOptions &opt,
                                 std::vector<double> &U);

}  // namespace nd
