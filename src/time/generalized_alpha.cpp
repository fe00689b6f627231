// Generalized-alpha (Chung-Hulbert 1993), one parameter rho_inf in [0, 1],
// the spectral radius at infinite frequency (docs/design.md §3):
//   M A^{n+1-alpha_m} + K_Theta U^{n+1-alpha_f} + N(U^{n+1-alpha_f}) = F^{n+1-alpha_f}
// with the Newmark(beta, gamma) updates, X^{n+1-a} = (1-a) X^{n+1} + a X^n.
// Divided by (1 - alpha_f): c = (1-alpha_m)/((1-alpha_f) beta tau^2),
// kappa = 1/(1-alpha_f), and the contact term at Y = (1-alpha_f) U + alpha_f U^n,
// where P_q(Y) = (1-alpha_f) P_q(U) + alpha_f P_q^n (P_q is affine).
// rho_inf = 1 is Newmark(1/4, 1/2) (to round-off, without contact).
#include "nitschedyn.h"
#include "time/newmark_update.hpp"
#include "time/scheme.hpp"

namespace nd {
namespace {

class GeneralizedAlpha : public TimeScheme {
 public:
  explicit GeneralizedAlpha(double rho)
      : am_((2 * rho - 1) / (rho + 1)),
        af_(rho / (rho + 1)),
        gamma_(0.5 - am_ + af_),
        beta_(0.25 * (1 - am_ + af_) * (1 - am_ + af_)) {
    rule_ = {TimeRule::Shifted, af_};  // the law at Y, its slope times 1 - alpha_f
  }
  bool is_explicit() const override { return false; }
  StepCoefficients coefficients(double tau) const override {
    return {(1 - am_) / ((1 - af_) * beta_ * tau * tau), 1 / (1 - af_)};
  }
  // r = [F^{n+1-af} - af K_Theta U^n - am M A^n
  //      + (1-am) M (U^n/(beta tau^2) + V^n/(beta tau) + (1/(2 beta) - 1) A^n)] / (1-af)
  void rhs(const StepInputs &in, double tau, const State &old, std::vector<double> &r) const override {
    // M y, y = (1 - alpha_m) (U^n/(beta tau^2) + V^n/(beta tau) + (1/(2 beta) - 1) A^n) - alpha_m A^n
    in.mass_combination((1 - am_) / (beta_ * tau * tau), (1 - am_) / (beta_ * tau),
                        (1 - am_) * (0.5 / beta_ - 1) - am_, r);
    std::vector<double> own, &KtU = in.workspace(own);
    in.k_theta_u(old.U, KtU);
    const bool has_load = !in.F_new.empty();
    for (size_t i = 0; i < r.size(); ++i) {
      double ri = r[i] - af_ * KtU[i];
      if (has_load) ri += (1 - af_) * in.F_new[i] + af_ * in.F_old[i];
      r[i] = ri / (1 - af_);
    }
  }
  void predict(double tau, const State &old, std::vector<double> &U) const override {
    predict_taylor(tau, old, 0.5, U);
  }
  bool predicts_constant_acceleration() const override { return true; }
  double velocity_slope(double tau) const override { return gamma_ / (beta_ * tau); }  // Newmark's
  void update(double tau, const State &old, State &next) const override {
    newmark_update(beta_, gamma_, tau, old, next);
  }
  // the balance at t^{n+1-alpha}: A at the alpha_m point, U and F at the alpha_f point
  double mean_weight() const override { return af_; }
  void mean_acceleration(double, const State &old, const State &next, std::vector<double> &A) const override {
    A.resize(old.A.size());
    for (size_t i = 0; i < A.size(); ++i) A[i] = (1 - am_) * next.A[i] + am_ * old.A[i];
  }

 private:
  double am_, af_, gamma_, beta_;
};

}  // namespace

std::unique_ptr<TimeScheme> make_generalized_alpha_scheme(const std::vector<double> &params) {
  require_parameter(params[0], 0, 1, "rho_inf (params[0])");
  return std::make_unique<GeneralizedAlpha>(params[0]);
}

}  // namespace nd
