#include "problem/integrator.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "assembly/coercivity.hpp"
#include "common/format.hpp"
#include "common/simd.hpp"
#include "monitor/energies.hpp"
#include "parallel/agreement.hpp"
#include "problem/forces.hpp"
#include "solve/newton.hpp"
#include "solve/predictor_check.hpp"
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

// The Newton tangent is symmetric (and positive definite with c M + K_Theta)
// iff Theta = 1, for a law whose tangent is (LawTraits::symmetric).
Structure tangent_structure(double theta, const LawTraits &law) {
  return theta == 1 && law.symmetric ? Structure::SymmetricPositiveDefinite : Structure::General;
}

// Newton refactors its tangent: when asked, or in 3D with an iterative solver
// (see make_integrator's choice below), or for a law whose blocks are not
// rank one or whose slope may be negative (the fallback, whatever was asked:
// the condensed Newton, the low-rank tangent and the updated factor add and
// drop terms phi' b_q p_q^T, phi' >= 0)
bool refactoring_tangent(const Definition &def, const Discretization &d) {
  return def.tangent == TangentChoice::Refactor || !rank_one_updates_apply(d.contact_law->traits()) ||
         (def.tangent == TangentChoice::Auto && d.geometry.dim == 3 && linear_solver_iterative(def.solver));
}

// A step may be its predictor (solve/predictor_check.hpp) when the scheme's
// predictor is exact at constant acceleration, the state has one, and the
// last step was its predictor, or applied no contact term and every
// kPredictorProbe-th step tries it (a deformed body's free flight pays one
// pass in kPredictorProbe for the try). Serial operators, every DOF with
// mass. From the state alone: a resumed run tries the same steps.
constexpr int64_t kPredictorProbe = 16;
bool predictor_may_solve(const Integrator &in, const Discretization &d, const Definition &def, const State &old) {
  // (a law zero where free: else a free flight has forces, no constant acceleration)
  if (!def.predicted_steps || !in.scheme->predicts_constant_acceleration() ||
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

}  // namespace

std::unique_ptr<Integrator> make_integrator(Discretization &d, const Definition &def,
                                            std::unique_ptr<Factorization> reuse,
                                            const std::function<Csr(double)> &own_part) {
  require_complete(def.missing_for_step());
  auto in = std::make_unique<Integrator>();
  in->scheme = make_scheme(def.scheme, def.scheme_params);
  in->tau = def.tau;
  if (in->scheme->is_explicit()) {
    if (!d.massless.empty()) in->massless = std::make_unique<MasslessSolver>(d, def.solver);
    return in;
  }
  in->coef = in->scheme->coefficients(def.tau);
  count(d.counters, &Counters::matrix_assemblies);
  csr_combine(in->coef.c, d.M, 1.0, d.K_theta, in->A);
  if (d.node_blocks && !d.contact.a.empty()) in->A_blocks = make_node_blocks(in->A, d.M, d.node_blocks->dim);
  const bool refactors = !d.contact.a.empty() && refactoring_tangent(def, d);
  // on split operators a Newton pass that refactors reads the points whose rows touch the rank's rows
  if (refactors && d.rows_split) in->halo = contact_point_halo(d.contact, *d.rows);
  if (d.rows_split && def.distributed_state) {
    std::vector<const Csr *> clamped;  // (their reactions read these columns)
    if (d.clamped) clamped = {&d.clamped->K, &d.clamped->M};
    if (in->halo) in->points = held_points(d.contact, *in->halo);
    in->held = newton_held_rows(in->A, *d.rows, d.contact, clamped, in->points ? &in->points->points : nullptr);
  }
  in->A_factor = reuse ? std::move(reuse)
                       : make_factorization(def.solver, in->A, Structure::SymmetricPositiveDefinite, d.counters,
                                                            &d.geometry);
  try {
    if (own_part) {  // several ranks: each adds its own cells' part of A to the distributed matrix
      Csr own;  // assembled by each rank alone: agreed before the factorization, which they make together
      on_every_rank(def.comm.get(), [&] { own = own_part(in->coef.c); }, "the assembly of the step matrix",
                    "no rank factored it");
      in->A_factor->factor_parts(in->A, own, Structure::SymmetricPositiveDefinite);
    } else {
      in->A_factor->factor(in->A, Structure::SymmetricPositiveDefinite);
    }
  } catch (const Error &e) {
    if (e.code() != ND_ERR_INDEFINITE) throw;
    // c M + K_Theta not positive definite: neither is K_Theta (M >= 0), so
    // gamma0 is too large for Theta whatever tau (a smaller tau, a larger c,
    // may still make the step well posed, not the free motion bounded)
    const std::string safe = safe_gamma0(d.theta, d.gamma0_limit);
    const std::string what = "the step operator c*M + K_Theta: " + std::string(e.what()) + "; with Theta = " +
                             num(def.theta) + ", gamma0 = " + num(d.gamma0) + " and tau = " + num(def.tau) +
                             " the step is not well posed";
    if (safe.empty()) fail(ND_ERR_INDEFINITE, what + ": lower the time step");
    fail(ND_ERR_INDEFINITE, what + ": K_Theta is not positive definite either, so gamma0 is too large for Theta; " +
                                safe + ", and gamma0 = 0 chooses one automatically; a smaller time step may also " +
                                "make the step well posed");
  }
  // Newton with contact: condensed on the points (the default), the full
  // Newton with the low-rank update of A's factor past its rank limit, both on
  // one column cache, and the updated factor of T past that where it applies;
  // in 3D the updated factor from the start: there a column A^{-1} b_q is a
  // solve with a factor several times denser per column than in 2D, and a
  // bounce activates hundreds of points, so updating T costs fewer solves
  // per Newton iteration than the columns; in 2D the columns win
  // (docs/performance.md, "Newton tangent by dimension"). Refactoring T is
  // the reference; in 3D it is also the choice of an iterative solver
  // (GAMG), where a column is a Krylov solve and a new tangent reuses the
  // multigrid hierarchy of an earlier one (PetscGamg::refactor); with GAMG
  // in 2D refactoring gains nothing over the condensed Newton.
  if (!d.contact.a.empty()) {
    const Structure s = tangent_structure(def.theta, d.contact_law->traits());
    const bool updown = updown_tangent_applies(def.solver, s) &&
                        (def.tangent == TangentChoice::Updown ||
                         (def.tangent == TangentChoice::Auto && d.geometry.dim == 3));
    if (refactors) {
      // on split operators the solves keep the rows Newton reads (a rank's rows and their halo)
      std::vector<int64_t> held = in->held;  // a distributed state's rows, else those Newton reads
      if (held.empty() && d.rows_split) held = newton_held_rows(in->A, *d.rows, d.contact);
      in->tangent = make_refactoring_tangent(in->A, *in->A_factor, def.solver, s, d.counters, &d.geometry,
                                             std::move(held), !in->held.empty());
    } else if (updown) {
      in->tangent = make_updown_tangent(in->A, *in->A_factor, d.counters);
    } else {
      in->max_rank = def.tangent == TangentChoice::Auto ? lowrank_rank_limit(in->A.n, d.contact) : -1;
      // at most twice the rank limit held (the memory bound of lowrank_rank_limit);
      // on split operators each on the rank's rows and the points' DOFs
      in->columns = std::make_unique<ContactColumns>(
          *in->A_factor, in->A.n, in->max_rank >= 0 ? 2 * in->max_rank : static_cast<int64_t>(d.contact.size()),
          d.rows_split ? d.rows.get() : nullptr, in->held.empty() ? nullptr : &in->held, def.column_rows);
      in->tangent = make_lowrank_tangent(in->A, *in->A_factor, def.solver, s, in->max_rank, kLowRankTwoSolveRank,
                                         d.counters, &d.geometry, in->columns.get());
      if (def.tangent != TangentChoice::LowRank) in->condensed = std::make_unique<CondensedCache>(*in->columns);
    }
  }
  return in;
}

State advance(Integrator &in, Discretization &d, const Definition &def, const State &old, const StepData &at_new,
              State &&storage) {
  const TimeScheme &scheme = *in.scheme;
  const double tau = in.tau;
  const size_t n = old.U.size();
  State next = reuse_storage(std::move(storage));
  next.n = old.n + 1;
  next.t_ref = old.t_ref, next.n_ref = old.n_ref, next.tau_ref = old.tau_ref;
  if (old.tau_ref != tau) next.t_ref = old.t, next.n_ref = old.n, next.tau_ref = tau;
  next.t = next.t_ref + static_cast<double>(next.n - next.n_ref) * tau;
  next.F = at_new.F;  // (shared, not copied)
  // an empty load vector means no load; both ends of the step need one if either has
  auto zeros = [n] { return std::make_shared<const std::vector<double>>(n, 0.0); };
  if (next.load().empty() && !old.load().empty()) next.F = zeros();  // nodal forces withdrawn
  const std::shared_ptr<const std::vector<double>> no_load_before =
      !next.load().empty() && old.load().empty() ? zeros() : nullptr;
  const std::vector<double> &F_old = no_load_before ? *no_load_before : old.load();
  next.F_fixed = at_new.F_fixed;
  next.gap = at_new.gap;
  // the contact term of the step: P^n with the obstacle where it was at t^n,
  // P(U) with it where it is at t^{n+1} (docs/design.md §8)
  ContactLaw law{&d.contact, d.theta, &scheme, nullptr, next.gap.empty() ? nullptr : next.gap.data(), d.counters};
  law.point_law = d.contact_law.get();
  const std::vector<double> &gap_old = at_new.gap_old ? *at_new.gap_old : old.gap;
  ContactLaw old_law{&d.contact, d.theta, nullptr, nullptr, gap_old.empty() ? nullptr : gap_old.data(), d.counters};
  law.buffers = &in.contact_scratch;
  // the products of the state at t^n: its P_q(U^n) (the implicit schemes'
  // contact terms read them) and what the right-hand side is made of
  Products scratch;  // only when the state has none (restart, new state): the same pass
  const Products &old_products = products_of(d, old, scratch, scheme.uses_acceleration());
  // points the step before left unevaluated (PointValues::ref): the bound
  // from their reference, whose P_q stand as P^n (all <= 0, as P^n's are);
  // a law that reads more of P^n than that (a scheme changed since) has
  // them evaluated
  const PointReference *ref = old_products.points.ref.get();
  PointValues old_points;
  const bool same_below_zero = same_for_nonpositive_Pn(scheme.contact_rule(), d.contact_law->traits());
  // (curved obstacles: P^n at this step's g^n, not the state's, evaluated)
  if (at_new.gap_old || (ref && !same_below_zero)) {
    ContactLaw at_old = state_contact_law(d, old);
    if (at_new.gap_old) at_old.gap = gap_old.empty() ? nullptr : gap_old.data();
    at_old.counters = d.counters;
    at_old.local = true;  // (every rank evaluates every point: no message)
    at_old.P_all(old.U.data(), old_points.P);
    ref = nullptr;
  }
  law.Pn = ref ? &ref->P : old_points.P.empty() ? &old_products.points.P : &old_points.P;
  if (def.contact_bounds) {
    const std::vector<double> &Un = ref ? ref->U : old.U, &gap_n = ref ? ref->gap : gap_old;
    law.Un = Un.data(), law.gap_n = gap_n.empty() ? nullptr : gap_n.data();
    if (ref) law.free_reach_n = ref->free_reach;
  }
  scheme.predict(tau, old, next.U);
  // Shown contact-free by the bound (every law and its slope zero: phi = 0),
  // the new state's points are left unevaluated, the bound's reference in
  // their place, from which the next step's bound is made: a free flight
  // evaluates them only when the body has come near enough the obstacle
  // since the last evaluation for the bound to fail. Where the scheme's law
  // reads only that P^n <= 0 (the next step's, TimeScheme), and every rank
  // holds the whole state (a distributed state's points stay the ranks').
  const bool may_leave_points = same_below_zero && d.contact_law->traits().zero_when_free && def.contact_bounds &&
                                !in.points && in.held.empty() && !d.contact.a.empty();
  // the new state's pass (compute_products), its points left unevaluated
  // where shown free
  auto new_state_products = [&](bool shown_free, PointValues *known, const HeldPoints *held) {
    std::shared_ptr<const PointReference> from;
    if (shown_free && may_leave_points) from = point_reference(d, old, old_products, def.guards.penetration);
    if (from) compute_products_bounded(d, next, std::move(from));
    else compute_products(d, next, known, held);
  };
  // P_q(U^{n+1}) and u_n - g0 if the step made them (explicit, or Newton), for the products
  PointValues &at_U = in.at_solution;
  clear_keeping_memory(at_U);
  bool predicted = false;  // an implicit step that is its predictor: updated, its pass made
  bool made = false;       // the condensed Newton's check updated the state and made its pass
  bool bounded = false;    // Newton's solution shown contact-free by the bound from law.Un
  if (scheme.is_explicit()) {
    next.last_iterations = 0;
    // massless DOFs: their static equilibrium with U_f predicted (problem/massless.hpp)
    if (in.massless) next.last_iterations = in.massless->solve(def.newton, next.load(), next.gap, next.t, next.U);
    d.equilibrium_acceleration(next, def.solver, false, true, &at_U);  // every step: M factored once, kept
  } else {
    std::vector<double> &r = in.rhs;  // (its memory kept from step to step)
    r.clear();  // (the scheme's rhs finds it empty, as a new vector)
    scheme.rhs(StepInputs{old_products, d.contact, d.theta, F_old, next.load(), &in.scratch}, tau, old, r);
    if (predictor_may_solve(in, d, def, old)) {  // the new state's pass, made now, checks the predictor
      constant_acceleration_update(tau, old, next);
      new_state_products(may_leave_points && law.certainly_free(next.U), nullptr, nullptr);
      predicted = predictor_solves_step(law, in.coef.c, r, next, in.scratch);
      if (predicted) next.last_iterations = 0, count(d.counters, &Counters::predicted_steps);
      else  // (U is still the predictor: where the solves start)
        next.products = reuse_storage(std::move(next.products));
    }
    if (predicted) {
      // nothing to solve: the new state and its pass are made
    } else if (d.contact.a.empty()) {  // no contact: one solve with the cached factor
      next.U.swap(r);  // r: the predictor, where an iterative solve starts
      if (in.held.empty()) in.A_factor->solve_from(next.U.data(), r.data());
      else in.A_factor->solve_at(next.U.data(), static_cast<int64_t>(n), in.held, r.data());
      next.last_iterations = 1;
    } else {
      law.halo = in.halo.get();
      // a distributed state: every iterate is right at the DOFs of the
      // contact points a rank reads (every point's, or with a halo the
      // points it holds), so each rank evaluates them itself
      if (!in.held.empty()) (in.halo ? law.halo_here : law.local) = true;
      law.held = in.points.get();
      NewtonSystem sys{&in.A, in.tangent.get(), &d.M, in.coef.c, in.coef.kappa, &law, d.rows.get(), d.rows_split};
      sys.blocks = in.A_blocks.get();
      sys.work = &in.newton;
      sys.complete = in.held.empty();
      sys.guess = in.A_factor->starts_from_guess();
      // the points at the solution from Newton's last residual, for the new
      // state's products where that pass is the products' (every point, on a
      // whole state: Newton hands them over only then), the same bits
      PointValues *solution_points = in.held.empty() && !in.points ? &at_U : nullptr;
      in.tangent->begin_step(old.tangent_log);
      NewtonResult res;
      if (in.condensed) {  // condensed on the contact points (docs/design.md §4); the full Newton from its end if need be
        // its last residual checked from the new state's products, made
        // then: in one process (a distributed state, Integrator::held, needs
        // several ranks) with every DOF with mass, where the products are the
        // state's own, whole
        auto update_and_pass = [&]() -> const Products & {
          scheme.update(tau, old, next);
          compute_products(d, next);
          made = true;
          return next.products;
        };
        std::function<const Products &()> products_at;  // (by reference: no allocation)
        if (!d.rows && d.massless.empty()) products_at = std::ref(update_and_pass);
        const CondensedResult cr = newton_condensed(sys, *in.A_factor, *in.condensed, in.max_rank, r, def.newton,
                                                    next.U, solution_points, products_at ? &products_at : nullptr);
        res = cr.newton;
        if (!res.converged) {
          if (made) next.products = reuse_storage(std::move(next.products)), made = false;  // (Newton goes on from U)
          const int before = res.iterations;
          res = newton_solve(sys, r, def.newton, next.U, solution_points);
          res.iterations += before;
        }
      } else {
        res = newton_solve(sys, r, def.newton, next.U, solution_points);
      }
      if (!res.converged)
        fail(ND_ERR_NEWTON, "Newton did not converge in " + std::to_string(res.iterations) + " iterations at t = " +
                                num(next.t) + " (residual " + num(res.residual) + ", tolerance " +
                                num(res.tolerance) + "); the step was not taken");
      next.last_iterations = res.iterations;
      bounded = res.bounded;
      const TangentLog *history = in.tangent->log();
      if (history) copy_log(next.tangent_log, *history, d.contact.size());
    }
  }
  // no contact solve: the history stays
  if (next.tangent_log.i.empty()) copy_log(next.tangent_log, old.tangent_log, d.contact.size());
  if (!predicted && !made) scheme.update(tau, old, next);
  // Massless DOFs (mass redistribution): no equation holds their V and A, and
  // the schemes' recursions for them are at best neutral (the hybrid's
  // V^{n+1} = 2 dU/tau - V^n keeps every error). They feed nothing back (M's
  // columns are zero there): difference quotients, first order, bounded.
  for (size_t i = 0; i < d.massless.size(); ++i)
    if (d.massless[i]) {
      next.V[i] = (next.U[i] - old.U[i]) / tau;
      if (next.A_valid) next.A[i] = (next.V[i] - old.V[i]) / tau;
    }
  next.partial = !in.held.empty();  // (an explicit step has none)
  if (!finite_with_work(d, old, F_old, next))
    fail(ND_ERR_NONFINITE_STATE,
         "the step to t = " + num(next.t) + " produced non-finite values; the step was not taken");
  next.total_iterations = old.total_iterations + next.last_iterations;
  // The step's contact term phi_q: the obstacle moving by dg_q against the
  // mean pressure -phi_q/gamma_q does the work -sum_q (w_q/gamma_q) phi_q dg_q.
  // Hybrid, Theta = 1: the step times dU = U^{n+1} - U^n, with p_q.dU = dP_q + dg_q
  // (P^n with g^n, P^{n+1} with g^{n+1}), gives
  //   dE_Theta = F^{n+1/2}.dU - sum_q (w_q/gamma_q) phi_q dg_q - D,
  //   D = sum_q (w_q/gamma_q) (phi_q dP_q - d([P_q]_+^2)/2) >= 0, 0 unless a point changes sides.
  // One pass over the points: phi is also the applied pressure (kept in the state).
  // (the products of the new state: its energy for the guard, its P_q for
  // phi and for the next step, and the next right-hand side)
  // (at_U: an explicit step's, or Newton's at its solution; empty: evaluated there)
  if (!predicted && !made) new_state_products(bounded, &at_U, in.points.get());
  const bool unevaluated = next.products.points.ref != nullptr;
  std::vector<double> phi = std::move(next.phi);  // (empty, its memory reused)
  phi.assign(d.contact.size(), 0.0);
  next.W_obstacle = old.W_obstacle;
  // with a distributed state's points: phi at the rank's points, the work of its own added over the ranks
  std::vector<double> dW(in.points ? phi.size() : 0);
  const bool pp = law.positive_part();
  auto apply = [&](size_t q) {
    double slope;
    law.law(q, next.products.points.P[q], phi[q], slope, pp);
    if (phi[q] == 0) return;  // (a term -0 or +0 changes no sum of W_obstacle, which is never -0)
    const double w = -d.contact.w[q] / d.contact.gamma[q] * phi[q] * (law.g(q) - old_law.g(q));
    if (in.points) dW[q] = w;
    else next.W_obstacle += w;
  };
  if (unevaluated) {
    // phi = 0 at every point: nothing applied, no work
  } else if (in.points) {
    std::fill(phi.begin(), phi.end(), std::numeric_limits<double>::quiet_NaN());
    for (int64_t q : in.points->points) apply(static_cast<size_t>(q));
  } else {
    for (size_t q = 0; q < phi.size(); ++q) apply(q);
  }
  if (d.clamped) {
    const double a = scheme.mean_weight();
    std::vector<double> Abar;
    scheme.mean_acceleration(tau, old, next, Abar);
    next.reaction = clamped_residual(d, Abar, step_mean(next.U, old.U, a), phi, step_mean(next.F_fixed, old.F_fixed, a));
  }
  next.phi = std::move(phi);
  if (in.points) sum_points(d, next, dW);  // (collective: every rank's step comes here)
  return next;
}

}  // namespace nd
