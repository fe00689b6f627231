#include "time/scheme.hpp"

#include "nitschedyn.h"

namespace nd {

bool SchemeSpec::is_explicit() const {
  return (kind == ND_SCHEME_THETA && theta == 0) || (kind == ND_SCHEME_NEWMARK && beta == 0);
}
bool SchemeSpec::is_hybrid() const { return kind == ND_SCHEME_HYBRID; }

StepCoefficients step_coefficients(const SchemeSpec &s, double tau) {
  switch (s.kind) {
    case ND_SCHEME_THETA:
      return {1 / (tau * tau * s.theta * s.theta), 1};
    case ND_SCHEME_NEWMARK:
      return {1 / (s.beta * tau * tau), 1};
    default:
      return {4 / (tau * tau), 2};
  }
}

void implicit_rhs(const SchemeSpec &s, double tau, const Csr &M, const State &old,
                  const std::vector<double> &F_old, const std::vector<double> &F_new,
                  const std::vector<double> &KtU,
                  std::vector<double> &r) {
  const size_t n = old.U.size();
  const double c = step_coefficients(s, tau).c;
  std::vector<double> y(n);
  for (size_t i = 0; i < n; ++i) {
    switch (s.kind) {
      case ND_SCHEME_THETA:
        y[i] = c * old.U[i] + old.V[i] / (tau * s.theta * s.theta) + (1 - s.theta) / s.theta * old.A[i];
        break;
      case ND_SCHEME_NEWMARK:
        y[i] = c * old.U[i] + old.V[i] / (s.beta * tau) + (0.5 / s.beta - 1) * old.A[i];
        break;
      default:
        y[i] = c * old.U[i] + 4 / tau * old.V[i];
    }
  }
  r.resize(n);
  M.multiply(y.data(), r.data());
  const bool has_load = !F_new.empty();
  for (size_t i = 0; i < n; ++i) {
    if (s.is_hybrid()) {  // 2 F^{n+1/2} - K_Theta U^n, F^{n+1/2} = (F^n + F^{n+1})/2
      r[i] -= KtU[i];
      if (has_load) r[i] += F_old[i] + F_new[i];
    } else if (has_load) {
      r[i] += F_new[i];
    }
  }
}

void predict_displacement(const SchemeSpec &s, double tau, const State &old, std::vector<double> &U) {
  U.resize(old.U.size());
  const bool newmark = s.kind == ND_SCHEME_NEWMARK && old.A_valid;
  for (size_t i = 0; i < U.size(); ++i)
    U[i] = old.U[i] + tau * old.V[i] + (newmark ? 0.5 * tau * tau * old.A[i] : 0.0);
}

void implicit_update(const SchemeSpec &s, double tau, const State &old, State &next) {
  const size_t n = old.U.size();
  next.V.resize(n);
  next.A.resize(n);
  next.A_valid = !s.is_hybrid();
  for (size_t i = 0; i < n; ++i) {
    const double dU = next.U[i] - old.U[i];
    switch (s.kind) {
      case ND_SCHEME_THETA: {
        const double q = (1 - s.theta) / s.theta;
        next.V[i] = dU / (tau * s.theta) - q * old.V[i];
        next.A[i] = (next.V[i] - old.V[i]) / (tau * s.theta) - q * old.A[i];
        break;
      }
      case ND_SCHEME_NEWMARK: {
        const double c = 1 / (s.beta * tau * tau);
        next.A[i] = c * dU - old.V[i] / (s.beta * tau) - (0.5 / s.beta - 1) * old.A[i];
        next.V[i] = old.V[i] + tau * ((1 - s.gamma) * old.A[i] + s.gamma * next.A[i]);
        break;
      }
      default:
        next.V[i] = 2 * dU / tau - old.V[i];
        next.A[i] = 0;
    }
  }
}

void explicit_update(const SchemeSpec &s, double tau, const State &old, State &next) {
  const size_t n = old.U.size();
  next.V.resize(n);
  for (size_t i = 0; i < n; ++i)
    next.V[i] = s.kind == ND_SCHEME_THETA
                    ? old.V[i] + tau * old.A[i]
                    : old.V[i] + tau * ((1 - s.gamma) * old.A[i] + s.gamma * next.A[i]);
}

}  // namespace nd
