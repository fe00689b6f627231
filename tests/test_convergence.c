/* The bar's errors against its exact solution (docs/design.md §7) decrease under
 * refinement, NX = 40, 80, 160, 320 with tau = h/2, over one period T = 3
 * (flight, impact, contact, release), at the observed rates asserted below.
 * (The contact stress is not among them: the Nitsche stress oscillates about
 * -1/2 while in contact and its L2(0,T) error stays near 0.4-0.5 at these
 * resolutions; the report issue studies it.)
 * The same on strips of Q1/Q2 quadrilaterals and hexahedra (one cell across,
 * nu = 0, gamma matched: test_quads shows such a strip is the bar to
 * round-off), their x-displacement along an edge measured as the bar's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bar1d_exact.h"
#include "testutil.h"

/* the bar (dim 1) or a strip of Q cells (dim 2, 3): on a strip, the nodes
   of the edge y = z = 0 and their x-components are the bar's */
static norm_acc run_bar_in(int dim, int nx, int degree, int scheme, const double *params) {
  const double tau = 0.5 / nx;
  const int64_t steps = 6 * nx; /* T = 3 */
  nd_problem p = dim == 1 ? nd_test_bar(nx, degree, scheme, params, 1.0, 0.2, tau)
                          : nd_test_strip(dim, dim == 2 ? ND_CELL_QUADRILATERAL : ND_CELL_HEXAHEDRON, nx, degree,
                                          scheme, params, 1.0, 0.2 / sqrt((double)dim), tau);
  int64_t n = 0, m = 0;
  const int points = (int)pow(degree + 1, dim - 1);
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * (size_t)(n * dim)), *U = malloc(sizeof(double) * (size_t)(n * dim)),
         *V = malloc(sizeof(double) * (size_t)(n * dim)), *xe = malloc(sizeof(double) * (size_t)n),
         *Ue = malloc(sizeof(double) * (size_t)n), *Ve = malloc(sizeof(double) * (size_t)n);
  int64_t *edge = malloc(sizeof(int64_t) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n; ++i) {
    int on_edge = 1;
    for (int k = 1; k < dim; ++k) on_edge &= x[i * dim + k] == 0;
    if (on_edge) xe[m] = x[i * dim], edge[m++] = i;
  }
  grid g;
  ck_assert_int_eq(grid_init(&g, degree, nx, xe, m), 0);
  norm_acc acc = {{0}, {0}};
  for (int64_t k = 0; k <= steps; ++k) {
    if (k > 0) ND_OK_OR_FAIL(nd_step(p));
    double lam = 0, at_points[9]; /* the contact facet's points: (degree + 1)^(dim - 1) */
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, U));
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, n, V));
    for (int64_t i = 0; i < m; ++i) Ue[i] = U[edge[i] * dim], Ve[i] = V[edge[i] * dim];
    ND_OK_OR_FAIL(nd_get_contact_pressure(p, points, at_points));
    for (int q = 0; q < points; ++q) lam += at_points[q] / points; /* (not asserted: the stress, their mean) */
    const phase ph = phase_at((double)k * tau);
    const space_norms s = norms_at(&g, Ue, Ve, ph);
    acc_add(&acc, &s, lam - exact_stress(ph), exact_stress(ph), (k == 0 || k == steps) ? 0.5 * tau : tau);
  }
  grid_free(&g);
  free(x), free(U), free(V), free(xe), free(Ue), free(Ve), free(edge);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return acc;
}

/* Observed rates: least-squares slopes of log(error) against log(h) over
   NX = 40, 80, 160, 320. The exact u has kinks and u_x, v jump by 1/2 across
   the travelling waves, so u is only in H^{3/2-}: a jump carried by a
   second-order scheme converges at about 1/3 in L2, and u, one derivative
   smoother, faster. Measured (P1/P2, hybrid/Newmark): u in L2(L2) 0.51-0.67,
   u in Linf(L2) 0.48-0.63, v in L2(L2) 0.29-0.31; generalized-alpha (rho_inf
   0.8 and 0.5): 0.61-0.70, 0.60-0.67, 0.26-0.32. The rate of a single
   halving is still pre-asymptotic here (it ranges from 0.13 to 0.87 with
   where the kinks fall relative to the nodes), which is why the slope is
   fitted over four levels; its bound sits 0.1 below the smallest measured
   slope, and every single refinement must still reduce the error. */
static const struct {
  int norm;
  double min_rate;
} expected[] = {{L2_L2_U, 0.41}, {LINF_L2_U, 0.38}, {L2_L2_V, 0.19}};

enum { LEVELS = 4 };

static double fitted_rate(const double *err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int l = 0; l < LEVELS; ++l) {
    const double x = -l * log(2.0), y = log(err[l]); /* log h up to a constant */
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (LEVELS * sxy - sx * sy) / (LEVELS * sxx - sx * sx);
}

/* the errors of LEVELS runs (NX = 40 << level) decrease at every
   refinement, and their fitted rates meet expected[] */
static void check_rates(const norm_acc *acc, const char *what, int degree, int scheme) {
  for (size_t e = 0; e < sizeof expected / sizeof expected[0]; ++e) {
    const int i = expected[e].norm;
    double err[LEVELS];
    for (int level = 0; level < LEVELS; ++level) err[level] = acc_relative(&acc[level], i);
    for (int level = 0; level + 1 < LEVELS; ++level)
      ck_assert_msg(err[level + 1] < err[level], "%s%d scheme %d %s: error grew from NX %d to %d", what, degree,
                    scheme, norm_names[i], 40 << level, 80 << level);
    const double rate = fitted_rate(err);
    printf("%s%d scheme %d %-12s %.3e %.3e %.3e %.3e  rate %.3f\n", what, degree, scheme, norm_names[i], err[0],
           err[1], err[2], err[3], rate);
    ck_assert_msg(rate >= expected[e].min_rate, "%s%d scheme %d %s: rate %.3f < %.2f", what, degree, scheme,
                  norm_names[i], rate, expected[e].min_rate);
  }
}

START_TEST(errors_decrease_under_refinement) {
  const double nm[2] = {0.25, 0.5}, ga8 = 0.8, ga5 = 0.5;
  const int schemes[] = {ND_SCHEME_HYBRID, ND_SCHEME_NEWMARK, ND_SCHEME_GENERALIZED_ALPHA,
                         ND_SCHEME_GENERALIZED_ALPHA};
  const double *params[] = {NULL, nm, &ga8, &ga5};
  for (int degree = 1; degree <= 2; ++degree)
    for (int s = 0; s < 4; ++s) {
      norm_acc acc[LEVELS];
      for (int level = 0; level < LEVELS; ++level)
        acc[level] = run_bar_in(1, 40 << level, degree, schemes[s], params[s]);
      check_rates(acc, "P", degree, schemes[s]);
    }
}
END_TEST

/* Q1/Q2 strips, 2D and 3D, the hybrid scheme: the bar's rates (the strip
   is the bar, test_quads: its errors are the hybrid P1/P2 bar's above to
   round-off, measured 0.62/0.64, 0.61/0.60, 0.31/0.32), the same bounds */
START_TEST(q_strips_converge_as_the_bar) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  norm_acc acc[LEVELS];
  for (int level = 0; level < LEVELS; ++level)
    acc[level] = run_bar_in(dim, 40 << level, degree, ND_SCHEME_HYBRID, NULL);
  check_rates(acc, dim == 2 ? "Q(2D)" : "Q(3D)", degree, ND_SCHEME_HYBRID);
}
END_TEST
int main(void) {
  Suite *s = suite_create("convergence");
  TCase *tc = tcase_create("bar");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, errors_decrease_under_refinement);
  tcase_add_loop_test(tc, q_strips_converge_as_the_bar, 0, 4);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
