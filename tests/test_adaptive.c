/* Adaptive time steps (nd_problem_set_adaptive_timestep, docs/design.md
 * §10.8). The checks are identities: an accepted step is bitwise the fixed
 * step of its size (a rejected try leaves no trace), the step that first
 * touches lands at the exact touch of a rigid flight, the hybrid Theta = 1
 * ledger stays non-increasing at any sizes, the time error against a
 * reference run falls with the tolerance, a restart is bitwise, and a step
 * the control cannot pass leaves the problem as it was. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* A free bar [0, 1] (region 1 at x = 0) flying at velocity -v0 towards the
   plane x = -gap: the first touch is at t = gap / v0 exactly. */
static nd_problem flying_bar(int nx, int degree, int scheme, double gap, double v0, double tau) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double up = 1, lo = -0.5, hi = 0.5, plane = -gap;
  ND_OK_OR_FAIL(nd_mesh_create_interval(nx, 0.0, 1.0, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo, &hi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &plane, &up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.2));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *v = malloc(sizeof(double) * (size_t)n);
  for (int64_t i = 0; i < n; ++i) v[i] = -v0;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v));
  free(v);
  return p;
}

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* E_Theta - W - W_obstacle: the hybrid Theta = 1 scheme's ledger */
static double ledger(nd_problem p) {
  return scalar(p, ND_ENERGY_AUGMENTED) - scalar(p, ND_WORK) - scalar(p, ND_WORK_OBSTACLE);
}

/* The first touch of a rigid flight: P_q is linear in t until then, so the
   cut step ends at gap / v0 to round-off; the ledger never rises past
   round-off through the impact, whatever sizes the control takes. */
START_TEST(lands_at_first_touch) {
  const double gap = 0.1037, v0 = 1.0;
  nd_problem p = flying_bar(20, 1 + _i, ND_SCHEME_HYBRID, gap, v0, 0.04);
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(p, 1e-3, 1e-6, 0.04));
  double t = 0, landed = INFINITY, L = ledger(p), rise = 0;
  const double E0 = scalar(p, ND_ENERGY_MECHANICAL);
  for (int k = 0; k < 400 && t < 2.5; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    t = scalar(p, ND_TIME);
    landed = fmin(landed, fabs(t - gap / v0));
    const double L1 = ledger(p);
    if (L1 - L > rise) rise = L1 - L;
    L = L1;
  }
  /* a step ended at the touch (tau_max = 0.04 does not divide 0.1037) */
  ck_assert_msg(landed <= 1e-12, "no step ended within %g of the touch at %g", landed, gap / v0);
  ck_assert_double_ge(scalar(p, ND_STAT_STEPS_REJECTED), 1);
  /* round-off of E0 = 0.5 summed over a few hundred steps */
  ck_assert_msg(rise <= 1e-13 * E0, "the ledger rose by %g (E0 %g)", rise, E0);
  /* turned off, the steps take nd_problem_set_timestep's size again */
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(p, 0, 0, 0));
  ck_assert_double_eq(scalar(p, ND_TIMESTEP), 0.04);
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert_double_eq(scalar(p, ND_TIMESTEP_LAST), 0.04);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

static const int kSchemes[] = {ND_SCHEME_HYBRID, ND_SCHEME_NEWMARK, ND_SCHEME_GENERALIZED_ALPHA, ND_SCHEME_THETA};
/* each scheme's parameters: none; beta, gamma; rho_inf; theta */
static const double *const kParams[] = {NULL, (const double[]){0.25, 0.5}, (const double[]){0.8},
                                        (const double[]){0.5}};

/* An adaptive run, then a fixed-step run given the same sizes one by one:
   bitwise the same states, so the rejected tries left nothing behind
   (the pre-compressed bar of docs/design.md §7, released onto the plane). */
START_TEST(replays_bitwise) {
  const int scheme = kSchemes[_i % 4], degree = 1 + _i / 4;
  nd_problem a = nd_test_bar(20, degree, scheme, kParams[_i % 4], 1.0, 0.2, 0.05);
  nd_problem b = nd_test_bar(20, degree, scheme, kParams[_i % 4], 1.0, 0.2, 0.05);
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(a, 1e-3, 1e-6, 0.05));
  int changes = 0;
  for (int k = 0; k < 200; ++k) {
    const double before = scalar(a, ND_TIMESTEP_LAST);
    ND_OK_OR_FAIL(nd_step(a));
    changes += k > 0 && scalar(a, ND_TIMESTEP_LAST) != before;
    ND_OK_OR_FAIL(nd_problem_set_timestep(b, scalar(a, ND_TIMESTEP_LAST)));
    ND_OK_OR_FAIL(nd_step(b));
    nd_test_snapshot sa = nd_test_take(a, 1), sb = nd_test_take(b, 1);
    /* (the scalars include ND_TIMESTEP, the next size: compare the fields and the clock) */
    ck_assert_msg(memcmp(sa.fields, sb.fields, sizeof(double) * (size_t)(3 * sa.n)) == 0, "step %d differs", k + 1);
    ck_assert_msg(sa.scalars[0] == sb.scalars[0], "step %d: t differs", k + 1);
    nd_test_snapshot_free(&sa);
    nd_test_snapshot_free(&sb);
  }
  ck_assert_double_ge(scalar(a, ND_STAT_STEPS_REJECTED), 1);
  /* (a measurement, not a check: the factorizations of any matrix, the
     adaptive run's rejected tries' sizes included, against those of the run
     given the accepted sizes by hand; docs/design.md §10.8) */
  printf("replay %d: %d size changes, %g rejected tries, factorizations %g (fixed run given the sizes: %g)\n", _i,
         changes, scalar(a, ND_STAT_STEPS_REJECTED), scalar(a, ND_STAT_FACTORIZATIONS),
         scalar(b, ND_STAT_FACTORIZATIONS));
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

/* max over the nodes of |U - U_ref| at t = T: the run steps to T exactly
   (its last step cut to land there through nd_problem_set_timestep) */
static double run_to(nd_problem p, double T, const double *U_ref, int64_t n, double *U) {
  double t = 0;
  while (T - t > 1e-13) {
    const double next = scalar(p, ND_TIMESTEP);
    if (t + next > T) {
      ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(p, 0, 0, 0));
      ND_OK_OR_FAIL(nd_problem_set_timestep(p, T - t));
    }
    ND_OK_OR_FAIL(nd_step(p));
    t = scalar(p, ND_TIME);
  }
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, U));
  double e = 0;
  if (U_ref)
    for (int64_t i = 0; i < n; ++i) e = fmax(e, fabs(U[i] - U_ref[i]));
  return e;
}

/* The time error against a run with 1/40 of the smallest size the control
   took, at T = 1.5 (through the impact and the contact): it falls with the
   tolerance. */
START_TEST(error_falls_with_tolerance) {
  const double T = 1.5;
  nd_problem ref = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 1e-4);
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(ref, &n));
  double *U_ref = malloc(sizeof(double) * (size_t)n), *U = malloc(sizeof(double) * (size_t)n);
  run_to(ref, T, NULL, n, U_ref);
  double last = INFINITY;
  const double tolerances[] = {1e-2, 1e-3, 1e-4};
  for (int k = 0; k < 3; ++k) {
    nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.05);
    ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(p, tolerances[k], 1e-6, 0.05));
    const double e = run_to(p, T, U_ref, n, U);
    printf("tolerance %g: %g steps, %g rejected, error %g\n", tolerances[k], scalar(p, ND_STAT_STEPS_ACCEPTED),
           scalar(p, ND_STAT_STEPS_REJECTED), e);
    ck_assert_msg(e < last, "tolerance %g: error %g, not below %g", tolerances[k], e, last);
    last = e;
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  free(U_ref);
  free(U);
  ND_OK_OR_FAIL(nd_problem_destroy(&ref));
}
END_TEST

/* A rectangle falling onto a slightly tilted plane: its bottom's points
   touch one after the other, several within one large step. */
static nd_problem tilted_drop(double tau) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[2] = {0, 0}, hi[2] = {2, 0.5}, blo[2] = {-1, -1e-9}, bhi[2] = {3, 1e-9};
  const double point[2] = {2, -0.01}, normal[2] = {-0.05, 1};
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(16, 4, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, point, normal));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *v = calloc((size_t)(2 * n), sizeof(double));
  for (int64_t i = 0; i < n; ++i) v[2 * i + 1] = -0.2;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v));
  free(v);
  return p;
}

/* With friction the points' values hold the tangential ones after the
   normal ones; the first-touch cut read them as normal values (past the
   end of its arrays: valgrind, in the stability suite's adaptive reruns).
   Coulomb's F = 0 with Theta = 0 is the frictionless method (the
   tangential Theta-term vanishes; docs/design.md §10.2): the adaptive run
   takes the same steps, cut at the same touches, to round-off. */
START_TEST(first_touch_with_friction) {
  const double F = 0;
  double t[2][200];
  int steps[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    nd_problem p = tilted_drop(0.2);
    ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 0.0, 0.0));
    if (k) ND_OK_OR_FAIL(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
    ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(p, 1e-3, 1e-6, 0.2));
    for (; steps[k] < 200 && scalar(p, ND_TIME) < 2; ++steps[k]) {
      ND_OK_OR_FAIL(nd_step(p));
      t[k][steps[k]] = scalar(p, ND_TIME);
    }
    ck_assert_double_ge(scalar(p, ND_STAT_STEPS_REJECTED), 1); /* (the touches cut steps) */
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  ck_assert_int_eq(steps[0], steps[1]);
  for (int i = 0; i < steps[0]; ++i)
    ck_assert_msg(fabs(t[1][i] - t[0][i]) <= 1e-12, "step %d ends at %.17g with friction, %.17g without", i, t[1][i],
                  t[0][i]);
}
END_TEST

/* Newton limited to 2 iterations fails where a large step activates several
   points at once (and says that adaptive steps exist); adaptive steps retry
   it smaller and go on to the end. */
START_TEST(mends_newton_failures) {
  nd_problem p = tilted_drop(0.2);
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0.0, 2));
  /* (without the penetration guard, which refuses the sinking large step first) */
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_PENETRATION, 0));
  int status = ND_OK;
  for (int k = 0; k < 40 && status == ND_OK; ++k) status = nd_step(p);
  ck_assert_int_eq(status, ND_ERR_NEWTON);
  ck_assert_ptr_nonnull(strstr(nd_last_error(), "nd_problem_set_adaptive_timestep"));
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_PENETRATION, 4));
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(p, 1.0, 1e-6, 0.2));
  while (scalar(p, ND_TIME) < 8) ND_OK_OR_FAIL(nd_step(p));
  ck_assert_double_ge(scalar(p, ND_STAT_STEPS_REJECTED), 1);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* A checkpoint holds the control (the next size, the last mean
   acceleration): a resumed run is bitwise the uninterrupted one. */
START_TEST(restarts_bitwise) {
  nd_problem a = nd_test_bar(20, 1, ND_SCHEME_NEWMARK, kParams[1], 1.0, 0.2, 0.05);
  nd_problem b = nd_test_bar(20, 1, ND_SCHEME_NEWMARK, kParams[1], 1.0, 0.2, 0.05);
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(a, 1e-3, 1e-6, 0.05));
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(b, 1e-3, 1e-6, 0.05));
  for (int k = 0; k < 60; ++k) ND_OK_OR_FAIL(nd_step(a));
  int64_t size = 0;
  unsigned char *buf = nd_test_checkpoint(a, &size);
  ND_OK_OR_FAIL(nd_problem_load_state(b, size, buf));
  free(buf);
  for (int k = 0; k < 100; ++k) {
    ND_OK_OR_FAIL(nd_step(a));
    ND_OK_OR_FAIL(nd_step(b));
  }
  nd_test_snapshot sa = nd_test_take(a, 1), sb = nd_test_take(b, 1);
  ck_assert(nd_test_same(&sa, &sb));
  nd_test_snapshot_free(&sa);
  nd_test_snapshot_free(&sb);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

/* A tolerance no size down to tau_min meets: ND_ERR_ACCURACY, the problem
   as it was (the same bits, the same next size); an explicit scheme is
   refused the same way. */
START_TEST(refusals_leave_no_trace) {
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.05);
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(p, 1e-9, 0.0125, 0.05));
  int status = ND_OK;
  for (int k = 0; k < 200 && status == ND_OK; ++k) {
    nd_test_snapshot before = nd_test_take(p, 1);
    status = nd_step(p);
    if (status == ND_OK) {
      nd_test_snapshot_free(&before);
      continue;
    }
    ck_assert_int_eq(status, ND_ERR_ACCURACY);
    ck_assert_ptr_nonnull(strstr(nd_last_error(), "tau_min"));
    nd_test_snapshot after = nd_test_take(p, 1);
    ck_assert(nd_test_same(&before, &after));
    nd_test_snapshot_free(&before);
    nd_test_snapshot_free(&after);
  }
  ck_assert_int_eq(status, ND_ERR_ACCURACY);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));

  const double beta0[] = {0.0, 0.5};
  nd_problem e = nd_test_bar(20, 1, ND_SCHEME_NEWMARK, beta0, 1.0, 0.2, 0.001);
  ND_OK_OR_FAIL(nd_problem_set_adaptive_timestep(e, 1e-3, 1e-6, 0.01));
  nd_test_snapshot before = nd_test_take(e, 1);
  ck_assert_int_eq(nd_step(e), ND_ERR_STATE);
  nd_test_snapshot after = nd_test_take(e, 1);
  ck_assert(nd_test_same(&before, &after));
  nd_test_snapshot_free(&before);
  nd_test_snapshot_free(&after);
  ND_OK_OR_FAIL(nd_problem_destroy(&e));
}
END_TEST

int main(void) {
  Suite *s = suite_create("adaptive");
  TCase *tc = tcase_create("adaptive");
  tcase_set_timeout(tc, 300);
  tcase_add_loop_test(tc, lands_at_first_touch, 0, 2);
  tcase_add_test(tc, first_touch_with_friction);
  tcase_add_loop_test(tc, replays_bitwise, 0, 8);
  tcase_add_test(tc, error_falls_with_tolerance);
  tcase_add_test(tc, mends_newton_failures);
  tcase_add_test(tc, restarts_bitwise);
  tcase_add_test(tc, refusals_leave_no_trace);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
