// The massless DOFs of mass redistribution in an explicit step
// (Khenous-Laborde-Renard 2008, Doyen-Ern-Piperno 2011). Redistribution
// zeroes the rows and columns of M on the contact nodes (lumped or
// consistent alike), so on those DOFs m the semi-discrete equation is static:
//   (K_Theta U)_m + N_m(U) = F_m,  U_f = the explicit predictor on the others.
// With x = U_m this is G(x) = A x + N~(x) - r = 0,
//   A = (K_Theta)_mm,  r = F_m - (K_Theta)_mf U_f,
//   N~ = N restricted to the rows m, its points' rows restricted to m and
//   their gaps shifted by p_q,f . U_f (P_q is linear in U); with friction
//   the tangential pairs likewise, their slip references shifted so,
// a small semi-smooth system solved by newton_solve (its stopping rule, c = 0:
// ||G|| <= rtol ||r|| + atol or an update at round-off, with the active set
// unchanged; atol raised to the round-off of r's terms, since U_m may be
// exactly 0 where "an update at the round-off of U" cannot hold). A is a principal submatrix of K_Theta: positive definite when
// K_Theta is positive semi-definite with only rigid motions in its kernel
// (none vanishes on the non-contact nodes). It is factored once, here; a
// Newton iteration with active points refactors the tangent A + N~'(x)
// (the block is small: the contact nodes only).
#pragma once
#include <memory>
#include <vector>

#include "linalg/csr.hpp"
#include "linalg/factorization.hpp"
#include "problem/discretization.hpp"
#include "solve/newton.hpp"
#include "solve/tangent_solver.hpp"

namespace nd {

class MasslessSolver {
 public:
  // Throws ND_ERR_INDEFINITE when (K_Theta)_mm is not positive definite.
  MasslessSolver(const Discretization &d, int solver);
  MasslessSolver(const MasslessSolver &) = delete;
  MasslessSolver &operator=(const MasslessSolver &) = delete;
  // U_m from U_f (U holds the predictor on entry: its U_m is Newton's first
  // guess), with the load F (empty: none) and the gaps (empty: the
  // assembled ones) at the step's end. Returns the Newton iterations; throws
  // ND_ERR_NEWTON (U then partly written: the caller discards it) at time t.
  // With friction, slip: the state's slip references (empty: zero).
  int solve(const NewtonOptions &opt, const std::vector<double> &F, const std::vector<double> &gap,
            const std::vector<double> &slip, double t, std::vector<double> &U);
  const std::vector<int64_t> &dofs() const { return dofs_; }
  const TangentStats &tangent_stats() const { return tangent_->stats; }

 private:
  double theta_;
  std::shared_ptr<const PointLaw> law_;
  Counters *counters_;
  std::vector<int64_t> dofs_;   // the massless free DOFs, ascending (local index -> free index)
  Csr A_, M0_;                  // (K_Theta)_mm and zeros on its pattern (Newton's c M term, c = 0)
  std::vector<int64_t> cptr_, ccol_;  // (K_Theta)_mf: per local row, free columns
  std::vector<double> cval_;
  ContactPoints cp_;            // the points touching m, rows restricted to m (local indices)
  std::vector<size_t> point_;   // their index among the discretization's points
  std::vector<SparseRow> pf_;   // p_q = a_q - gamma_q s_q on the other DOFs (free indices)
  std::vector<double> base_gap_;  // the assembled gaps of those points
  // friction: the tangential pairs' p_qk on the other DOFs (as pf_), the
  // index of each pair among the discretization's (its slip reference), and
  // the references x sees
  std::vector<SparseRow> ptf_;
  std::vector<size_t> slip_point_;
  std::vector<double> gap_t_;
  std::vector<double> r_, gap_, x_;
  ContactScratch scratch_;      // the buffers of the contact passes (ContactLaw::buffers)
  std::unique_ptr<Factorization> factor_;
  std::unique_ptr<TangentSolver> tangent_;
};

}  // namespace nd
