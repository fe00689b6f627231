// The step driver (docs/architecture.md §2): one step from t^n to t^{n+1},
// naming no scheme, law or obstacle. advance() below reads as the method
// does; each phase is a method of Step:
//   start         time, loads, gaps and prescribed motion at t^{n+1}
//   contact_term  the law over the step: P^n, and what the bounds start from
//   explicit_step M A^{n+1} = F - K_Theta U - N(U) at the predicted U
//   implicit_step the scheme's right-hand side, then the cheapest solve that
//                 is exact: the predictor, one solve without contact points,
//                 or Newton (condensed on the contact points, then full)
//   finish        V and A, finiteness and the loads' work, the new state's
//                 products (energy, next right-hand side), the applied
//                 contact term, the obstacle's work, the reactions
// The fast paths each ask whether they apply (the law's traits, the
// definition's switches); what they skip is shown not to change the bits.
#include "problem/integrator.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "common/format.hpp"
#include "common/simd.hpp"
#include "monitor/energies.hpp"
#include "monitor/guards.hpp"
#include "parallel/agreement.hpp"
#include "problem/forces.hpp"
#include "solve/friction.hpp"
#include "solve/clamped_coupling.hpp"
#include "solve/newton.hpp"
#include "fast/predictor_check.hpp"
#include "solve/products.hpp"

namespace nd {

namespace {

// Whether the new state is finite, and its W (the loads' trapezoidal work
// added to old.W), over the rows each rank has right: with split rows its
// own (the ranks' counts and sums joined rank after rank, the same bits on
// every rank), else every row (in four sums, below). The test and the sum
// in their own loops, in registers: one loop summing into the array
// `gather` reads kept the running sum in memory, a store and a load a row.
bool finite_with_work(const Discretization &d, const State &old, const std::vector<double> &F_old, State &next) {
  const Share *mine = d.rows_split ? d.rows.get() : nullptr;
  const RowSet rows = own_rows(mine);
  const int64_t n = static_cast<int64_t>(next.U.size()), m = rows.size(n);
  const std::vector<double> &F = next.load();
  const bool loaded = !F.empty(), acc = next.A.size() == next.U.size();
  const double *U = next.U.data(), *V = next.V.data(), *A = next.A.data(), *U0 = old.U.data();
  // |x| <= max is false for inf and NaN: no branch per row
  // (as int: & of two bools reads as a mistaken &&)
  auto finite = [](double x) -> int { return std::fabs(x) <= std::numeric_limits<double>::max(); };
  int ok = 1;
  if (!mine) {
    const size_t all = static_cast<size_t>(n);
    ok = all_finite(U, all) && all_finite(V, all) && (!acc || all_finite(A, all));
  } else {
    for (int64_t k = 0; k < m; ++k) {
      const int64_t i = rows[k];
      ok &= finite(U[i]) & finite(V[i]) & (!acc || finite(A[i]));
    }
  }
  auto term = [&](int64_t i) { return 0.5 * (F[i] + F_old[i]) * (U[i] - U0[i]); };
  if (!mine) {
    // in four sums (i mod 4), not one chain of n dependent adds, each
    // waiting on the one before: that latency, not memory, bounds the pass
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    int64_t i = 0;
    if (loaded) {
      for (; i + 3 < n; i += 4) s0 += term(i), s1 += term(i + 1), s2 += term(i + 2), s3 += term(i + 3);
      if (i < n) s0 += term(i);
      if (i + 1 < n) s1 += term(i + 1);
      if (i + 2 < n) s2 += term(i + 2);
    }
    next.W = old.W + ((s0 + s1) + (s2 + s3));
    return ok;
  }
  double work = 0;
  if (loaded)
    for (int64_t k = 0; k < m; ++k) work += term(rows[k]);
  double sums[2] = {work, ok ? 0.0 : 1.0};  // the work, the ranks with a non-finite value
  gather(*mine, {}, sums, 2);
  next.W = old.W + sums[0];
  return sums[1] == 0;
}

// A step may be its predictor (fast/predictor_check.hpp) when the scheme's
// predictor is exact at constant acceleration, the state has one, and the
// last step was its predictor, or applied no contact term and every
// kPredictorProbe-th step tries it (a deformed body's free flight pays one
// pass in kPredictorProbe for the try). Serial operators, every DOF with
// mass. From the state alone: a resumed run tries the same steps.
constexpr int64_t kPredictorProbe = 16;
bool predictor_may_solve(const Integrator &in, const Discretization &d, const Definition &def, const State &old,
                         bool moving) {
  // (a law zero where free: else a free flight has forces, no constant acceleration)
  // (damping: G's C term is not among the state's products the check reads)
  if (moving || !def.predicted_steps || d.damped() || !in.scheme->predicts_constant_acceleration() ||
      !d.contact_law->traits().zero_when_free || !old.A_valid || d.rows || !in.held.empty() || !d.massless.empty())
    return false;
  if (old.last_iterations == 0) return true;
  for (double phi : old.phi)
    if (phi != 0) return false;
  return old.n % kPredictorProbe == 0;
}

// to = from, a tangent history (TangentLog), into memory that holds its
// largest form (reserve_tangent_log), reserved the first time: a history
// grows step by step, and each state's copy took a little more memory
void copy_log(TangentLog &to, const TangentLog &from, size_t n_points) {
  if (!from.i.empty()) reserve_tangent_log(to, static_cast<int64_t>(n_points));
  to.i.assign(from.i.begin(), from.i.end());
  to.x.assign(from.x.begin(), from.x.end());
}

class Step {
 public:
  Step(Integrator &in, Discretization &d, const Definition &def, const State &old, const Products &old_products,
       const StepData &at_new, StateWithProducts &&storage)
      : in_(in), d_(d), def_(def), old_(old), old_held_(old_products), at_new_(at_new), scheme_(*in.scheme),
        tau_(in.tau), next(reuse_storage(std::move(storage.state))),
        next_products(reuse_storage(std::move(storage.products))) {}

  void start();
  void contact_term();
  void predict() { scheme_.predict(tau_, old_, next.U); }
  bool is_explicit() const { return scheme_.is_explicit(); }
  void explicit_step();
  void implicit_step();
  void finish();

 private:
  void new_state_products(bool shown_free, PointValues *known, const HeldPoints *held);
  void prescribed_work(const Discretization &d, std::vector<double> &R);
  void newton(std::vector<double> &r);
  void damping_rhs(std::vector<double> &r);
  void damping_dissipation();

  Integrator &in_;
  Discretization &d_;
  const Definition &def_;
  const State &old_;
  const Products &old_held_;  // old_'s products as the problem holds them (current or not)
  const StepData &at_new_;
  const TimeScheme &scheme_;
  const double tau_;

 public:
  State next;  // the state at t^{n+1}, made aside (the problem swaps it in once accepted)
  Products next_products;  // its products, made by the step (the energy, the next right-hand side)

 private:
  // the load at t^n as the step reads it (zeros when only t^{n+1} has one)
  std::shared_ptr<const std::vector<double>> no_load_before_;
  const std::vector<double> *F_old_ = nullptr;
  // the contact term of the step: P^n with the obstacle where it was at t^n,
  // P(U) with it where it is at t^{n+1} (docs/design.md §8)
  ContactLaw law_, old_law_;
  const std::vector<double> *gap_old_ = nullptr;
  Products scratch_;  // only when the state has none (restart, new state): the same pass
  const Products *old_products_ = nullptr;
  PointValues old_points_;
  bool same_below_zero_ = false, may_leave_points_ = false;
  // what the solve left: an implicit step that is its predictor (updated,
  // its pass made); the condensed Newton's check updated the state and made
  // its pass; Newton's solution shown contact-free by the bound from law.Un
  bool predicted_ = false, made_ = false, bounded_ = false;
  // prescribed motion (docs/design.md §10.5): the clamped DOFs move this
  // step (next.Uc set), read at the scheme's mean point
  bool moving_ = false;
  ClampedMean clamped_mean_;
  const std::vector<double> *shift_ = nullptr;  // the step's shift of the slip references (null: none)
};

void Step::start() {
  const size_t n = old_.U.size();
  next.n = old_.n + 1;
  next.t_ref = old_.t_ref, next.n_ref = old_.n_ref, next.tau_ref = old_.tau_ref;
  if (old_.tau_ref != tau_) next.t_ref = old_.t, next.n_ref = old_.n, next.tau_ref = tau_;
  next.t = next.t_ref + static_cast<double>(next.n - next.n_ref) * tau_;
  next.F = at_new_.F;  // (shared, not copied)
  // an empty load vector means no load; both ends of the step need one if either has
  auto zeros = [n] { return std::make_shared<const std::vector<double>>(n, 0.0); };
  if (next.load().empty() && !old_.load().empty()) next.F = zeros();  // nodal forces withdrawn
  if (!next.load().empty() && old_.load().empty()) no_load_before_ = zeros();
  F_old_ = no_load_before_ ? no_load_before_.get() : &old_.load();
  next.F_fixed = at_new_.F_fixed;
  next.gap = at_new_.gap;
  // friction: the slip reference of the step is the state's, moved with the
  // obstacle's tangential displacement (slip is relative: docs/design.md §10.2)
  next.D_friction = old_.D_friction;
  next.by_region = old_.by_region;  // (end_friction_step adds the step's)
  next.W_geometry = old_.W_geometry;  // (Problem::step adds this step's re-linearisation)
  if (d_.contact.m > 1) {
    next.slip = old_.slip;
    shift_ = at_new_.slip_shift && !at_new_.slip_shift->empty() ? at_new_.slip_shift : nullptr;
    if (shift_ && shift_->size() != next.slip.size())
      fail(ND_ERR_INTERNAL, "the shift of the slip references does not match them");
    if (shift_)
      for (size_t j = 0; j < next.slip.size(); ++j) next.slip[j] += (*shift_)[j];
  }
  // prescribed motion: the clamped DOFs' U, V, A at t^{n+1} (a definition
  // without values brings a moved support back to 0)
  const bool given = at_new_.Uc && !at_new_.Uc->empty();
  moving_ = d_.clamped && (given || !old_.Uc.empty());
  next.W_prescribed = old_.W_prescribed;
  if (!moving_) return;
  if (given) next.Uc = *at_new_.Uc;
  else next.Uc.assign(d_.clamped->dofs.size(), 0.0);
  require_motion_supported(d_, next, !in_.held.empty() || in_.points, scheme_.is_explicit());
  clamped_mean_ = prescribed_update(scheme_, tau_, old_, next);
}

void Step::contact_term() {
  const Discretization &d = d_;
  law_ = ContactLaw{&d.contact, d.theta, &scheme_, nullptr, next.gap.empty() ? nullptr : next.gap.data(), d.counters};
  law_.point_law = d.contact_law.get();
  if (!next.slip.empty()) law_.gap_t = next.slip.data();
  gap_old_ = at_new_.gap_old ? at_new_.gap_old : &old_.gap;
  old_law_ = ContactLaw{&d.contact, d.theta, nullptr, nullptr, gap_old_->empty() ? nullptr : gap_old_->data(),
                        d.counters};
  if (!old_.slip.empty()) old_law_.gap_t = old_.slip.data();
  law_.buffers = &in_.contact_scratch;
  // the products of the state at t^n: its P_q(U^n) (the implicit schemes'
  // contact terms read them) and what the right-hand side is made of
  old_products_ = &products_of(d, old_, old_held_, scratch_, scheme_.uses_acceleration());
  // points the step before left unevaluated (PointValues::ref): the bound
  // from their reference, whose P_q stand as P^n (all <= 0, as P^n's are);
  // a law that reads more of P^n than that (a scheme changed since) has
  // them evaluated
  const PointReference *ref = old_products_->points.ref.get();
  same_below_zero_ = same_for_nonpositive_Pn(scheme_.contact_rule(), d.contact_law->traits());
  // (curved obstacles: P^n at this step's g^n, not the state's, evaluated)
  if (at_new_.gap_old || (ref && !same_below_zero_)) {
    ContactLaw at_old = state_contact_law(d, old_);
    if (at_new_.gap_old) at_old.gap = gap_old_->empty() ? nullptr : gap_old_->data();
    at_old.counters = d.counters;
    at_old.local = true;  // (every rank evaluates every point: no message)
    at_old.P_all(old_.U.data(), old_points_.P);
    ref = nullptr;
  }
  law_.Pn = ref ? &ref->P : old_points_.P.empty() ? &old_products_->points.P : &old_points_.P;
  if (def_.contact_bounds) {
    const std::vector<double> &Un = ref ? ref->U : old_.U, &gap_n = ref ? ref->gap : *gap_old_;
    law_.Un = Un.data(), law_.gap_n = gap_n.empty() ? nullptr : gap_n.data();
    if (ref) law_.free_reach_n = ref->free_reach;
  }
  // Shown contact-free by the bound (every law and its slope zero: phi = 0),
  // the new state's points are left unevaluated, the bound's reference in
  // their place, from which the next step's bound is made: a free flight
  // evaluates them only when the body has come near enough the obstacle
  // since the last evaluation for the bound to fail. Where the scheme's law
  // reads only that P^n <= 0 (the next step's, TimeScheme), and every rank
  // holds the whole state (a distributed state's points stay the ranks').
  may_leave_points_ = same_below_zero_ && d.contact_law->traits().zero_when_free && def_.contact_bounds &&
                      !in_.points && in_.held.empty() && !d.contact.a.empty();
  // P_q(U^{n+1}) and u_n - g0 if the step makes them (explicit, or Newton), for the products
  clear_keeping_memory(in_.at_solution);
}

// the new state's pass (compute_products), its points left unevaluated
// where shown free
void Step::new_state_products(bool shown_free, PointValues *known, const HeldPoints *held) {
  std::shared_ptr<const PointReference> from;
  if (shown_free && may_leave_points_) from = point_reference(d_, old_, *old_products_, penetration_limit(d_, def_.guards, old_.guard));
  if (from) compute_products_bounded(d_, next, next_products, std::move(from));
  else compute_products(d_, next, next_products, known, held);
}

// The moving supports' share of the step's work: the loads on the clamped
// DOFs by the trapezoid, as W's, and the reactions R (with the clamped
// rows' own block) times dU_c: W_prescribed, the work of the prescribed
// motion on the body. With the hybrid scheme R is the midpoint equation's,
// so that E_Theta - W - W_obstacle - W_prescribed holds as without motion.
void Step::prescribed_work(const Discretization &d, std::vector<double> &R) {
  add_clamped_block(d, clamped_mean_, R);
  const std::vector<double> &F1 = next.F_fixed, &F0 = old_.F_fixed;
  double w = 0, wr = 0;
  for (size_t c = 0; c < R.size(); ++c) {
    const double dU = next.Uc[c] - (old_.Uc.empty() ? 0.0 : old_.Uc[c]);
    wr += R[c] * dU;
    if (!F1.empty() || !F0.empty()) w += 0.5 * ((F1.empty() ? 0.0 : F1[c]) + (F0.empty() ? 0.0 : F0[c])) * dU;
  }
  next.W += w;
  next.W_prescribed += wr;
}

void Step::explicit_step() {
  next.last_iterations = 0;
  // massless DOFs: their static equilibrium with U_f predicted (problem/massless.hpp)
  if (in_.massless)
    next.last_iterations = in_.massless->solve(def_.newton, next.load(), next.gap, next.slip, next.t, next.U);
  if (!d_.damped()) {
    d_.equilibrium_acceleration(next, def_.solver, false, true, &in_.at_solution);  // every step: M factored once, kept
    return;
  }
  // damping: V^{n+1} = V_known + slope A^{n+1} (the update with A^{n+1} = 0 gives V_known)
  State known;
  known.U = next.U;
  known.A.assign(old_.U.size(), 0.0);
  scheme_.update(tau_, old_, known);
  const Discretization::DampedVelocity dv{&known.V, scheme_.velocity_slope(tau_), in_.damped_mass_factor.get()};
  d_.equilibrium_acceleration(next, def_.solver, false, true, &in_.at_solution, &dv);
}

// The damping term of G, kappa C Vbar, Vbar = (1-a) V^{n+1} + a V^n (a the
// scheme's mean_weight), V^{n+1} = V* + s (U - U^n) affine in U (s the
// velocity slope, V* the update's V at U = U^n): kappa (1-a) s C U is in A
// (Integrator::damping), the rest, kappa C z with z = (1-a)(V* - s U^n) + a V^n,
// leaves the right-hand side. One update and one product with C, whatever the scheme.
void Step::damping_rhs(std::vector<double> &r) {
  const size_t n = old_.U.size();
  const double a = scheme_.mean_weight(), s = scheme_.velocity_slope(tau_);
  State at_old;
  at_old.U = old_.U;
  scheme_.update(tau_, old_, at_old);
  std::vector<double> z(n), Cz(n);
  for (size_t i = 0; i < n; ++i) z[i] = (1 - a) * (at_old.V[i] - s * old_.U[i]) + a * old_.V[i];
  d_.C.multiply(z.data(), Cz.data());
  count(d_.counters, &Counters::spmv);
  for (size_t i = 0; i < n; ++i) r[i] -= in_.coef.kappa * Cz[i];
}

// dD = (U^{n+1} - U^n) . C Vbar: the work of the damping force the step
// applied (Vbar as in damping_rhs); for the hybrid scheme tau Vbar' C Vbar >= 0
void Step::damping_dissipation() {
  next.D_damping = old_.D_damping;
  if (!d_.damped()) return;
  const size_t n = old_.U.size();
  const std::vector<double> Vbar = step_mean(next.V, old_.V, scheme_.mean_weight());
  std::vector<double> CV(n);
  d_.C.multiply(Vbar.data(), CV.data());
  count(d_.counters, &Counters::spmv);
  double dD = 0;
  for (size_t i = 0; i < n; ++i) dD += (next.U[i] - old_.U[i]) * CV[i];
  if (moving_) {  // the whole body's: the moving supports' rows and columns of C too
    std::vector<double> dU(n), dUc(next.Uc.size());
    for (size_t i = 0; i < n; ++i) dU[i] = next.U[i] - old_.U[i];
    for (size_t c = 0; c < dUc.size(); ++c) dUc[c] = next.Uc[c] - (old_.Uc.empty() ? 0.0 : old_.Uc[c]);
    dD += clamped_damping_work(d_, clamped_mean_, dU.data(), Vbar.data(), dUc);
  }
  next.D_damping += dD;
}

void Step::implicit_step() {
  std::vector<double> &r = in_.rhs;  // (its memory kept from step to step)
  r.clear();                         // (the scheme's rhs finds it empty, as a new vector)
  scheme_.rhs(StepInputs{*old_products_, d_.contact, d_.theta, *F_old_, next.load(), &in_.scratch}, tau_, old_, r);
  if (d_.damped()) damping_rhs(r);
  if (moving_) subtract_clamped_coupling(d_, clamped_mean_, in_.coef.kappa, r.data());  // the lifting
  if (predictor_may_solve(in_, d_, def_, old_, moving_)) {  // the new state's pass, made now, checks the predictor
    constant_acceleration_update(tau_, old_, next);
    new_state_products(may_leave_points_ && law_.certainly_free(next.U), nullptr, nullptr);
    predicted_ = predictor_solves_step(law_, in_.coef.c, r, next, next_products, in_.scratch);
    if (predicted_) next.last_iterations = 0, count(d_.counters, &Counters::predicted_steps);
    else  // (U is still the predictor: where the solves start)
      next_products = reuse_storage(std::move(next_products));
  }
  if (predicted_) return;  // nothing to solve: the new state and its pass are made
  if (d_.contact.a.empty()) {  // no contact: one solve with the cached factor
    next.U.swap(r);            // r: the predictor, where an iterative solve starts
    if (in_.held.empty()) in_.A_factor->solve_from(next.U.data(), r.data());
    else in_.A_factor->solve_at(next.U.data(), static_cast<int64_t>(old_.U.size()), in_.held, r.data());
    next.last_iterations = 1;
    return;
  }
  newton(r);
}

void Step::newton(std::vector<double> &r) {
  Integrator &in = in_;
  law_.halo = in.halo.get();
  // a distributed state: every iterate is right at the DOFs of the
  // contact points a rank reads (every point's, or with a halo the
  // points it holds), so each rank evaluates them itself
  if (!in.held.empty()) (in.halo ? law_.halo_here : law_.local) = true;
  law_.held = in.points.get();
  NewtonSystem sys{&in.A, in.tangent.get(), &d_.M, in.coef.c, in.coef.kappa, &law_, d_.rows.get(), d_.rows_split};
  sys.blocks = in.A_blocks.get();
  sys.work = &in.newton;
  sys.complete = in.held.empty();
  sys.guess = in.A_factor->starts_from_guess();
  // the points at the solution from Newton's last residual, for the new
  // state's products where that pass is the products' (every point, on a
  // whole state: Newton hands them over only then), the same bits
  PointValues *solution_points = in.held.empty() && !in.points ? &in.at_solution : nullptr;
  in.tangent->begin_step(old_.tangent_log);
  NewtonResult res;
  if (in.condensed) {  // condensed on the contact points (docs/design.md §4); the full Newton from its end if need be
    // its last residual checked from the new state's products, made
    // then: in one process (a distributed state, Integrator::held, needs
    // several ranks) with every DOF with mass, where the products are the
    // state's own, whole
    auto update_and_pass = [&]() -> const Products & {
      scheme_.update(tau_, old_, next);
      compute_products(d_, next, next_products);
      made_ = true;
      return next_products;
    };
    std::function<const Products &()> products_at;  // (by reference: no allocation)
    // (damping: G's C term is not among the products)
    if (!d_.rows && d_.massless.empty() && !d_.damped()) products_at = std::ref(update_and_pass);
    const CondensedResult cr = newton_condensed(sys, *in.A_factor, *in.condensed, in.max_rank, r, def_.newton, next.U,
                                                solution_points, products_at ? &products_at : nullptr);
    res = cr.newton;
    if (!res.converged) {
      if (made_) next_products = reuse_storage(std::move(next_products)), made_ = false;  // (Newton goes on from U)
      const int before = res.iterations;
      res = newton_solve(sys, r, def_.newton, next.U, solution_points);
      res.iterations += before;
    }
  } else {
    res = newton_solve(sys, r, def_.newton, next.U, solution_points);
  }
  if (!res.converged)
    fail(ND_ERR_NEWTON, "Newton did not converge in " + std::to_string(res.iterations) + " iterations at t = " +
                            num(next.t) + " (residual " + num(res.residual) + ", tolerance " + num(res.tolerance) +
                            "); the step was not taken: try half the time step, or let the library choose it "
                            "(nd_problem_set_adaptive_timestep)");
  next.last_iterations = res.iterations;
  bounded_ = res.bounded;
  const TangentLog *history = in.tangent->log();
  if (history) copy_log(next.tangent_log, *history, d_.contact.size());
}

void Step::finish() {
  const Discretization &d = d_;
  // no contact solve: the history stays
  if (next.tangent_log.i.empty()) copy_log(next.tangent_log, old_.tangent_log, d.contact.size());
  if (!predicted_ && !made_) scheme_.update(tau_, old_, next);
  // Massless DOFs (mass redistribution): no equation holds their V and A, and
  // the schemes' recursions for them are at best neutral (the hybrid's
  // V^{n+1} = 2 dU/tau - V^n keeps every error). They feed nothing back (M's
  // columns are zero there): difference quotients, first order, bounded.
  for (size_t i = 0; i < d.massless.size(); ++i)
    if (d.massless[i]) {
      next.V[i] = (next.U[i] - old_.U[i]) / tau_;
      if (next.A_valid) next.A[i] = (next.V[i] - old_.V[i]) / tau_;
    }
  next.partial = !in_.held.empty();  // (an explicit step has none)
  if (!finite_with_work(d, old_, *F_old_, next))
    fail(ND_ERR_NONFINITE_STATE,
         "the step to t = " + num(next.t) + " produced non-finite values; the step was not taken");
  next.total_iterations = old_.total_iterations + next.last_iterations;
  damping_dissipation();
  // The step's contact term phi_q: the obstacle moving by dg_q against the
  // mean pressure -phi_q/gamma_q does the work -sum_q (w_q/gamma_q) phi_q dg_q.
  // Hybrid, Theta = 1: the step times dU = U^{n+1} - U^n, with p_q.dU = dP_q + dg_q
  // (P^n with g^n, P^{n+1} with g^{n+1}), gives
  //   dE_Theta = F^{n+1/2}.dU - sum_q (w_q/gamma_q) phi_q dg_q - D,
  //   D = sum_q (w_q/gamma_q) (phi_q dP_q - d([P_q]_+^2)/2) >= 0, 0 unless a point changes sides.
  // One pass over the points: phi is also the applied pressure (kept in the state).
  // (the products of the new state: its energy for the guard, its P_q for
  // phi and for the next step, and the next right-hand side)
  // (at_solution: an explicit step's, or Newton's at its solution; empty: evaluated there)
  if (!predicted_ && !made_) new_state_products(bounded_, &in_.at_solution, in_.points.get());
  const bool unevaluated = next_products.points.ref != nullptr;
  std::vector<double> phi = std::move(next.phi);  // (empty, its memory reused)
  phi.assign(d.contact.size(), 0.0);
  next.W_obstacle = old_.W_obstacle;
  // with a distributed state's points: phi at the rank's points, the work of its own added over the ranks
  std::vector<double> dW(in_.points ? phi.size() : 0);
  const bool pp = law_.positive_part();
  auto apply = [&](size_t q) {
    double slope;
    law_.law(q, next_products.points.P[q], phi[q], slope, pp);
    if (phi[q] == 0) return;  // (a term -0 or +0 changes no sum of W_obstacle, which is never -0)
    const double w = -d.contact.w[q] / d.contact.gamma[q] * phi[q] * (law_.g(q) - old_law_.g(q));
    if (in_.points) dW[q] = w;
    else next.W_obstacle += w;
  };
  if (unevaluated) {
    // phi = 0 at every point: nothing applied, no work
  } else if (in_.points) {
    std::fill(phi.begin(), phi.end(), std::numeric_limits<double>::quiet_NaN());
    for (int64_t q : in_.points->points) apply(static_cast<size_t>(q));
  } else {
    for (size_t q = 0; q < phi.size(); ++q) apply(q);
  }
  // friction: the tangential values applied, the new slip reference, D_f (solve/friction.hpp)
  if (d.contact.m > 1) end_friction_step(law_, d, phi, shift_, next, next_products.points.P);
  if (d.clamped) {
    const double a = scheme_.mean_weight();
    std::vector<double> Abar;
    scheme_.mean_acceleration(tau_, old_, next, Abar);
    std::vector<double> Vbar;
    if (d.damped()) Vbar = step_mean(next.V, old_.V, a);
    next.reaction = clamped_residual(d, Abar, step_mean(next.U, old_.U, a), phi,
                                     step_mean(next.F_fixed, old_.F_fixed, a), &next.phi_t,
                                     d.damped() ? &Vbar : nullptr);
    if (moving_) prescribed_work(d, next.reaction);
  }
  next.phi = std::move(phi);
  if (in_.points) sum_points(d, next, next_products, dW);  // (collective: every rank's step comes here)
}

}  // namespace

StateWithProducts advance(Integrator &in, Discretization &d, const Definition &def, const State &old,
                          const Products &old_products, const StepData &at_new, StateWithProducts &&storage) {
  Step step(in, d, def, old, old_products, at_new, std::move(storage));
  step.start();
  step.contact_term();
  step.predict();  // the first guess of U^{n+1}; an explicit scheme's U^{n+1} itself
  if (step.is_explicit()) step.explicit_step();
  else step.implicit_step();
  step.finish();
  return StateWithProducts{std::move(step.next), std::move(step.next_products)};
}

}  // namespace nd
