#include "fast/predictor_check.hpp"

#include <cfloat>
#include <cmath>

#include "time/scheme.hpp"

namespace nd {

bool predictor_solves_step(const ContactLaw &law, double c, const std::vector<double> &r, const State &s,
                           const Products &p, std::vector<double> &G) {
  const ContactPoints &cp = *law.cp;
  // (points left unevaluated: shown free by the bound, PointValues::ref)
  const bool pp = law.positive_part();
  for (size_t q = 0; q < cp.size() && !p.points.ref; ++q) {
    double phi, slope;
    law.law(q, p.points.P[q], phi, slope, pp);
    if (phi != 0 || slope != 0) return false;
  }
  // G = c M U + K_Theta U - r
  const std::vector<double> none;
  StepInputs{p, cp, law.theta, none, none}.k_theta_u(s.U, G);
  for (size_t i = 0; i < G.size(); ++i) G[i] += c * p.MU[i] - r[i];
  double g2 = 0, r2 = 0, m2 = 0;
  for (size_t i = 0; i < G.size(); ++i) g2 += G[i] * G[i], r2 += r[i] * r[i], m2 += p.MU[i] * p.MU[i];
  const double scale = DBL_EPSILON * (std::sqrt(r2) + c * std::sqrt(m2));
  return std::sqrt(g2) <= kPredictorRoundOffs * scale;
}

}  // namespace nd
