#include "time/step_control.hpp"

#include <algorithm>
#include <cmath>

#include "time/state.hpp"

namespace nd {

namespace {
// a landing closer than this fraction to either end of the step is not cut:
// the step already ends (or began) at the touch
constexpr double kTouchMargin = 0.01;
// the usual safety factor of error-per-step control, and the order of the
// truncation error (tau^3): the size that would meet the tolerance is
// tau ratio^(-1/3)
constexpr double kSafety = 0.9;
double size_for(double tau, double ratio) {
  return ratio > 0 ? kSafety * tau * std::cbrt(1 / ratio) : 2 * tau;
}
double norm_inf(const std::vector<double> &v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}
}  // namespace

double ladder_below(const AdaptiveOptions &o, double x) {
  double tau = o.tau_max;
  // (tau_min > 0 bounds the halvings: at most log2(tau_max/tau_min) + 1)
  while (tau > x && tau > o.tau_min) tau *= 0.5;
  return std::max(tau, o.tau_min);
}

double step_error(const AdaptiveOptions &o, const State &old, State &next, double tau, double balance_gain,
                  double energy) {
  const size_t n = next.V.size();
  StepControl &c = next.control;
  c.a_mean.resize(n);
  for (size_t i = 0; i < n; ++i) c.a_mean[i] = (next.V[i] - old.V[i]) / tau;
  c.scale = std::max(old.control.scale, norm_inf(next.U));
  double ratio = 0;
  const StepControl &was = old.control;
  if (was.a_mean.size() == n && was.tau_last > 0 && c.scale > 0) {
    // u''' ~ (a^{n+1/2} - a^{n-1/2}) / ((tau + tau_last) / 2)
    double d = 0;
    for (size_t i = 0; i < n; ++i) d = std::max(d, std::fabs(c.a_mean[i] - was.a_mean[i]));
    const double truncation = tau * tau * tau / 12 * d * 2 / (tau + was.tau_last);
    ratio = truncation / (o.tolerance * c.scale);
  }
  if (balance_gain > 0 && energy > 0) ratio = std::max(ratio, balance_gain / (o.tolerance * energy));
  return ratio;
}

double size_after_accepted(const AdaptiveOptions &o, double tau, double ratio) {
  return ladder_below(o, std::min(size_for(tau, ratio), 2 * tau));
}

double size_after_rejected(const AdaptiveOptions &o, double tau, double ratio) {
  // (at most half: a retry that would nearly repeat the failed step is wasted)
  return ladder_below(o, std::min(size_for(tau, ratio), 0.5 * tau));
}

double first_touch(const std::vector<double> &P_old, const std::vector<double> &P_new,
                   const std::vector<double> &un_old, const std::vector<double> &rate, double tau) {
  // (the normal values: friction's tangential ones follow them in P)
  const size_t nq = un_old.size();
  if (P_old.size() < nq || P_new.size() < nq || rate.size() < nq) return 1;
  for (size_t q = 0; q < nq; ++q)
    if (P_old[q] > 0) return 1;  // (in contact already: not the first touch)
  double s = 1;
  for (size_t q = 0; q < nq; ++q)
    if (P_new[q] > 0 && rate[q] > 0) s = std::min(s, std::max(0.0, -un_old[q]) / (rate[q] * tau));
  return s > kTouchMargin && s < 1 - kTouchMargin ? s : 1;
}

}  // namespace nd
