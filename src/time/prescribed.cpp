#include "time/prescribed.hpp"

#include <utility>

namespace nd {

ClampedMean prescribed_update(const TimeScheme &scheme, double tau, const State &old, State &next) {
  const size_t m = next.Uc.size();
  State o, x;  // the clamped DOFs as a state of their own
  auto or_zeros = [m](const std::vector<double> &v) { return v.empty() ? std::vector<double>(m, 0.0) : v; };
  o.U = or_zeros(old.Uc), o.V = or_zeros(old.Vc), o.A = or_zeros(old.Ac);
  o.A_valid = true;
  x.U = next.Uc;
  if (scheme.is_explicit()) {  // backward differences (prescribed.hpp)
    x.V.resize(m), x.A.resize(m);
    for (size_t i = 0; i < m; ++i) {
      x.V[i] = (x.U[i] - o.U[i]) / tau;
      x.A[i] = (x.V[i] - o.V[i]) / tau;
    }
    x.A_valid = true;
  } else {
    scheme.update(tau, o, x);
  }
  ClampedMean mean;
  const double a = scheme.mean_weight();
  mean.U.resize(m);
  for (size_t i = 0; i < m; ++i) mean.U[i] = a == 0 ? x.U[i] : (1 - a) * x.U[i] + a * o.U[i];
  scheme.mean_acceleration(tau, o, x, mean.A);
  mean.V.resize(m);
  for (size_t i = 0; i < m; ++i) mean.V[i] = a == 0 ? x.V[i] : (1 - a) * x.V[i] + a * o.V[i];
  next.Vc = std::move(x.V);
  next.Ac = x.A.size() == m ? std::move(x.A) : std::vector<double>(m, 0.0);
  return mean;
}

}  // namespace nd
