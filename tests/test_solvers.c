/* Every linear-solver backend gives the same answers: the bar run through
 * the dense and the banded LAPACK paths, for symmetric (Theta = 1) and
 * non-symmetric (Theta = 0, -1) tangents, P1 and P2, all schemes. Both are
 * direct solvers of the same systems: they may differ by round-off only,
 * amplified over the run (relative 1e-10 over 240 steps). */
#include <math.h>
#include <stdlib.h>

#include "testutil.h"

static double run(int solver, int degree, int scheme, const double *params, double theta, double *u, int64_t n) {
  const int nx = 40;
  nd_problem p = nd_test_bar(nx, degree, scheme, params, theta, 0.2, 1.0 / (2 * nx));
  ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, solver));
  for (int k = 0; k < 240; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u));
  double iters = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_NEWTON_ITERATIONS_TOTAL, &iters));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return iters;
}

START_TEST(dense_and_banded_agree) {
  const double thetas[] = {1.0, 0.0, -1.0}, half = 0.5, nm[2] = {0.25, 0.5};
  const int schemes[] = {ND_SCHEME_HYBRID, ND_SCHEME_THETA, ND_SCHEME_NEWMARK};
  const double *params[] = {NULL, &half, nm};
  for (int degree = 1; degree <= 2; ++degree)
    for (int t = 0; t < 3; ++t)
      for (int s = 0; s < 3; ++s) {
        const int64_t n = degree == 1 ? 41 : 81;
        double *a = malloc(sizeof(double) * (size_t)n), *b = malloc(sizeof(double) * (size_t)n);
        const double ia = run(ND_SOLVER_DENSE, degree, schemes[s], params[s], thetas[t], a, n);
        const double ib = run(ND_SOLVER_BANDED, degree, schemes[s], params[s], thetas[t], b, n);
        double diff = 0, norm = 0;
        for (int64_t i = 0; i < n; ++i) {
          diff = fmax(diff, fabs(a[i] - b[i]));
          norm = fmax(norm, fabs(a[i]));
        }
        ck_assert_msg(diff <= 1e-10 * norm, "P%d Theta %g scheme %d: dense and banded differ by %g", degree,
                      thetas[t], schemes[s], diff / norm);
        ck_assert_double_eq(ia, ib); /* same Newton path */
        free(a);
        free(b);
      }
}
END_TEST

int main(void) {
  Suite *s = suite_create("solvers");
  TCase *tc = tcase_create("conformance");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, dense_and_banded_agree);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
