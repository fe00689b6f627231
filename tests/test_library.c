/* The library-level API: nd_version against the header macros, and the
 * monitor callback of nd_step (docs/design.md §6). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "testutil.h"

START_TEST(version_matches_header) {
  int major = -1, minor = -1, patch = -1;
  ND_OK_OR_FAIL(nd_version(&major, &minor, &patch));
  ck_assert_str_eq(nd_last_error(), "");
  ck_assert_int_eq(major, ND_VERSION_MAJOR);
  ck_assert_int_eq(minor, ND_VERSION_MINOR);
  ck_assert_int_eq(patch, ND_VERSION_PATCH);
  char expected[64];
  snprintf(expected, sizeof expected, "%d.%d.%d", ND_VERSION_MAJOR, ND_VERSION_MINOR,
           ND_VERSION_PATCH);
  ck_assert_str_eq(ND_VERSION_STRING, expected);
  snprintf(expected, sizeof expected, "%d.%d.%d", major, minor, patch);
  ck_assert_str_eq(ND_VERSION_STRING, expected);
}
END_TEST

START_TEST(version_null_pointers) {
  int a = 0, b = 0, c = 0;
  const struct {
    int *major, *minor, *patch;
    const char *name;
  } cases[] = {{NULL, &b, &c, "major"},
               {&a, NULL, &c, "minor"},
               {&a, &b, NULL, "patch"},
               {NULL, NULL, NULL, NULL}};
  for (size_t i = 0; i < sizeof cases / sizeof *cases; ++i) {
    const int st = nd_version(cases[i].major, cases[i].minor, cases[i].patch);
    const char *msg = nd_last_error();
    ck_assert_msg(st == ND_ERR_NULL, "case %zu: nd_version returned %d (%s)", i, st,
                  nd_strerror(st));
    ck_assert_msg(msg != NULL && strncmp(msg, "nd_version: ", 12) == 0,
                  "case %zu: message '%s' does not start with 'nd_version: '", i,
                  msg ? msg : "(NULL)");
    if (cases[i].name)
      ck_assert_msg(strstr(msg, cases[i].name) != NULL, "case %zu: message '%s' does not name %s",
                    i, msg, cases[i].name);
  }
}
END_TEST

/* ---- monitor ------------------------------------------------------------ */

struct counter {
  nd_problem expected_handle;
  int calls;
  int stop_at;       /* return non-zero on this call */
  double time[8];    /* ND_TIME seen by the monitor, per call */
  double index[8];   /* ND_STEP_INDEX seen by the monitor, per call */
  int scalar_status; /* first non-ND_OK status of nd_get_scalar in the callback */
};

static int count_and_stop(nd_problem p, void *userdata) {
  struct counter *c = userdata;
  if (p != c->expected_handle) c->scalar_status = -1000;
  double t = NAN, n = NAN;
  const int s1 = nd_get_scalar(p, ND_TIME, &t);
  const int s2 = nd_get_scalar(p, ND_STEP_INDEX, &n);
  if (c->scalar_status == ND_OK) c->scalar_status = s1 != ND_OK ? s1 : s2;
  if (c->calls < 8) {
    c->time[c->calls] = t;
    c->index[c->calls] = n;
  }
  ++c->calls;
  return c->calls == c->stop_at ? 1 : 0;
}

static double scalar(nd_problem p, int key) {
  double x = NAN;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

START_TEST(monitor_stops_on_third_step) {
  const double tau = 0.025;
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, tau);
  struct counter c = {p, 0, 3, {0}, {0}, ND_OK};
  ND_OK_OR_FAIL(nd_problem_set_monitor(p, count_and_stop, &c));
  ck_assert_int_eq(c.calls, 0); /* setting it does not call it */

  ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert_int_eq(c.calls, 2);
  const int st = nd_step(p);
  ck_assert_msg(st == ND_MONITOR_STOP, "third step returned %d (%s): %s", st, nd_strerror(st),
                nd_last_error());
  ck_assert_str_eq(nd_last_error(), "");
  ck_assert_int_eq(c.calls, 3);
  ck_assert_int_eq(c.scalar_status, ND_OK);

  /* the step was taken */
  ck_assert_double_eq(scalar(p, ND_STEP_INDEX), 3);
  ck_assert_double_eq_tol(scalar(p, ND_TIME), 3 * tau, 1e-14);
  /* the monitor saw each accepted step */
  for (int k = 0; k < 3; ++k) {
    ck_assert_double_eq(c.index[k], k + 1);
    ck_assert_double_eq_tol(c.time[k], (k + 1) * tau, 1e-14);
  }

  /* stepping may go on after a stop */
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert_int_eq(c.calls, 4);
  ck_assert_double_eq(scalar(p, ND_STEP_INDEX), 4);

  /* a NULL monitor removes it */
  ND_OK_OR_FAIL(nd_problem_set_monitor(p, NULL, NULL));
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert_int_eq(c.calls, 4);
  ck_assert_double_eq(scalar(p, ND_STEP_INDEX), 5);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* A step that fails does not call the monitor. */
START_TEST(monitor_not_called_on_failed_step) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_interval(4, 0.0, 1.0, &m));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  struct counter c = {p, 0, 1, {0}, {0}, ND_OK};
  ND_OK_OR_FAIL(nd_problem_set_monitor(p, count_and_stop, &c));
  const int st = nd_step(p); /* no material, scheme or time step */
  ck_assert_int_eq(st, ND_ERR_INCOMPLETE);
  ck_assert_int_eq(c.calls, 0);
  ck_assert_msg(strncmp(nd_last_error(), "nd_step: ", 9) == 0, "message '%s'", nd_last_error());
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

static Suite *library_suite(void) {
  Suite *s = suite_create("library");
  TCase *version = tcase_create("version");
  tcase_add_test(version, version_matches_header);
  tcase_add_test(version, version_null_pointers);
  suite_add_tcase(s, version);
  TCase *monitor = tcase_create("monitor");
  tcase_add_test(monitor, monitor_stops_on_third_step);
  tcase_add_test(monitor, monitor_not_called_on_failed_step);
  suite_add_tcase(s, monitor);
  return s;
}

int main(void) { return nd_test_run(library_suite()); }
