/* The applied contact pressure (nd_get_contact_pressure_applied) and mass
 * redistribution (nd_problem_set_mass_redistribution), through the C API.
 *  - A free bar (no clamped end) falling on the obstacle: summing the equation
 *    a step satisfies over all DOFs removes K_Theta (1'K = 0, s_q.1 = 0), so the
 *    momentum 1'MV changes exactly by the applied resultant:
 *    hybrid (1'MV^{n+1} - 1'MV^n)/tau = ND_CONTACT_FORCE_APPLIED, and
 *    generalized-alpha 1'M A^{n+1-alpha_m} = ND_CONTACT_FORCE_APPLIED.
 *    For P1 on a uniform mesh 1'M = the row sums (h/2 at the ends, h inside).
 *  - Schemes that apply the end-of-step force: applied = lambda_q bitwise.
 *  - Redistribution: the hybrid scheme's E_Theta stays non-increasing (the
 *    proof needs only M symmetric positive semi-definite), the explicit scheme
 *    (massless DOFs in static equilibrium) balances momentum like the hybrid,
 *    checkpoints tell the two masses apart, restarts stay bitwise. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

enum { NX = 20 };

static nd_problem free_bar(int scheme, const double *params, double tau) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double up = 1, zero = 0, lo0 = -0.5, hi0 = 0.5;
  ND_OK_OR_FAIL(nd_mesh_create_interval(NX, 0.0, 1.0, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo0, &hi0));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &zero, &up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  double v0[NX + 1];
  for (int i = 0; i <= NX; ++i) v0[i] = -0.1;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, NX + 1, NULL, v0));
  return p;
}

/* 1'M x for the P1 consistent mass on the uniform mesh (rho = 1) */
static double mass_sum(const double *x) {
  const double h = 1.0 / NX;
  double s = 0.5 * h * (x[0] + x[NX]);
  for (int i = 1; i < NX; ++i) s += h * x[i];
  return s;
}

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

START_TEST(hybrid_applied_force_is_the_momentum_change) {
  const double tau = 0.01;
  nd_problem p = free_bar(ND_SCHEME_HYBRID, NULL, tau);
  double V[NX + 1], w = 0, lam_app = 0, lam = 0;
  double worst = 0, worst_end = 0, scale = 0;
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, NX + 1, V));
  double p_old = mass_sum(V);
  for (int k = 0; k < 300; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, NX + 1, V));
    const double p_new = mass_sum(V), rate = (p_new - p_old) / tau;
    const double applied = scalar(p, ND_CONTACT_FORCE_APPLIED);
    /* the resultant is -sum_q w_q lambda_app_q (one point in 1D) */
    ND_OK_OR_FAIL(nd_problem_get_contact_points(p, 1, NULL, &w));
    ND_OK_OR_FAIL(nd_get_contact_pressure_applied(p, 1, &lam_app));
    ND_OK_OR_FAIL(nd_get_contact_pressure(p, 1, &lam));
    ck_assert(fabs(applied + w * lam_app) <= 1e-15 * fabs(applied));
    scale = fmax(scale, fmax(fabs(p_new) / tau, fabs(applied)));
    worst = fmax(worst, fabs(rate - applied));
    worst_end = fmax(worst_end, fabs(rate + w * lam));
    p_old = p_new;
  }
  /* round-off: a sum of NX + 1 terms, divided by tau */
  ck_assert_msg(worst <= 1e-12 * scale, "momentum balance off by %g (scale %g)", worst, scale);
  /* the end-of-step lambda does not balance it: the identity is not vacuous */
  ck_assert_msg(scale > 0 && worst_end > 1e-3 * scale, "end-of-step force balances too (%g)", worst_end);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(generalized_alpha_applied_force_is_at_the_alpha_points) {
  const double tau = 0.01, rho = 0.8, am = (2 * rho - 1) / (rho + 1);
  nd_problem p = free_bar(ND_SCHEME_GENERALIZED_ALPHA, &rho, tau);
  double A_old[NX + 1], A[NX + 1];
  double worst = 0, scale = 0;
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, NX + 1, A_old));
  for (int k = 0; k < 300; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, NX + 1, A));
    const double ma = (1 - am) * mass_sum(A) + am * mass_sum(A_old);
    const double applied = scalar(p, ND_CONTACT_FORCE_APPLIED);
    scale = fmax(scale, fmax(fabs(ma), fabs(applied)));
    worst = fmax(worst, fabs(ma - applied));
    memcpy(A_old, A, sizeof A);
  }
  ck_assert_msg(scale > 0 && worst <= 1e-11 * scale, "alpha-point balance off by %g (scale %g)", worst, scale);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(end_of_step_schemes_apply_lambda) {
  const nd_test_scheme schemes[] = {{ND_SCHEME_THETA, {0.5, 0}}, {ND_SCHEME_THETA, {1, 0}},
                                    {ND_SCHEME_NEWMARK, {0.25, 0.5}}};
  for (int s = 0; s < 3; ++s) {
    nd_problem p = nd_test_bar(NX, 2, schemes[s].scheme, schemes[s].params, 1.0, 0.0, 0.01);
    int64_t nq = 0;
    ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &nq));
    double *lam = malloc(sizeof(double) * (size_t)nq), *app = malloc(sizeof(double) * (size_t)nq);
    int active = 0;
    for (int k = 0; k <= 150; ++k) {
      if (k > 0) ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_get_contact_pressure(p, nq, lam));
      ND_OK_OR_FAIL(nd_get_contact_pressure_applied(p, nq, app));
      for (int64_t q = 0; q < nq; ++q) {
        ck_assert(lam[q] == app[q]);
        active += lam[q] < 0;
      }
      ck_assert(scalar(p, ND_CONTACT_FORCE) == scalar(p, ND_CONTACT_FORCE_APPLIED));
    }
    ck_assert_int_gt(active, 0);
    free(lam);
    free(app);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

START_TEST(redistributed_hybrid_energy_does_not_grow) {
  for (int degree = 1; degree <= 2; ++degree) {
    nd_problem p = nd_test_bar(NX, degree, ND_SCHEME_HYBRID, NULL, 1.0, 0.0, 0.005);
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
    double E = scalar(p, ND_ENERGY_AUGMENTED);
    const double E0 = E;
    double force = 0;
    for (int k = 0; k < 600; ++k) {
      ND_OK_OR_FAIL(nd_step(p));
      const double E1 = scalar(p, ND_ENERGY_AUGMENTED);
      /* 1e-12: the Newton tolerance, as in test_energy */
      ck_assert_msg(E1 <= E + 1e-12 * E0, "P%d step %d: E_Theta grew from %.17g to %.17g", degree, k, E, E1);
      E = E1;
      force = fmax(force, scalar(p, ND_CONTACT_FORCE_APPLIED));
    }
    ck_assert(force > 0); /* the bar did hit the obstacle */
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* The explicit scheme with redistribution (lumped and consistent mass): the
   massless DOFs are solved from their static equilibrium each step, so the
   free bar's momentum changes exactly by the applied resultant, as for the
   hybrid scheme: 1'M A^{n+1} = ND_CONTACT_FORCE_APPLIED (Newton's tolerance:
   the massless rows hold to rtol = 1e-10 of their right-hand side). The
   column sums of the redistributed P1 mass: node 0 none, node 1 3h/2 (cell
   0's mass h, HRZ-lumped or consistent alike), h inside, h/2 at x = 1. */
START_TEST(redistributed_explicit_momentum_is_the_applied_force) {
  const double params[2] = {0, 0.5}, tau = 0.004, h = 1.0 / NX;
  for (int lumped = 0; lumped <= 1; ++lumped) {
    nd_problem p = free_bar(ND_SCHEME_NEWMARK, params, tau);
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
    double A[NX + 1], worst = 0, scale = 0;
    int in_contact = 0;
    for (int k = 0; k < 1000; ++k) {
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, NX + 1, A));
      double ma = 1.5 * h * A[1] + 0.5 * h * A[NX];
      for (int i = 2; i < NX; ++i) ma += h * A[i];
      const double applied = scalar(p, ND_CONTACT_FORCE_APPLIED);
      in_contact += applied > 0;
      scale = fmax(scale, fmax(fabs(ma), fabs(applied)));
      worst = fmax(worst, fabs(ma - applied));
    }
    ck_assert_msg(in_contact > 10, "%d steps in contact", in_contact);
    ck_assert_msg(worst <= 1e-9 * scale, "lumped %d: momentum balance off by %g (scale %g)", lumped, worst, scale);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

START_TEST(checkpoints_know_the_mass_and_the_applied_pressure) {
  nd_problem p = nd_test_bar(NX, 2, ND_SCHEME_HYBRID, NULL, 1.0, 0.0, 0.005);
  nd_problem q = nd_test_bar(NX, 2, ND_SCHEME_HYBRID, NULL, 1.0, 0.0, 0.005);
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
  for (int k = 0; k < 250; ++k) ND_OK_OR_FAIL(nd_step(p));
  int64_t nb = 0, nq = 0;
  ND_OK_OR_FAIL(nd_problem_get_state_size(p, &nb));
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &nq));
  unsigned char *buf = malloc((size_t)nb);
  ND_OK_OR_FAIL(nd_problem_save_state(p, nb, buf));
  /* the same mesh with the original mass is another problem */
  ck_assert_int_eq(nd_problem_load_state(q, nb, buf), ND_ERR_STATE);
  double a1[64], a2[64], u1[2 * NX + 1], u2[2 * NX + 1];
  ck_assert_int_le(nq, 64);
  ND_OK_OR_FAIL(nd_get_contact_pressure_applied(p, nq, a1));
  for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, 2 * NX + 1, u1));
  ND_OK_OR_FAIL(nd_problem_load_state(p, nb, buf));
  ND_OK_OR_FAIL(nd_get_contact_pressure_applied(p, nq, a2));
  ck_assert(memcmp(a1, a2, sizeof(double) * (size_t)nq) == 0);
  for (int k = 0; k < 20; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, 2 * NX + 1, u2));
  ck_assert(memcmp(u1, u2, sizeof u1) == 0);
  free(buf);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

/* The explicit scheme with redistribution keeps nothing between steps but
   the state: a restart from a checkpoint in contact continues bitwise. */
START_TEST(redistributed_explicit_restarts_bitwise) {
  const double params[2] = {0, 0.5};
  nd_problem p = nd_test_bar(NX, 1, ND_SCHEME_NEWMARK, params, 1.0, 0.2, 0.5 / NX);
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
  for (int k = 0; k < 45; ++k) ND_OK_OR_FAIL(nd_step(p)); /* t = 1.125: in contact */
  ck_assert(scalar(p, ND_CONTACT_FORCE) > 0);
  int64_t nb = 0;
  ND_OK_OR_FAIL(nd_problem_get_state_size(p, &nb));
  unsigned char *buf = malloc((size_t)nb);
  ND_OK_OR_FAIL(nd_problem_save_state(p, nb, buf));
  double u1[NX + 1], u2[NX + 1], a1[NX + 1], a2[NX + 1];
  for (int k = 0; k < 40; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, NX + 1, u1));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, NX + 1, a1));
  nd_problem q = nd_test_bar(NX, 1, ND_SCHEME_NEWMARK, params, 1.0, 0.2, 0.5 / NX);
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(q, 1));
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(q, 1));
  ND_OK_OR_FAIL(nd_problem_load_state(q, nb, buf));
  for (int k = 0; k < 40; ++k) ND_OK_OR_FAIL(nd_step(q));
  ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_DISPLACEMENT, NX + 1, u2));
  ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_ACCELERATION, NX + 1, a2));
  ck_assert(memcmp(u1, u2, sizeof u1) == 0);
  ck_assert(memcmp(a1, a2, sizeof a1) == 0);
  free(buf);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

int main(void) {
  Suite *s = suite_create("pressure");
  TCase *tc = tcase_create("pressure");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, hybrid_applied_force_is_the_momentum_change);
  tcase_add_test(tc, generalized_alpha_applied_force_is_at_the_alpha_points);
  tcase_add_test(tc, end_of_step_schemes_apply_lambda);
  tcase_add_test(tc, redistributed_hybrid_energy_does_not_grow);
  tcase_add_test(tc, redistributed_explicit_momentum_is_the_applied_force);
  tcase_add_test(tc, checkpoints_know_the_mass_and_the_applied_pressure);
  tcase_add_test(tc, redistributed_explicit_restarts_bitwise);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
