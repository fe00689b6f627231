// The theta-scheme (paper eq. (15)); theta = 0 is its explicit variant
// (U^{n+1} = U^n + tau V^n, V^{n+1} = V^n + tau A^n). theta < 1/2 amplifies
// every undamped oscillation (docs/design.md §3).
#include "nitschedyn.h"
#include "time/scheme.hpp"

namespace nd {
namespace {

class Theta : public TimeScheme {
 public:
  explicit Theta(double theta) : th_(theta) {}
  bool is_explicit() const override { return th_ == 0; }
  // |1 + (1-theta) i w tau| > |1 - theta i w tau| for every w tau > 0
  bool always_unstable() const override { return th_ < 0.5; }
  StepCoefficients coefficients(double tau) const override { return {1 / (tau * tau * th_ * th_), 1}; }
  // F^{n+1} + M [c U^n + V^n/(tau theta^2) + (1 - theta)/theta A^n]
  void rhs(const StepInputs &in, double tau, const State &, std::vector<double> &r) const override {
    in.mass_combination(coefficients(tau).c, 1 / (tau * th_ * th_), (1 - th_) / th_, r);  // M y
    if (!in.F_new.empty())
      for (size_t i = 0; i < r.size(); ++i) r[i] += in.F_new[i];
  }
  // U^n + tau V^n + theta tau^2 A^n: with V^{n+1} = V^n + tau A^n it is
  // U^n + tau (theta V^{n+1} + (1 - theta) V^n), exact at constant acceleration
  void predict(double tau, const State &old, std::vector<double> &U) const override {
    predict_taylor(tau, old, th_, U);
  }
  bool predicts_constant_acceleration() const override { return !is_explicit(); }
  // V^{n+1} = (U^{n+1} - U^n)/(tau theta) - ...; explicit: V^n + tau A^n, no A^{n+1}
  double velocity_slope(double tau) const override { return is_explicit() ? 0.0 : 1 / (tau * th_); }
  void update(double tau, const State &old, State &next) const override {
    const size_t n = old.U.size();
    next.V.resize(n);
    if (is_explicit()) {
      for (size_t i = 0; i < n; ++i) next.V[i] = old.V[i] + tau * old.A[i];
      return;
    }
    next.A.resize(n);
    next.A_valid = true;
    const double q = (1 - th_) / th_;
    for (size_t i = 0; i < n; ++i) {
      next.V[i] = (next.U[i] - old.U[i]) / (tau * th_) - q * old.V[i];
      next.A[i] = (next.V[i] - old.V[i]) / (tau * th_) - q * old.A[i];
    }
  }

 private:
  double th_;
};

}  // namespace

std::unique_ptr<TimeScheme> make_theta_scheme(const std::vector<double> &params) {
  require_parameter(params[0], 0, 1, "theta (params[0])");
  return std::make_unique<Theta>(params[0]);
}

}  // namespace nd
