// A time scheme (docs/design.md §3), one file per scheme behind this interface, and
// the registry from ND_SCHEME_* ids. The step driver knows no scheme by name.
//
// An implicit step solves for U = U^{n+1}
//   G(U) = (c M + K_Theta) U + kappa sum_q (w_q/gamma_q) phi(P_q(U), P_q^n) b_q - r = 0
// where phi is the contact law taken by the scheme's time rule (contact_rule). An explicit step predicts U^{n+1},
// then solves M A^{n+1} = F^{n+1} - K_Theta U^{n+1} - N(U^{n+1}).
#pragma once
#include <cmath>
#include <memory>
#include <vector>

#include "assembly/contact.hpp"
#include "contact/law.hpp"
#include "time/products.hpp"
#include "time/state.hpp"

namespace nd {

struct StepCoefficients {
  double c, kappa;
};

// What a right-hand side may read: the products of the state at t^n (M U^n,
// M V^n, M A^n, K U^n, from the pass that also gave its energy: a
// right-hand side needs no product of its own), the contact rows for
// K_Theta U^n, and the loads at both ends of the step (F_old, F_new both
// empty when there is no load).
struct StepInputs {
  const Products &old;
  const ContactPoints &contact;
  double theta;  // Nitsche's Theta
  const std::vector<double> &F_old, &F_new;
  // r = a M U^n + b M V^n + e M A^n (e = 0 when A^n is not valid)
  void mass_combination(double a, double b, double e, std::vector<double> &r) const;
  // K_Theta U^n = K U^n - Theta sum_q w_q gamma_q (s_q.U^n) s_q
  void k_theta_u(const std::vector<double> &U, std::vector<double> &out) const;
  // where a right-hand side may put K_Theta U^n (its memory kept from step
  // to step), or null: a vector of its own
  std::vector<double> *work = nullptr;
  std::vector<double> &workspace(std::vector<double> &own) const { return work ? *work : own; }
};

class TimeScheme {
 public:
  virtual ~TimeScheme() = default;
  virtual bool is_explicit() const = 0;
  // Amplifies every undamped oscillation whatever the step (theta < 1/2,
  // Newmark gamma < 1/2): refused unless the caller insists.
  virtual bool always_unstable() const { return false; }
  // Stable for omega tau up to this limit (infinite: unconditionally stable).
  virtual double stability_limit() const { return INFINITY; }
  // Does the state carry A^n (Remark 3.2 at t^0)? The hybrid scheme needs none.
  virtual bool uses_acceleration() const { return true; }
  virtual StepCoefficients coefficients(double tau) const = 0;  // implicit schemes
  virtual void rhs(const StepInputs &in, double tau, const State &old, std::vector<double> &r) const = 0;
  // The first guess of U^{n+1}; for an explicit scheme, U^{n+1} itself.
  virtual void predict(double tau, const State &old, std::vector<double> &U) const = 0;
  // Whether predict() is exact when the acceleration does not change over
  // the step (the Taylor predictor of the Newmark family): a step may then
  // be its predictor (fast/predictor_check.hpp).
  virtual bool predicts_constant_acceleration() const { return false; }
  // Where the step takes the contact law (contact/law.hpp): at U^{n+1} by
  // default; the law applies the rule (apply_rule), the scheme names it.
  const TimeRule &contact_rule() const { return rule_; }
  // Implicit: V^{n+1}, A^{n+1} from U^{n+1}. Explicit: V^{n+1} from A^{n+1}.
  virtual void update(double tau, const State &old, State &next) const = 0;
  // The equation a step satisfies on the free DOFs, M Abar + K_Theta Ubar +
  // Nbar = Fbar, with Ubar = (1-a) U^{n+1} + a U^n, Fbar likewise (a =
  // mean_weight()), Nbar from the scheme's contact term and Abar from
  // mean_acceleration(). The reactions and the obstacle's work come from it.
  virtual double mean_weight() const { return 0; }
  // The update's V^{n+1} is affine in the step's unknown: in U^{n+1} for an
  // implicit scheme, in A^{n+1} for an explicit one; its slope (the damping
  // term C Vbar of docs/design.md §10.5 is formed from it and from update()).
  virtual double velocity_slope(double tau) const = 0;
  virtual void mean_acceleration(double tau, const State &old, const State &next, std::vector<double> &A) const {
    (void)tau, (void)old;
    A = next.A;
  }

 protected:
  TimeRule rule_;  // set by a scheme whose contact term is not the law at U^{n+1}
};

// The registry: how many parameters an ND_SCHEME_* id reads (throws
// ND_ERR_SCHEME for an unknown id), and the scheme for checked parameters
// (throws ND_ERR_SCHEME naming the parameter that is out of range).
int scheme_parameter_count(int id);
std::unique_ptr<TimeScheme> make_scheme(int id, const std::vector<double> &params);

// The entries of the registry, one per scheme file.
std::unique_ptr<TimeScheme> make_theta_scheme(const std::vector<double> &params);
std::unique_ptr<TimeScheme> make_newmark_scheme(const std::vector<double> &params);
std::unique_ptr<TimeScheme> make_hybrid_scheme(const std::vector<double> &params);
std::unique_ptr<TimeScheme> make_generalized_alpha_scheme(const std::vector<double> &params);

// U = U^n + tau V^n (+ w tau^2 A^n when w != 0 and A^n is known): the
// predictor the schemes share; w = 1/2 (Newmark's Taylor predictor) or the
// theta-scheme's theta makes it exact at constant acceleration.
void predict_taylor(double tau, const State &old, double w, std::vector<double> &U);

// A step at constant acceleration, the predictor's (predicts_constant_acceleration):
// U^{n+1} given, A^{n+1} = A^n and V^{n+1} = V^n + tau A^n, what the Newmark
// relations give from that U^{n+1} without c (U^{n+1} - U^n)'s round-off
// (c = 1/(beta tau^2) times the round-off of U).
void constant_acceleration_update(double tau, const State &old, State &next);

// A parameter check shared by the schemes: lo <= x <= hi (NaN fails).
void require_parameter(double x, double lo, double hi, const char *what);

}  // namespace nd
