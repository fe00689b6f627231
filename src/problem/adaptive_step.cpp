// Adaptive time steps (docs/design.md §10.8): nd_step takes one accepted
// step of a size the step control chooses. A step is tried as a fixed step
// of that size (Problem::step_once), judged before the problem commits it
// (judge_step), and retried smaller when rejected or when it failed in a
// way a smaller step can mend: a failed try leaves the problem exactly as
// it was, so the accepted step is bitwise the fixed step of its size.
#include <algorithm>
#include <cmath>
#include <string>

#include "common/format.hpp"
#include "problem/problem.hpp"
#include "solve/products.hpp"

namespace nd {

namespace {

// A try the control rejects (not an error of the problem): retried with
// tau_retry; `landing`: cut to end at the first touch
class Rejected : public Error {
 public:
  Rejected(std::string message, double retry, bool land)
      : Error(ND_ERR_ACCURACY, std::move(message)), tau_retry(retry), landing(land) {}
  double tau_retry;
  bool landing;
};

// the failures a smaller step can mend: Newton, a blow-up, a gain of
// energy or a sinking the guards refused, A = c M + K_Theta indefinite
// (c grows as tau falls)
bool mended_by_smaller_steps(int code) {
  return code == ND_ERR_NEWTON || code == ND_ERR_NONFINITE_STATE || code == ND_ERR_ENERGY_GROWTH ||
         code == ND_ERR_PENETRATION || code == ND_ERR_INDEFINITE;
}

// at most this many tries a step (the ladder from tau_max to tau_min is
// shorter than this for any tau_min/tau_max above 1e-15)
constexpr int kMostTries = 64;

}  // namespace

void Problem::use_timestep(double tau) {
  if (tau == def_.tau && (integrator_ || kept_integrators_.empty())) return;
  const uint64_t of = disc_ ? disc_->id : 0;
  if (integrator_) kept_integrators_.insert(kept_integrators_.begin(), KeptIntegrator{def_.tau, of, std::move(integrator_)});
  def_.tau = tau;
  for (auto it = kept_integrators_.begin(); it != kept_integrators_.end(); ++it)
    if (it->tau == tau && it->of == of && of != 0) {
      integrator_ = std::move(it->in);
      kept_integrators_.erase(it);
      break;
    }
  // (of another discretization: of no use again)
  kept_integrators_.erase(std::remove_if(kept_integrators_.begin(), kept_integrators_.end(),
                                         [of](const KeptIntegrator &k) { return k.of != of; }),
                          kept_integrators_.end());
  if (kept_integrators_.size() > static_cast<size_t>(kKeptSizes)) kept_integrators_.resize(kKeptSizes);
}

void Problem::adaptive_step() {
  const AdaptiveOptions &o = def_.adaptive;
  if (communicator_size(def_.comm.get()) > 1)
    fail(ND_ERR_STATE, "adaptive time steps on several MPI ranks are not supported yet: step with a fixed time step "
                       "(nd_problem_set_adaptive_timestep with tolerance 0)");
  const double tau_before = def_.tau;
  const double next = state_ready_ ? state_.control.tau_next : 0;
  double tau = next > 0 ? next : ladder_below(o, std::clamp(def_.tau, o.tau_min, o.tau_max));
  Attempt attempt;
  for (int tries = 1;; ++tries) {
    use_timestep(tau);
    try {
      step_once(&attempt);
      count(counters_.get(), &Counters::steps_accepted);
      return;
    } catch (const Rejected &r) {
      count(counters_.get(), &Counters::steps_rejected);
      if (r.landing) {
        attempt.may_land = false;  // (one cut a step: the landing is then taken as it comes)
      } else if (tau <= o.tau_min || tries == kMostTries) {
        use_timestep(tau_before);  // (the problem as it was: the next step starts from the same size)
        fail(ND_ERR_ACCURACY, std::string(r.what()) + " at the smallest step tau_min = " + num(o.tau_min) +
                                  "; the step was not taken: raise the tolerance or lower tau_min");
      }
      tau = r.tau_retry;
      attempt.retried = true;
    } catch (const Error &e) {
      if (!mended_by_smaller_steps(e.code())) {
        use_timestep(tau_before);
        throw;
      }
      if (tau <= o.tau_min || tries == kMostTries) {
        use_timestep(tau_before);
        fail(e.code(), std::string(e.what()) + " (adaptive steps: at the smallest step tau_min = " + num(o.tau_min) + ")");
      }
      count(counters_.get(), &Counters::steps_rejected);
      tau = ladder_below(o, 0.5 * tau);
      attempt.retried = true;
    }
  }
}

void Problem::judge_step(const Attempt &attempt, const State &from, State &next, const Products &next_products) {
  const AdaptiveOptions &o = def_.adaptive;
  const Discretization &d = *disc_;
  const double tau = def_.tau;
  if (integrator_->scheme->is_explicit())
    fail(ND_ERR_STATE, "adaptive time steps are for the implicit schemes: an explicit scheme steps at its critical "
                       "step (nd_problem_estimate_critical_timestep)");
  // the step that first touches ends at the touch
  if (attempt.may_land && d.contact.size() > 0) {
    PointValues at_old, at_new;
    const PointValues &was = state_points(d, from, products_, at_old, d.counters);
    // (in contact already: no first touch, and the new state's points need no evaluation)
    // (the normal values: with friction the points' tangential ones follow them)
    const size_t nq = std::min(was.P.size(), d.contact.size());
    const bool touching = std::any_of(was.P.begin(), was.P.begin() + static_cast<std::ptrdiff_t>(nq),
                                      [](double P) { return P > 0; });
    std::vector<double> rate(touching ? 0 : d.contact.size());
    for (size_t q = 0; q < rate.size(); ++q) rate[q] = d.contact.a[q].dot(from.V.data());
    const double s = touching ? 1 : first_touch(was.P, state_points(d, next, next_products, at_new, d.counters).P, was.un, rate, tau);
    if (s < 1 && s * tau >= o.tau_min)
      throw Rejected("the step makes the first contact points active", s * tau, true);
  }
  // the step's gain of the energy balance (monitor/guards.hpp: its value
  // at the states the guard evaluated), above the lowest the run reached
  const GuardState &was = from.guard, &now = next.guard;
  double gain = 0;
  if (std::isfinite(now.balance) && std::isfinite(was.balance))
    gain = now.balance - std::max(was.balance, std::isfinite(was.balance_low) ? was.balance_low : was.balance);
  const double ratio = step_error(o, from, next, tau, gain, std::max(now.budget, now.E_top));
  if (ratio > 1)
    throw Rejected("the error estimate of the step to t = " + num(next.t) + " is " + num(ratio) +
                       " times the tolerance " + num(o.tolerance),
                   size_after_rejected(o, tau, ratio), false);
  StepControl &c = next.control;
  c.ratio = ratio;
  c.tau_last = tau;
  c.hold = attempt.retried ? kHoldSteps : std::max(0.0, from.control.hold - 1);
  c.tau_next = size_after_accepted(o, tau, ratio);
  if (c.hold > 0) c.tau_next = std::min(c.tau_next, tau);
}

}  // namespace nd
