// Newmark (paper eq. (16)); beta = 0 is its explicit variant
// (U^{n+1} = U^n + tau V^n + tau^2/2 A^n, then A^{n+1} from the equilibrium).
#include <cmath>

#include "nitschedyn.h"
#include "time/newmark_update.hpp"
#include "time/scheme.hpp"

namespace nd {
namespace {

class Newmark : public TimeScheme {
 public:
  Newmark(double beta, double gamma) : beta_(beta), gamma_(gamma) {}
  bool is_explicit() const override { return beta_ == 0; }
  // gamma < 1/2 is negative numerical damping: growth at every step size
  bool always_unstable() const override { return gamma_ < 0.5; }
  // gamma >= 1/2: unconditionally stable for 2 beta >= gamma, else for
  // omega tau <= (gamma/2 - beta)^(-1/2) (2 for the central difference)
  double stability_limit() const override {
    return 2 * beta_ >= gamma_ ? INFINITY : 1 / std::sqrt(0.5 * gamma_ - beta_);
  }
  StepCoefficients coefficients(double tau) const override { return {1 / (beta_ * tau * tau), 1}; }
  // F^{n+1} + M [c U^n + V^n/(beta tau) + (1/(2 beta) - 1) A^n]
  void rhs(const StepInputs &in, double tau, const State &, std::vector<double> &r) const override {
    in.mass_combination(coefficients(tau).c, 1 / (beta_ * tau), 0.5 / beta_ - 1, r);  // M y
    if (!in.F_new.empty())
      for (size_t i = 0; i < r.size(); ++i) r[i] += in.F_new[i];
  }
  void predict(double tau, const State &old, std::vector<double> &U) const override {
    predict_taylor(tau, old, 0.5, U);
  }
  bool predicts_constant_acceleration() const override { return true; }
  // implicit: gamma/(beta tau) (A^{n+1}'s slope c times gamma tau); explicit: gamma tau
  double velocity_slope(double tau) const override {
    return is_explicit() ? gamma_ * tau : gamma_ / (beta_ * tau);
  }
  void update(double tau, const State &old, State &next) const override {
    if (is_explicit())
      newmark_velocity(gamma_, tau, old, next);
    else
      newmark_update(beta_, gamma_, tau, old, next);
  }

 private:
  double beta_, gamma_;
};

}  // namespace

std::unique_ptr<TimeScheme> make_newmark_scheme(const std::vector<double> &params) {
  require_parameter(params[0], 0, 0.5, "beta (params[0])");
  require_parameter(params[1], 0, 1, "gamma (params[1])");
  return std::make_unique<Newmark>(params[0], params[1]);
}

}  // namespace nd
