// A step its predictor already solves (docs/design.md §4: leave out what a scene does
// not need). A body in free flight whose acceleration does not change (a
// rigid motion under a uniform body force: the drop before its impact) has
// U^{n+1} = U^n + tau V^n + w tau^2 A^n exactly, the predictor of Newmark and
// generalized-alpha (w = 1/2) and of the theta-scheme (w = theta). A nonlinear solver checks its first guess
// before it iterates; here the check costs no product of its own: it reads
// the new state's pass (M U, K U, P_q), which the step makes anyway.
#pragma once
#include <vector>

#include "solve/contact_law.hpp"
#include "time/products.hpp"
#include "time/state.hpp"

namespace nd {

// Round-offs a predictor's residual may hold: ||G|| <= k eps (||r|| + c ||M U||),
// newton_tolerance's scale with k eps for its rtol (1e-10 by default).
// 16 leaves a margin over what a direct solve's own residual holds (about
// one unit) and what predicted steps hold (a few units, most where A^0's
// round-off weighs (omega tau)^2/2 more): docs/performance.md, "Predictor
// round-off allowance".
constexpr double kPredictorRoundOffs = 16;

// Whether s.U solves the implicit step G(U) = (c M + K_Theta) U + kappa N(U) - r = 0
// to round-off, from p, s's products (valid for s): no contact point active at U
// (phi_q and its slope zero at every point: N and its tangent vanish; or
// the points left unevaluated, shown free by the bound: PointValues::ref)
// and the residual within kPredictorRoundOffs. Serial operators only. G: a
// workspace (its values are not read).
bool predictor_solves_step(const ContactLaw &law, double c, const std::vector<double> &r, const State &s,
                           const Products &p, std::vector<double> &G);

}  // namespace nd
