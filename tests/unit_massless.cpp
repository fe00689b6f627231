// The explicit scheme with mass redistribution (problem/massless.hpp): the
// massless DOFs m are found each step from their static equilibrium
//   (K_Theta U + N(U) - F)_m = 0,  U_f from the explicit predictor.
//  - After every step that equation holds to Newton's tolerance (rtol times
//    its right-hand side F_m - (K_Theta)_mf U_f, or round-off), in 1D (P1,
//    P2) and 2D (Theta = 1: symmetric tangent; Theta = 0: general).
//  - The energy identity that holds (Theta = 1, no load): the step is the
//    central difference (Stoermer-Verlet) on the free DOFs for the condensed
//    potential Pi~(U_f) = min_{U_m} Pi(U), Pi = 1/2 U'K_Theta U + sum_q
//    (w_q/2gamma_q)[P_q]_+^2 (Pi~'s gradient is (K_Theta U + N)_f at the
//    minimizer). Where Pi~ is quadratic (one active set at U^{n-1}, U^n,
//    U^{n+1}) the shadow energy
//      S^{n+1/2} = 1/2 V'MV + (Pi(U^n) + Pi(U^{n+1}))/2 - 1/4 D'HD,
//      D = U^{n+1} - U^n, V = D/tau, H = K_Theta + sum_active (w_q/gamma_q) p_q p_q'
//    is conserved to round-off (D'HD is D_f'(Schur complement)D_f since D_m
//    is the response to D_f). At a change of the active set S jumps; E_Theta
//    stays within O(h) of its value after the first step (measured below).
//  - (K_Theta)_mm is factored once at set-up: no factorization in flight,
//    one per Newton iteration with active points.
//  - A step whose massless Newton fails returns ND_ERR_NEWTON and leaves the
//    state bitwise as it was; the run then continues as an uninterrupted one.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "capi/handles.hpp"
#include "monitor/energies.hpp"
#include "nitschedyn.h"
// check.h last: it defines a macro `fail` that the library's headers would meet
#include <check.h>

#include "testutil.h"

namespace {

const double kExplicit[2] = {0, 0.5};

nd_problem bar(int nx, int degree, double tau, bool lumped = true) {
  nd_problem p = nd_test_bar(nx, degree, ND_SCHEME_NEWMARK, kExplicit, 1.0, 0.2, tau);
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
  return p;
}

// A 2D block (8 x 4 on (0,2) x (0,1)) 0.2 above the plane y = 0, moving
// down at speed 1: no Dirichlet boundary, flight, impact, bounce, flight.
nd_problem block(double Theta) {
  nd_mesh m = nullptr;
  nd_problem p = nullptr;
  const double lo[2] = {0, 0}, hi[2] = {2, 1}, l1[2] = {-1, -1e-3}, h1[2] = {3, 1e-3};
  const double o[2] = {0, -0.2}, up[2] = {0, 1};
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(8, 4, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, l1, h1));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 10.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, Theta, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, kExplicit));
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  std::vector<double> v0(static_cast<size_t>(2 * n), 0.0);
  for (int64_t i = 0; i < n; ++i) v0[static_cast<size_t>(2 * i + 1)] = -1;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, nullptr, v0.data()));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 1.0));
  double tc = 0;
  ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tc));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.5 * tc));
  return p;
}

double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

// ||(K_Theta U + N(U) - F)_m||, and Newton's tolerance for it: rtol ||F_m -
// (K_Theta)_mf U_f|| or round-off of the terms (the update-at-round-off rule)
void massless_residual(nd_problem p, double rtol, double &res, double &tol) {
  nd::Problem &pr = p->problem;
  const nd::Discretization &d = pr.discretization();
  const nd::State &s = pr.current_state();
  const size_t n = s.U.size();
  std::vector<double> G(n), Uf = s.U, Um(n, 0.0), KUf(n), KUm(n);
  for (size_t i = 0; i < n; ++i)
    if (d.massless[i]) Uf[i] = 0, Um[i] = s.U[i];
  d.K_theta.multiply(s.U.data(), G.data());
  d.K_theta.multiply(Uf.data(), KUf.data());
  d.K_theta.multiply(Um.data(), KUm.data());
  const nd::ContactLaw law = nd::state_contact_law(d, s);
  law.add_force(s.U.data(), 1.0, G.data(), nullptr);
  double g2 = 0, r2 = 0, a2 = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!d.massless[i]) continue;
    const double F = s.load().empty() ? 0.0 : s.load()[i];
    g2 += (G[i] - F) * (G[i] - F);
    r2 += (F - KUf[i]) * (F - KUf[i]);
    a2 += KUm[i] * KUm[i];
  }
  res = std::sqrt(g2);
  tol = rtol * std::sqrt(r2) + 1e-13 * (std::sqrt(r2) + std::sqrt(a2));
}

START_TEST(massless_dofs_are_in_equilibrium_after_every_step) {
  struct Case {
    const char *what;
    nd_problem p;
    int steps;
  } cases[] = {{"bar P1 tau = h/2", bar(40, 1, 0.5 / 40), 240},
               {"bar P1 tau = h (CFL 1)", bar(40, 1, 1.0 / 40), 120},
               {"bar P2 tau = h/8", bar(20, 2, 0.125 / 20), 480},
               {"bar P1 consistent mass", bar(20, 1, 0.25 / 20, false), 240},
               {"block Theta = 1", block(1.0), 400},
               {"block Theta = 0", block(0.0), 400}};
  ND_OK_OR_FAIL(nd_problem_set_guard(cases[1].p, ND_GUARD_CRITICAL_TIMESTEP, 0));  // its estimate is conservative
  for (Case &c : cases) {
    int contact = 0, flight = 0;
    double worst = 0;
    for (int k = 0; k < c.steps; ++k) {
      ND_OK_OR_FAIL(nd_step(c.p));
      double res, tol;
      massless_residual(c.p, 1e-10, res, tol);
      ck_assert_msg(res <= tol, "%s step %d: massless residual %g > tolerance %g", c.what, k, res, tol);
      worst = std::max(worst, res / tol);
      (scalar(c.p, ND_ACTIVE_POINTS) > 0 ? contact : flight) += 1;
    }
    std::printf("%s: %d steps in contact, %d in flight, residual/tolerance <= %.2g\n", c.what, contact, flight, worst);
    ck_assert_int_gt(contact, 5);
    ck_assert_int_gt(flight, 5);
    ND_OK_OR_FAIL(nd_problem_destroy(&c.p));
  }
}
END_TEST

// Pi(U) = 1/2 U'K_Theta U + sum_q (w_q/2 gamma_q)[P_q]_+^2 (Theta = 1), and the active set
double potential(const nd::Discretization &d, const nd::State &s, std::vector<char> &active) {
  std::vector<double> KU(s.U.size());
  d.K_theta.multiply(s.U.data(), KU.data());
  double pi = 0.5 * nd::dot(static_cast<int64_t>(KU.size()), s.U.data(), KU.data());
  const nd::ContactLaw law = nd::state_contact_law(d, s);
  active.assign(d.contact.size(), 0);
  for (size_t q = 0; q < d.contact.size(); ++q) {
    const double P = law.P(q, s.U.data());
    active[q] = P > 0;
    if (P > 0) pi += 0.5 * d.contact.w[q] / d.contact.gamma[q] * P * P;
  }
  return pi;
}

START_TEST(shadow_energy_is_conserved_between_switches) {
  struct Case {
    const char *what;
    nd_problem p;
    int steps;
    double drift;  // measured max |E_Theta - E_Theta^1| / E_Theta^1, with a margin
  } cases[] = {{"P1 tau = h/2", bar(40, 1, 0.5 / 40), 480, 0.005},         // measured 0.0023
               {"P1 tau = h (CFL 1)", bar(40, 1, 1.0 / 40), 240, 0.015},  // 0.0075
               {"P2 tau = h/8", bar(20, 2, 0.125 / 20), 960, 0.001}};     // 0.00047
  ND_OK_OR_FAIL(nd_problem_set_guard(cases[1].p, ND_GUARD_CRITICAL_TIMESTEP, 0));
  for (Case &c : cases) {
    nd_problem p = c.p;
    ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50));  // to round-off: the identity is exact only then
    nd::Problem &pr = p->problem;
    const double tau = scalar(p, ND_TIMESTEP);
    ND_OK_OR_FAIL(nd_step(p));  // from here on U_m is in equilibrium
    const double E1 = scalar(p, ND_ENERGY_AUGMENTED);
    nd::State prev = pr.current_state();
    std::vector<char> act_prev, act, act_next;
    double pi_prev = potential(pr.discretization(), prev, act_prev), S_prev = NAN, worst = 0, drift = 0, jump = 0;
    int checked = 0, switches = 0;
    for (int k = 1; k < c.steps; ++k) {
      ND_OK_OR_FAIL(nd_step(p));
      const nd::Discretization &d = pr.discretization();
      const nd::State &s = pr.current_state();
      const double pi = potential(d, s, act);
      // S^{n+1/2} over the step prev -> s
      const size_t n = s.U.size();
      std::vector<double> D(n), MD(n), KD(n);
      for (size_t i = 0; i < n; ++i) D[i] = s.U[i] - prev.U[i];
      d.M.multiply(D.data(), MD.data());
      d.K_theta.multiply(D.data(), KD.data());
      double dHd = nd::dot(static_cast<int64_t>(n), D.data(), KD.data());
      for (size_t q = 0; q < d.contact.size(); ++q)
        if (act[q]) {
          const double pd = d.contact.a[q].dot(D.data()) - d.contact.gamma[q] * d.contact.s[q].dot(D.data());
          dHd += d.contact.w[q] / d.contact.gamma[q] * pd * pd;
        }
      const double S = 0.5 * nd::dot(static_cast<int64_t>(n), D.data(), MD.data()) / (tau * tau) +
                       0.5 * (pi_prev + pi) - 0.25 * dHd;
      if (!std::isnan(S_prev)) {
        if (act_prev == act && act == act_next) {
          worst = std::max(worst, std::fabs(S - S_prev) / E1);
          ++checked;
        } else {
          jump = std::max(jump, std::fabs(S - S_prev) / E1);
          ++switches;
        }
      }
      // act_next: the active set two levels back, act_prev one level back
      act_next = act_prev;
      act_prev = act;
      S_prev = S;
      pi_prev = pi;
      prev = s;
      drift = std::max(drift, std::fabs(scalar(p, ND_ENERGY_AUGMENTED) - E1) / E1);
    }
    std::printf("%s: shadow energy conserved to %.2g over %d steps, jumps up to %.2g at %d switches; "
                "E_Theta within %.2g of E_Theta^1\n", c.what, worst, checked, jump, switches, drift);
    ck_assert_int_gt(checked, c.steps / 2);
    ck_assert_int_gt(switches, 0);
    ck_assert_msg(worst <= 1e-12, "%s: shadow energy changed by %g", c.what, worst);
    ck_assert_msg(drift <= c.drift, "%s: E_Theta drifted by %g", c.what, drift);
    ND_OK_OR_FAIL(nd_problem_destroy(&c.p));
  }
}
END_TEST

START_TEST(factored_once_refactored_only_in_contact) {
  nd_problem p = bar(40, 1, 0.5 / 40);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  const double f0 = scalar(p, ND_STAT_FACTORIZATIONS);
  const nd::MasslessSolver *ms = p->problem.integrator()->massless.get();
  ck_assert_ptr_nonnull(ms);
  ck_assert_int_eq(static_cast<int64_t>(ms->dofs().size()), 1);  // the contact node
  int k = 0;
  for (; k < 240 && scalar(p, ND_ACTIVE_POINTS) == 0; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    if (scalar(p, ND_ACTIVE_POINTS) == 0) ck_assert(scalar(p, ND_STAT_FACTORIZATIONS) == f0);
  }
  ck_assert_int_gt(k, 5);
  for (int j = 0; j < 120; ++j) ND_OK_OR_FAIL(nd_step(p));
  const double refactored = static_cast<double>(ms->tangent_stats().refactorizations);
  ck_assert(refactored > 0);
  ck_assert(scalar(p, ND_STAT_FACTORIZATIONS) == f0 + refactored);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

std::vector<double> snapshot(nd_problem p) {
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  const int64_t nd = n * p->problem.space().dim;  // values per field
  std::vector<double> x(static_cast<size_t>(3 * nd + 15));
  for (int f = 0; f < 3; ++f) ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT + f, n, x.data() + f * nd));
  // the scalars, not the ND_STAT_* counters
  for (int k = 0; k < 15; ++k) ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME + k, &x[static_cast<size_t>(3 * nd + k)]));
  return x;
}

START_TEST(a_failed_massless_newton_keeps_the_state) {
  // one Newton iteration allowed: on the bar one is always enough (one DOF,
  // and the predictor guesses its side); the block's impact needs more
  nd_problem p = block(1.0), ref = block(1.0);
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0, 1));
  int failures = 0;
  for (int k = 0; k < 240; ++k) {
    const std::vector<double> before = snapshot(p);
    const int status = nd_step(p);
    if (status != ND_OK) {
      ck_assert_int_eq(status, ND_ERR_NEWTON);
      ck_assert_ptr_nonnull(std::strstr(nd_last_error(), "massless"));
      ck_assert(snapshot(p) == before);
      ++failures;
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0, 50));
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0, 1));
    }
    ND_OK_OR_FAIL(nd_step(ref));
    ck_assert_msg(snapshot(p) == snapshot(ref), "step %d differs from the uninterrupted run", k);
  }
  ck_assert_int_gt(failures, 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&ref));
}
END_TEST

}  // namespace

int main(void) {
  Suite *s = suite_create("massless");
  TCase *tc = tcase_create("massless");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, massless_dofs_are_in_equilibrium_after_every_step);
  tcase_add_test(tc, shadow_energy_is_conserved_between_switches);
  tcase_add_test(tc, factored_once_refactored_only_in_contact);
  tcase_add_test(tc, a_failed_massless_newton_keeps_the_state);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
