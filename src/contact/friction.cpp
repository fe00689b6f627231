#include "contact/friction.hpp"

#include <cmath>

namespace nd {

namespace {
LawTraits friction_traits(int dim, bool symmetric) {
  LawTraits t;
  t.m = dim;
  t.rank_one = false;
  t.symmetric = symmetric;
  // the tangential values are not zero where the point is free: the slip
  // reference follows the body there (problem/friction_state.cpp), so every
  // step evaluates every point (no bound stands for them)
  t.zero_when_free = false;
  t.nondecreasing = false;
  t.positive_part = false;
  t.max_slope = 1;  // (sticking: the identity in every direction)
  return t;
}
}  // namespace

FrictionLaw::FrictionLaw(int dim, double parameter, bool symmetric)
    : PointLaw(friction_traits(dim, symmetric)), parameter_(parameter) {}

void FrictionLaw::at(double x, double &value, double &slope) const {
  value = x > 0 ? x : 0;
  slope = x > 0 ? 1 : 0;
}

void FrictionLaw::over_step_m(const TimeRule &rule, size_t, double gamma, int m, const double *P, const double *Pn,
                              double *value, double *J) const {
  for (int k = 0; k < m * m; ++k) J[k] = 0;
  over_step(rule, P[0], Pn ? Pn[0] : 0.0, value[0], J[0]);
  const double c = tangential_weight(rule);
  double Y[2] = {0, 0}, norm2 = 0;
  for (int k = 1; k < m; ++k) {
    Y[k - 1] = c * P[k] + (c == 1 ? 0.0 : (1 - c) * (Pn ? Pn[k] : 0.0));
    norm2 += Y[k - 1] * Y[k - 1];
  }
  double r, dr;
  radius(value[0], gamma, r, dr);
  const double norm = std::sqrt(norm2);
  if (r > 0 && norm <= r) {  // sticking: phi_t = Y_t
    for (int k = 1; k < m; ++k) value[k] = Y[k - 1], J[k * m + k] = c;
    return;
  }
  if (norm == 0) {  // r = 0 at Y_t = 0: nothing, and no slope
    for (int k = 1; k < m; ++k) value[k] = 0;
    return;
  }
  // sliding: phi_t = r Y/|Y|, d/dY = (r/|Y|)(I - y y^T), y = Y/|Y|; d/dP_n = dr phi_n' y
  const double s = r / norm;
  for (int k = 1; k < m; ++k) {
    const double yk = Y[k - 1] / norm;
    value[k] = s * Y[k - 1];
    for (int l = 1; l < m; ++l) J[k * m + l] = c * s * ((k == l ? 1.0 : 0.0) - yk * Y[l - 1] / norm);
    J[k * m] = dr * J[0] * yk;
  }
}

}  // namespace nd
