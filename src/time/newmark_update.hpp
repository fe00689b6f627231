// The Newmark(beta, gamma) updates, shared by Newmark and generalized-alpha:
//   A^{n+1} = (U^{n+1} - U^n)/(beta tau^2) - V^n/(beta tau) - (1/(2 beta) - 1) A^n
//   V^{n+1} = V^n + tau ((1 - gamma) A^n + gamma A^{n+1})
#pragma once
#include <cstddef>

#include "time/state.hpp"

namespace nd {

inline void newmark_velocity(double gamma, double tau, const State &old, State &next) {
  next.V.resize(old.U.size());
  for (size_t i = 0; i < next.V.size(); ++i)
    next.V[i] = old.V[i] + tau * ((1 - gamma) * old.A[i] + gamma * next.A[i]);
}

inline void newmark_update(double beta, double gamma, double tau, const State &old, State &next) {
  const size_t n = old.U.size();
  next.A.resize(n);
  next.A_valid = true;
  const double c = 1 / (beta * tau * tau);
  for (size_t i = 0; i < n; ++i)
    next.A[i] = c * (next.U[i] - old.U[i]) - old.V[i] / (beta * tau) - (0.5 / beta - 1) * old.A[i];
  newmark_velocity(gamma, tau, old, next);
}

}  // namespace nd
