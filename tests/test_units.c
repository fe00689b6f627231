/* The same scene in scaled units and in SI gives the same dimensionless
 * answer: the 1D bar of docs/design.md §7 (E = rho = L = 1) against a steel bar
 * (E = 2.1e11 Pa, rho = 7850 kg/m^3, L = 2.5 m), both with the automatic
 * gamma0 (so gamma0 E is the same), tau = h/(2c), c = sqrt(E/rho). Lengths
 * scale with L, times with L/c, energies (per unit area) with E L. And the
 * hybrid scheme with Theta = 1 keeps E_Theta non-increasing on the stiff
 * steel bar as on the scaled one. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

static nd_problem bar(double L, double E, double rho, double gamma0E) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[2] = {-0.5 * L, 0.5 * L}, hi[2] = {0.5 * L, 1.5 * L}, zero = 0, up = 1;
  const double c = sqrt(E / rho), tau = (L / 40) / (2 * c);
  ND_OK_OR_FAIL(nd_mesh_create_interval(40, 0.0, L, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo[0], &hi[0]));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo[1], &hi[1]));
  ND_OK_OR_FAIL(nd_problem_create(m, 2, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, E, 0.3, rho));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &zero, &up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, gamma0E / E)); /* 0: automatic */
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * (size_t)n), *u0 = malloc(sizeof(double) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n; ++i) u0[i] = 0.5 * (L - x[i]);
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, NULL));
  free(x);
  free(u0);
  return p;
}

START_TEST(si_and_scaled_units_agree) {
  const double L = 2.5, E = 2.1e11, rho = 7850;
  nd_problem a = bar(1, 1, 1, 0), b = bar(L, E, rho, 0);
  ck_assert_double_eq_tol(scalar(a, ND_GAMMA0) * 1, scalar(b, ND_GAMMA0) * E, 1e-14 * scalar(a, ND_GAMMA0));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(a, &n));
  double *ua = malloc(sizeof(double) * (size_t)n), *ub = malloc(sizeof(double) * (size_t)n);
  double worst = 0, prev_a = scalar(a, ND_ENERGY_AUGMENTED), prev_b = scalar(b, ND_ENERGY_AUGMENTED);
  for (int k = 0; k < 480; ++k) { /* T = 6: two impacts */
    ND_OK_OR_FAIL(nd_step(a));
    ND_OK_OR_FAIL(nd_step(b));
    ND_OK_OR_FAIL(nd_get_field(a, ND_FIELD_DISPLACEMENT, n, ua));
    ND_OK_OR_FAIL(nd_get_field(b, ND_FIELD_DISPLACEMENT, n, ub));
    for (int64_t i = 0; i < n; ++i) worst = fmax(worst, fabs(ua[i] - ub[i] / L));
    const double ea = scalar(a, ND_ENERGY_AUGMENTED), eb = scalar(b, ND_ENERGY_AUGMENTED);
    worst = fmax(worst, fabs(ea - eb / (E * L)) / 0.125);
    ck_assert_msg(ea <= prev_a * (1 + 1e-12) && eb <= prev_b * (1 + 1e-12), "E_Theta rose at step %d", k);
    prev_a = ea, prev_b = eb;
  }
  printf("scaled vs SI bar, 480 steps: largest difference of u/L and of E_Theta/(E L) (relative to 1/8): %.2e\n",
         worst);
  ck_assert_double_lt(worst, 1e-10);
  free(ua);
  free(ub);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

/* the stiffest penalty of the stability suite on the steel bar: the hybrid
   scheme's E_Theta still never rises (through two impacts) */
START_TEST(hybrid_energy_is_monotone_with_a_stiff_penalty) {
  nd_problem p = bar(2.5, 2.1e11, 7850, 1e-8);
  double prev = 0, e = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &prev));
  for (int k = 0; k < 480; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &e));
    ck_assert_msg(e <= prev * (1 + 1e-12), "step %d: E_Theta rose from %.17g to %.17g", k, prev, e);
    prev = e;
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("units");
  TCase *tc = tcase_create("bar");
  tcase_add_test(tc, si_and_scaled_units_agree);
  tcase_add_test(tc, hybrid_energy_is_monotone_with_a_stiff_penalty);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
