/* A failed nd_step leaves the problem exactly as it was at t^n: every field,
 * every scalar and the contact pressure compare equal bit for bit, and the
 * run continues afterwards as if the failure had never happened. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

enum { N_KEYS = 12 };

typedef struct {
  int64_t n, nq;
  double *fields; /* u, v, a */
  double *pressure;
  double scalars[N_KEYS];
} snapshot;

static snapshot take(nd_problem p) {
  snapshot s;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &s.n));
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &s.nq));
  s.fields = malloc(sizeof(double) * (size_t)(3 * s.n));
  s.pressure = malloc(sizeof(double) * (size_t)(s.nq > 0 ? s.nq : 1));
  for (int f = 0; f < 3; ++f) ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT + f, s.n, s.fields + f * s.n));
  if (s.nq > 0) ND_OK_OR_FAIL(nd_get_contact_pressure(p, s.nq, s.pressure));
  for (int k = 0; k < N_KEYS; ++k) ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME + k, &s.scalars[k]));
  return s;
}

static void assert_same(const snapshot *a, const snapshot *b) {
  ck_assert_int_eq(a->n, b->n);
  ck_assert_int_eq(a->nq, b->nq);
  ck_assert_msg(memcmp(a->fields, b->fields, sizeof(double) * (size_t)(3 * a->n)) == 0, "fields differ");
  ck_assert_msg(a->nq == 0 || memcmp(a->pressure, b->pressure, sizeof(double) * (size_t)a->nq) == 0,
                "contact pressures differ");
  for (int k = 0; k < N_KEYS; ++k)
    ck_assert_msg(memcmp(&a->scalars[k], &b->scalars[k], sizeof(double)) == 0, "scalar %d differs: %.17g vs %.17g",
                  ND_TIME + k, a->scalars[k], b->scalars[k]);
}

static void release(snapshot *s) {
  free(s->fields);
  free(s->pressure);
}

START_TEST(newton_failure_keeps_the_state) {
  /* Newmark with one Newton iteration allowed: the first impact (t = 1)
     needs more, so that step fails; with the default limit it succeeds. */
  const double nm[2] = {0.25, 0.5}, tau = 1.0 / 80;
  nd_problem p = nd_test_bar(40, 2, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, tau);
  nd_problem ref = nd_test_bar(40, 2, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, tau);
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0.0, 1));
  int failures = 0;
  for (int k = 0; k < 160; ++k) {
    snapshot before = take(p);
    int status = nd_step(p);
    if (status != ND_OK) {
      ck_assert_int_eq(status, ND_ERR_NEWTON);
      ck_assert_msg(strstr(nd_last_error(), "nd_step:") == nd_last_error(), "message: %s", nd_last_error());
      snapshot after = take(p);
      assert_same(&before, &after);
      release(&after);
      ++failures;
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0.0, 50));
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0.0, 1));
    }
    release(&before);
    ND_OK_OR_FAIL(nd_step(ref));
    /* the run with failures is the uninterrupted run */
    snapshot a = take(p), b = take(ref);
    ck_assert_msg(memcmp(a.fields, b.fields, sizeof(double) * (size_t)(3 * a.n)) == 0, "step %d differs", k);
    release(&a);
    release(&b);
  }
  ck_assert_int_gt(failures, 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&ref));
}
END_TEST

START_TEST(divergence_is_refused_and_keeps_the_state) {
  /* explicit Newmark far above the critical step: the solution grows
     without bound until a step would produce Inf or NaN */
  const double nm[2] = {0.0, 0.5};
  nd_problem p = nd_test_bar(40, 1, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, 1.0);
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  /* the guards would refuse it long before (test_guards): off, to reach the
     last line of defence */
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY, 0));
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0)); /* (it refuses the growth at its first impact) */
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_PENETRATION, 0));
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0));
  int status = ND_OK, k = 0;
  snapshot before = take(p);
  for (; k < 100000 && status == ND_OK; ++k) {
    release(&before);
    before = take(p);
    status = nd_step(p);
  }
  ck_assert_int_eq(status, ND_ERR_NONFINITE_STATE);
  snapshot after = take(p);
  assert_same(&before, &after);
  for (int64_t i = 0; i < 3 * after.n; ++i) ck_assert(isfinite(after.fields[i]));
  release(&before);
  release(&after);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* The guards refuse a blow-up long before it overflows, each with its own
   code, and keep the state: explicit Newmark far above its critical step (the
   energy guard), and Theta = 0 with a penalty so weak that the bar sinks into
   the obstacle (the penetration guard). */
START_TEST(guards_refuse_and_keep_the_state) {
  const double nm[2] = {0.0, 0.5}, avg[2] = {0.25, 0.5};
  struct {
    nd_problem p;
    int code;
  } cases[2];
  cases[0].p = nd_test_bar(40, 1, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, 1.1 / 40); /* tau = 1.1 h */
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(cases[0].p, 1));
  ND_OK_OR_FAIL(nd_problem_set_guard(cases[0].p, ND_GUARD_CRITICAL_TIMESTEP, 0)); /* reach the energy guard */
  cases[0].code = ND_ERR_ENERGY_GROWTH;
  cases[1].p = nd_test_bar(40, 1, ND_SCHEME_NEWMARK, avg, 0.0, 1e4, 1.0 / 80);
  cases[1].code = ND_ERR_PENETRATION;
  for (int c = 0; c < 2; ++c) {
    nd_problem p = cases[c].p;
    int status = ND_OK, k = 0;
    snapshot before = take(p);
    for (; k < 1000 && status == ND_OK; ++k) {
      release(&before);
      before = take(p);
      status = nd_step(p);
    }
    ck_assert_msg(status == cases[c].code, "case %d: step %d returned %d (%s)", c, k, status, nd_last_error());
    printf("case %d refused at step %d: %s\n", c, k, nd_last_error());
    snapshot after = take(p);
    assert_same(&before, &after);
    /* and the energy at t^n is within the guard's factor */
    double E = 0, W = 0, E0 = c == 0 ? 0.125 : 0.125;
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_MECHANICAL, &E));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_WORK, &W));
    ck_assert_double_le(E, 2 * (E0 + fmax(W, 0)) * (1 + 1e-12));
    release(&before);
    release(&after);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* nd_problem_setup does the first step's set-up early: nothing observable
   changes, and the steps after it are bitwise those of a twin without it. */
START_TEST(setup_is_invisible) {
  const double nm[2] = {0.25, 0.5};
  for (int scheme = ND_SCHEME_NEWMARK; scheme <= ND_SCHEME_HYBRID; ++scheme) {
    nd_problem a = nd_test_bar(20, 2, scheme, nm, 1.0, 0.2, 0.025);
    nd_problem b = nd_test_bar(20, 2, scheme, nm, 1.0, 0.2, 0.025);
    snapshot before = take(a);
    ND_OK_OR_FAIL(nd_problem_setup(a));
    ND_OK_OR_FAIL(nd_problem_setup(a)); /* a second call is a no-op */
    snapshot after = take(a);
    assert_same(&before, &after);
    release(&before);
    release(&after);
    for (int k = 0; k < 60; ++k) { /* into contact at t = 1 */
      ND_OK_OR_FAIL(nd_step(a));
      ND_OK_OR_FAIL(nd_step(b));
    }
    snapshot sa = take(a), sb = take(b);
    assert_same(&sa, &sb);
    release(&sa);
    release(&sb);
    ND_OK_OR_FAIL(nd_problem_destroy(&a));
    ND_OK_OR_FAIL(nd_problem_destroy(&b));
  }
}
END_TEST

/* Theta = 1 with gamma0 E far above 1 and a long step: c M + K_Theta is
   indefinite, and nd_problem_setup says so before any step. */
START_TEST(setup_reports_an_ill_posed_step) {
  const double nm[2] = {0.25, 0.5};
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_NEWMARK, nm, 1.0, 100.0, 1.0);
  snapshot before = take(p);
  ck_assert_int_eq(nd_problem_setup(p), ND_ERR_INDEFINITE);
  ck_assert_ptr_nonnull(strstr(nd_last_error(), "nd_problem_setup"));
  snapshot after = take(p);
  assert_same(&before, &after);
  release(&before);
  release(&after);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("step_failure");
  TCase *tc = tcase_create("problem");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, newton_failure_keeps_the_state);
  tcase_add_test(tc, divergence_is_refused_and_keeps_the_state);
  tcase_add_test(tc, guards_refuse_and_keep_the_state);
  tcase_add_test(tc, setup_is_invisible);
  tcase_add_test(tc, setup_reports_an_ill_posed_step);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
