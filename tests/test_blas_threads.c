/* The BLAS thread policy (nd_set_blas_threads), seen from outside: the
   caller's count is back when the calls return, after failed steps and
   calls from two threads at once (unit_blas_threads sees inside a call). Observed through OpenBLAS's
   own getter, found like the library finds it; without OpenBLAS only the
   setting's round trip and its refusals are checked (and that is printed). */
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>

#include "testutil.h"

static int (*blas_get)(void);
static void (*blas_set)(int);

static int have_openblas(void) {
  blas_get = (int (*)(void))dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
  blas_set = (void (*)(int))dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  if (!blas_get || !blas_set) printf("no OpenBLAS in this process: the thread counts are not observed\n");
  return blas_get && blas_set;
}

/* the bar in contact at t = 1 (Newmark: the impact needs Newton iterations) */
static nd_problem bar(void) {
  const double nm[2] = {0.25, 0.5};
  return nd_test_bar(40, 2, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, 1.0 / 80);
}

START_TEST(the_limit_round_trips_and_refuses_negatives) {
  int n = -1;
  ND_OK_OR_FAIL(nd_get_blas_threads(&n));
  ck_assert_int_eq(n, 1); /* the default */
  ND_OK_OR_FAIL(nd_set_blas_threads(3));
  ND_OK_OR_FAIL(nd_get_blas_threads(&n));
  ck_assert_int_eq(n, 3);
  ck_assert_int_eq(nd_set_blas_threads(-1), ND_ERR_VALUE);
  ND_OK_OR_FAIL(nd_get_blas_threads(&n));
  ck_assert_int_eq(n, 3); /* unchanged by the refused call */
  ck_assert_int_eq(nd_get_blas_threads(NULL), ND_ERR_NULL);
  ND_OK_OR_FAIL(nd_set_blas_threads(1));
}
END_TEST

START_TEST(steps_restore_the_callers_count) {
  if (!have_openblas()) return;
  blas_set(2);
  ck_assert_int_eq(blas_get(), 2);
  for (int limit = 0; limit <= 1; ++limit) {
    ND_OK_OR_FAIL(nd_set_blas_threads(limit));
    nd_problem p = bar();
    for (int k = 0; k < 100; ++k) ND_OK_OR_FAIL(nd_step(p)); /* through the impact at t = 1 */
    ck_assert_int_eq(blas_get(), 2);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  ND_OK_OR_FAIL(nd_set_blas_threads(1));
}
END_TEST

START_TEST(a_failed_step_restores_the_callers_count) {
  if (!have_openblas()) return;
  blas_set(2);
  nd_problem p = bar();
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0.0, 1)); /* the impact fails */
  int status = ND_OK, k = 0;
  for (; k < 100 && status == ND_OK; ++k) status = nd_step(p);
  ck_assert_int_eq(status, ND_ERR_NEWTON);
  ck_assert_int_eq(blas_get(), 2);
  ck_assert_int_eq(nd_step(NULL), ND_ERR_NULL); /* refused at the boundary */
  ck_assert_int_eq(blas_get(), 2);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

static void *run_bar(void *data) {
  nd_problem p = data;
  for (int k = 0; k < 200; ++k)
    if (nd_step(p) != ND_OK) return data;
  return NULL;
}

START_TEST(two_threads_stepping_at_once_restore_the_count) {
  if (!have_openblas()) return;
  blas_set(2);
  for (int round = 0; round < 5; ++round) {
    nd_problem a = bar(), b = bar();
    pthread_t ta, tb;
    ck_assert_int_eq(pthread_create(&ta, NULL, run_bar, a), 0);
    ck_assert_int_eq(pthread_create(&tb, NULL, run_bar, b), 0);
    void *ra, *rb;
    ck_assert_int_eq(pthread_join(ta, &ra), 0);
    ck_assert_int_eq(pthread_join(tb, &rb), 0);
    ck_assert_ptr_null(ra);
    ck_assert_ptr_null(rb);
    ck_assert_int_eq(blas_get(), 2);
    ND_OK_OR_FAIL(nd_problem_destroy(&a));
    ND_OK_OR_FAIL(nd_problem_destroy(&b));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("blas_threads");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, the_limit_round_trips_and_refuses_negatives);
  tcase_add_test(tc, steps_restore_the_callers_count);
  tcase_add_test(tc, a_failed_step_restores_the_callers_count);
  tcase_add_test(tc, two_threads_stepping_at_once_restore_the_count);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
