/* The checks made before the first step (docs/design.md §3b), each on a case that
 * must trip it and on one that must not:
 *  - the coercivity limit gamma0* of K_Theta: on the 1D bar the element bound
 *    is exact and known in closed form (P1: 1/E, P2: 1/(4E)); past the exact
 *    global limit setup refuses Theta > 0 with ND_ERR_NOT_COERCIVE; the
 *    automatic gamma0 is half the bound;
 *  - every refusal of a gamma0 too large states the safe bound, the value of
 *    ND_GAMMA0_LIMIT (the coercivity check, the step operator c M + K_Theta
 *    and the massless block of K_Theta found indefinite, the energy guard,
 *    the overflow of the Nitsche terms);
 *  - schemes that amplify every oscillation (theta < 1/2, Newmark gamma < 1/2);
 *  - an initial state inside the obstacle.
 * The guards during stepping are in test_step_failure; that they stay quiet
 * on sound runs is shown by every other test, which run with the defaults. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* the bar of docs/design.md §7 with Young's modulus E and the obstacle at plane_x;
   tau = h/2 in units of the wave speed sqrt(E) */
static nd_problem bar(int degree, double young, double theta, double gamma0, double plane_x) {
  const double nm[2] = {0.25, 0.5};
  nd_problem p =
      nd_test_bar_at(20, degree, ND_SCHEME_NEWMARK, nm, theta, gamma0, 0.025 / sqrt(young), plane_x, NULL);
  ND_OK_OR_FAIL(nd_problem_set_material(p, young, 0.0, 1.0));
  return p;
}

START_TEST(coercivity_limit_of_the_bar) {
  /* one contact cell of length h: K_e = (E/h)[1 -1; -1 1] and h w s s^T with
     s = E (1, -1)/h (P1) give lambda = E; P2's end derivative is 3/h, ...:
     lambda = 4E */
  const double youngs[] = {1.0, 2.5, 2.1e11};
  for (int degree = 1; degree <= 2; ++degree)
    for (int e = 0; e < 3; ++e) {
      const double E = youngs[e], exact = 1 / (degree == 1 ? E : 4 * E);
      nd_problem p = bar(degree, E, 1.0, 0.1 * exact, 0.0);
      ck_assert_double_eq_tol(scalar(p, ND_GAMMA0_LIMIT), exact, 1e-12 * exact);
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 0.5, 0.1 * exact)); /* Theta gamma0 <= gamma0* */
      ck_assert_double_eq_tol(scalar(p, ND_GAMMA0_LIMIT), 2 * exact, 2e-12 * exact);
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, -1.0, 0.1 * exact));
      ck_assert(isinf(scalar(p, ND_GAMMA0_LIMIT)));
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      /* the element bound is the global limit here: just below, setup
         passes; just above, it is refused, and nothing changes */
      p = bar(degree, E, 1.0, 0.999 * exact, 0.0);
      ND_OK_OR_FAIL(nd_problem_setup(p));
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      p = bar(degree, E, 1.0, 1.01 * exact, 0.0);
      ck_assert_int_eq(nd_problem_setup(p), ND_ERR_NOT_COERCIVE);
      printf("%s\n", nd_last_error());
      ck_assert_int_eq(nd_problem_setup(p), ND_ERR_NOT_COERCIVE);  /* still: nothing was kept */
      ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_COERCIVITY, 0)); /* for a study */
      ND_OK_OR_FAIL(nd_problem_setup(p));
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* The disk (h = 4): the element bound is sufficient, not exact: the global
   limit lies at 1.53 (P1) and 1.59 (P2) times it, as measured by bisection on
   the exact check (7.39e-3 and 2.56e-3, the thresholds measured with an
   eigensolver before the check existed). */
START_TEST(coercivity_limit_of_the_disk) {
  for (int degree = 1; degree <= 2; ++degree) {
    const double factors[] = {1.4, 1.7};
    for (int f = 0; f < 2; ++f) {
      nd_mesh m = NULL;
      nd_problem p = NULL;
      const double origin[2] = {0, 0}, up[2] = {0, 1};
      ND_OK_OR_FAIL(nd_mesh_read_gmsh(ND_MESH_DIR "/disk_h4.msh", &m));
      ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
      ND_OK_OR_FAIL(nd_mesh_destroy(&m));
      ND_OK_OR_FAIL(nd_problem_set_material(p, 50, 0.25, 1));
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
      const double limit = scalar(p, ND_GAMMA0_LIMIT);
      ck_assert_double_eq_tol(scalar(p, ND_GAMMA0), 0.5 * limit, 1e-15 * limit); /* automatic */
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, factors[f] * limit));
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
      ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.1));
      const int status = nd_problem_setup(p);
      printf("disk P%d: gamma0* = %.4g (element bound); %.1f gamma0*: %s\n", degree, limit, factors[f],
             status == ND_OK ? "accepted" : nd_last_error());
      ck_assert_int_eq(status, f == 0 ? ND_OK : ND_ERR_NOT_COERCIVE);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
  }
}
END_TEST

START_TEST(automatic_gamma0) {
  /* half the bound for Theta <= 1, half the Theta-scaled bound above */
  const double thetas[] = {1.0, 0.0, -1.0, 2.0};
  for (int t = 0; t < 4; ++t) {
    nd_problem p = bar(2, 3.0, thetas[t], 0.0, 0.0);
    const double bound1 = 1 / (4 * 3.0), expected = 0.5 * bound1 / fmax(thetas[t], 1.0);
    ck_assert_double_eq_tol(scalar(p, ND_GAMMA0), expected, 1e-12 * expected);
    /* (Theta = -1 with it gains 5 % of the energy at the impact, the method's own (Theta - 1) term,
       docs/design.md §3b: the energy-balance guard refuses that (test_guards_scale); here, the step runs) */
    if (thetas[t] < 0) ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0));
    for (int k = 0; k < 120; ++k) ND_OK_OR_FAIL(nd_step(p)); /* through the impact at t = 1 */
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* Theta <= 0 with the hybrid scheme: 1/50 of gamma0* (docs/design.md §3b.1),
   at which the (Theta - 1) term of Theorem 2.8 gains about 1e-3 of the
   energy at the impact, against 5 % at the old automatic value, half the
   bound (measured: 1.0e-3 at P1, 2.5e-4 at P2 with Theta = -1, round-off
   with Theta = 0; asserted below 2e-3, 25 times below the guard's line),
   the balance guard on and every step taken; the scheme changed to the
   theta-scheme: half the bound again */
START_TEST(automatic_gamma0_of_the_hybrid_scheme_with_theta_at_most_zero) {
  const double thetas[] = {0.0, -1.0};
  for (int t = 0; t < 2; ++t)
    for (int degree = 1; degree <= 2; ++degree) {
      nd_problem p = bar(degree, 3.0, thetas[t], 0.0, 0.0);
      const double bound = 1 / ((degree == 1 ? 1 : 4) * 3.0);
      ck_assert_double_eq_tol(scalar(p, ND_GAMMA0), 0.5 * bound, 1e-12 * bound);
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
      ck_assert_double_eq_tol(scalar(p, ND_GAMMA0), 0.02 * bound, 1e-12 * bound);
      const double E0 = scalar(p, ND_ENERGY_MECHANICAL);
      double growth = 0;
      for (int k = 0; k < 120; ++k) { /* through the impact at t = 1 */
        ND_OK_OR_FAIL(nd_step(p));
        growth = fmax(growth, scalar(p, ND_ENERGY_MECHANICAL) / (E0 + scalar(p, ND_WORK)) - 1);
      }
      printf("bar P%d Theta = %g, hybrid, automatic gamma0 = gamma0* / 50: largest E/(E0 + W) - 1 = %.6g\n", degree,
             thetas[t], growth);
      ck_assert_double_lt(growth, 2e-3);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      p = bar(degree, 3.0, thetas[t], 0.0, 0.0);
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_THETA, (const double[]){1.0}));
      ck_assert_double_eq_tol(scalar(p, ND_GAMMA0), 0.5 * bound, 1e-12 * bound);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* message states "gamma0 <= X is safe" with X the bound ND_GAMMA0_LIMIT
   reported (to the 6 significant digits of the library's messages) */
static void assert_states_bound(const char *message, double limit) {
  const char *at = strstr(message, "gamma0 <= ");
  ck_assert_msg(at != NULL, "no \"gamma0 <= \" in: %s", message);
  char *end = NULL;
  const double x = strtod(at + strlen("gamma0 <= "), &end);
  ck_assert_msg(end != at + strlen("gamma0 <= ") && strncmp(end, " is safe", 8) == 0, "no bound in: %s", message);
  ck_assert_msg(fabs(x - limit) <= 5e-6 * limit, "the message's bound %.17g is not ND_GAMMA0_LIMIT %.17g: %s", x,
                limit, message);
}

/* The bar (P2, E = 3: gamma0* = 1/12) with Theta = 1 and a gamma0 above the
   bound, with and without the coercivity guard: each refusal states the bound
   that nd_get_scalar(ND_GAMMA0_LIMIT) reports, read from the same problem */
START_TEST(refusals_of_a_large_gamma0_state_the_bound) {
  const double E = 3, central[2] = {0, 0.5};
  for (int guard = 1; guard >= 0; --guard) {
    /* far above: c M + K_Theta of Newmark's step is indefinite at set-up */
    nd_problem p = bar(2, E, 1.0, 1.0, 0.0);
    const double limit = scalar(p, ND_GAMMA0_LIMIT);
    ck_assert(limit > 0 && isfinite(limit));
    ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 1e3 * limit));
    ck_assert_double_eq_tol(scalar(p, ND_GAMMA0_LIMIT), limit, 1e-15 * limit);
    ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_COERCIVITY, guard));
    ck_assert_int_eq(nd_problem_setup(p), ND_ERR_INDEFINITE);
    printf("guard %d, step operator: %s\n", guard, nd_last_error());
    assert_states_bound(nd_last_error(), limit);
    ck_assert_ptr_nonnull(strstr(nd_last_error(), "smaller time step"));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));

    /* just above: the step is well posed; the check refuses K_Theta, or
       without it the energy guard refuses the growing free motion */
    p = bar(2, E, 1.0, 1.1 * limit, 0.0);
    ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_COERCIVITY, guard));
    int status = nd_problem_setup(p);
    if (guard) {
      ck_assert_int_eq(status, ND_ERR_NOT_COERCIVE);
    } else {
      for (int k = 0; k < 400 && status == ND_OK; ++k) status = nd_step(p);
      ck_assert_int_eq(status, ND_ERR_ENERGY_GROWTH);
    }
    printf("guard %d, 1.1 gamma0*: %s\n", guard, nd_last_error());
    assert_states_bound(nd_last_error(), limit);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));

    /* the explicit central difference with the contact nodes' mass
       redistributed: (K_Theta)_mm, factored at set-up, is indefinite */
    p = bar(2, E, 1.0, 1e3 * limit, 0.0);
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, central));
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, 1e-4));
    ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_COERCIVITY, guard));
    status = nd_problem_setup(p);
    ck_assert_msg(status == ND_ERR_INDEFINITE || (guard && status == ND_ERR_NOT_COERCIVE), "status %d: %s", status,
                  nd_last_error());
    printf("guard %d, massless block: %s\n", guard, nd_last_error());
    assert_states_bound(nd_last_error(), limit);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));

    /* so large that the Nitsche terms overflow: the operators cannot be
       assembled (ND_GAMMA0_LIMIT neither), the bound read before still holds */
    p = bar(2, E, 1.0, 1e308, 0.0);
    ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_COERCIVITY, guard));
    ck_assert_int_eq(nd_problem_setup(p), ND_ERR_NITSCHE);
    printf("guard %d, overflow: %s\n", guard, nd_last_error());
    assert_states_bound(nd_last_error(), limit);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

START_TEST(schemes_unstable_at_every_step_are_refused) {
  const double th[] = {0.0, 0.3, 0.49}, nm[2] = {0.3, 0.4};
  for (int i = 0; i < 4; ++i) {
    nd_problem p = bar(1, 1.0, 1.0, 0.2, 0.0);
    if (i < 3)
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_THETA, &th[i]));
    else
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm));
    ck_assert_int_eq(nd_step(p), ND_ERR_UNSTABLE);
    ck_assert_double_eq(scalar(p, ND_STEP_INDEX), 0);
    ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_UNSTABLE_SCHEME, 0));
    ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0));
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1)); /* theta = 0 */
    ND_OK_OR_FAIL(nd_step(p)); /* allowed for a study */
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  const double half = 0.5; /* the limit itself conserves energy: accepted */
  nd_problem p = bar(1, 1.0, 1.0, 0.2, 0.0);
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_THETA, &half));
  ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(initial_penetration_is_refused) {
  /* u0 = -(1-x)/2 moves x = 0 by 1/2 towards the obstacle: an obstacle at
     x = -0.5001 is still clear, one at -0.4999 starts 1e-4 inside */
  const double planes[] = {0.5001, 0.4999};
  for (int i = 0; i < 2; ++i) {
    nd_problem p = bar(1, 1.0, 1.0, 0.2, -planes[i]);
    int64_t n = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
    double *x = malloc(sizeof(double) * (size_t)n), *u0 = malloc(sizeof(double) * (size_t)n);
    ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
    for (int64_t k = 0; k < n; ++k) u0[k] = -0.5 * (1 - x[k]); /* towards the obstacle */
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, NULL));
    const int status = nd_problem_setup(p);
    ck_assert_int_eq(status, i == 0 ? ND_OK : ND_ERR_PENETRATION);
    if (i == 1) {
      printf("%s\n", nd_last_error());
      ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_INITIAL_PENETRATION, 0));
      ND_OK_OR_FAIL(nd_problem_setup(p));
    }
    free(x);
    free(u0);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("guards");
  TCase *tc = tcase_create("before_the_first_step");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, coercivity_limit_of_the_bar);
  tcase_add_test(tc, coercivity_limit_of_the_disk);
  tcase_add_test(tc, automatic_gamma0);
  tcase_add_test(tc, automatic_gamma0_of_the_hybrid_scheme_with_theta_at_most_zero);
  tcase_add_test(tc, refusals_of_a_large_gamma0_state_the_bound);
  tcase_add_test(tc, schemes_unstable_at_every_step_are_refused);
  tcase_add_test(tc, initial_penetration_is_refused);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
