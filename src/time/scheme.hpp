// The time-marching schemes of section 3 of the paper (DESIGN §3 table).
// Every implicit step solves (c M + K_Theta) U + kappa N(U) = r for U^{n+1};
// the explicit variants (theta = 0, Newmark beta = 0) predict U^{n+1} and
// then solve M A^{n+1} = F^{n+1} - K_Theta U^{n+1} - N(U^{n+1}).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "linalg/csr.hpp"

namespace nd {

struct SchemeSpec {
  int kind = 0;  // ND_SCHEME_*
  double theta = 0, beta = 0, gamma = 0;
  bool is_explicit() const;
  bool is_hybrid() const;
};

// The state at t^n, in free DOFs. F is the load F^n used by the last step.
struct State {
  double t = 0;
  int64_t n = 0;
  std::vector<double> U, V, A, F;
  bool A_valid = false;  // the hybrid scheme needs no acceleration: computed on demand
  double W = 0;
  int last_iterations = 0;
  int64_t total_iterations = 0;
};

struct StepCoefficients {
  double c, kappa;
};
StepCoefficients step_coefficients(const SchemeSpec &s, double tau);

// r for an implicit step. F_old, F_new: loads at t^n, t^{n+1} (both empty when
// there is none); KtU = K_Theta U^n (used by the hybrid scheme only).
void implicit_rhs(const SchemeSpec &s, double tau, const Csr &M, const State &old,
                  const std::vector<double> &F_old, const std::vector<double> &F_new,
                  const std::vector<double> &KtU,
                  std::vector<double> &r);
// A first guess for U^{n+1}: U^n + tau V^n (+ tau^2/2 A^n for Newmark); for an
// explicit scheme this is the step's displacement.
void predict_displacement(const SchemeSpec &s, double tau, const State &old, std::vector<double> &U);
// V^{n+1}, A^{n+1} from U^{n+1} (implicit), or V^{n+1} from A^{n+1} (explicit).
void implicit_update(const SchemeSpec &s, double tau, const State &old, State &next);
void explicit_update(const SchemeSpec &s, double tau, const State &old, State &next);

}  // namespace nd
