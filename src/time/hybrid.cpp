// The paper's hybrid scheme (eq. (17)): Crank-Nicolson for the bulk, a
// contact term that switches on the sign of P_q^n. With Theta = 1 and no load
// E_Theta never increases. It carries no acceleration.
#include "nitschedyn.h"
#include "time/scheme.hpp"

namespace nd {
namespace {

class Hybrid : public TimeScheme {
 public:
  // Phi = H(P^n) phi((P^n + P)/2) + H(-P^n) (phi(P^n) + phi(P))/2, H(0) = 1/2 (paper)
  Hybrid() { rule_.kind = TimeRule::Hybrid; }
  bool is_explicit() const override { return false; }
  bool uses_acceleration() const override { return false; }
  StepCoefficients coefficients(double tau) const override { return {4 / (tau * tau), 2}; }
  // 2 F^{n+1/2} - K_Theta U^n + M (c U^n + 4/tau V^n), F^{n+1/2} = (F^n + F^{n+1})/2
  void rhs(const StepInputs &in, double tau, const State &old, std::vector<double> &r) const override {
    in.mass_combination(coefficients(tau).c, 4 / tau, 0, r);  // M y
    std::vector<double> own, &KtU = in.workspace(own);
    in.k_theta_u(old.U, KtU);
    const bool has_load = !in.F_new.empty();
    for (size_t i = 0; i < r.size(); ++i) {
      r[i] -= KtU[i];
      if (has_load) r[i] += in.F_old[i] + in.F_new[i];
    }
  }
  void predict(double tau, const State &old, std::vector<double> &U) const override {
    predict_taylor(tau, old, 0, U);
  }
  double velocity_slope(double tau) const override { return 2 / tau; }
  void update(double tau, const State &old, State &next) const override {
    const size_t n = old.U.size();
    next.V.resize(n);
    next.A.assign(n, 0.0);
    next.A_valid = false;
    for (size_t i = 0; i < n; ++i) next.V[i] = 2 * (next.U[i] - old.U[i]) / tau - old.V[i];
  }
  // M (V^{n+1} - V^n)/tau + K_Theta U^{n+1/2} + N_hyb = F^{n+1/2} (G divided by kappa = 2)
  double mean_weight() const override { return 0.5; }
  void mean_acceleration(double tau, const State &old, const State &next, std::vector<double> &A) const override {
    A.resize(old.V.size());
    for (size_t i = 0; i < A.size(); ++i) A[i] = (next.V[i] - old.V[i]) / tau;
  }
};

}  // namespace

std::unique_ptr<TimeScheme> make_hybrid_scheme(const std::vector<double> &) { return std::make_unique<Hybrid>(); }

}  // namespace nd
