/* Generalized-alpha through the public API (docs/design.md §3):
 *  - rho_inf = 1 is Newmark(1/4, 1/2): without contact, with a load and from
 *    the equilibrium acceleration, the two march the same states to
 *    round-off, in 1D, 2D and 3D, P1 and P2;
 *  - with contact, Newton converges through the impacts of the disk and the
 *    ball, which bounce off the plane.
 * Its damping of the highest mode is measured in unit_schemes, its
 * convergence on the bar in test_convergence. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* A clamped block (the interval, a rectangle, a box; clamped where x0 = 0),
   under a body force, with an initial velocity: no obstacle. */
static nd_problem block(int dim, int degree, int scheme, const double *params) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1}, clamp_lo[3] = {-1, -1, -1}, clamp_hi[3] = {1e-9, 2, 2};
  if (dim == 1) ND_OK_OR_FAIL(nd_mesh_create_interval(16, 0.0, 2.0, &m));
  if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle(8, 4, lo, hi, &m));
  if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box(4, 2, 2, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, clamp_lo, clamp_hi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  const double f[3] = {0.05, -0.1, 0.02};
  ND_OK_OR_FAIL(nd_problem_set_material(p, 3.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, f));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.05));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * (size_t)(n * dim)), *v0 = malloc(sizeof(double) * (size_t)(n * dim));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n * dim; ++i) v0[i] = 0.3 * sin(1.0 + 2.0 * x[i - i % dim] + i % dim);
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v0));
  free(x);
  free(v0);
  return p;
}

START_TEST(rho_inf_one_is_newmark_without_contact) {
  const double one = 1, nm[2] = {0.25, 0.5};
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree) {
      nd_problem ga = block(dim, degree, ND_SCHEME_GENERALIZED_ALPHA, &one);
      nd_problem nw = block(dim, degree, ND_SCHEME_NEWMARK, nm);
      int64_t n = 0;
      ND_OK_OR_FAIL(nd_problem_get_node_count(ga, &n));
      const size_t len = (size_t)(n * dim);
      double *a = malloc(sizeof(double) * len), *b = malloc(sizeof(double) * len);
      double worst = 0;
      for (int k = 0; k < 100; ++k) {
        ND_OK_OR_FAIL(nd_step(ga));
        ND_OK_OR_FAIL(nd_step(nw));
        for (int field = ND_FIELD_DISPLACEMENT; field <= ND_FIELD_ACCELERATION; ++field) {
          ND_OK_OR_FAIL(nd_get_field(ga, field, n, a));
          ND_OK_OR_FAIL(nd_get_field(nw, field, n, b));
          double diff = 0, size = 0;
          for (size_t i = 0; i < len; ++i) {
            diff = fmax(diff, fabs(a[i] - b[i]));
            size = fmax(size, fabs(b[i]));
          }
          worst = fmax(worst, diff / size);
        }
      }
      /* the two solve equivalent equations (generalized-alpha's is the mean of
         the equilibria at t^n and t^{n+1}) in a different order: measured
         2.6e-12 to 1.6e-11 after 100 steps; an error in a coefficient shows
         at the size of the scheme's truncation error, 1e-3 here */
      printf("%dD P%d: generalized-alpha(1) vs Newmark(1/4,1/2), max relative difference of u, v, a: %.2e\n", dim,
             degree, worst);
      ck_assert_msg(worst < 1e-10, "%dD P%d: differ by %g", dim, degree, worst);
      free(a);
      free(b);
      ND_OK_OR_FAIL(nd_problem_destroy(&ga));
      ND_OK_OR_FAIL(nd_problem_destroy(&nw));
    }
}
END_TEST

/* The disk and the ball of docs/design.md §7 (h = 4), falling under gravity onto
   the plane at t = 10: every step converges, the body is in contact from
   t = 10 and leaves the plane moving up. */
static void drop(const char *mesh, int dim, int degree, double rho_inf, double tau, double T) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(mesh, &m));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  const double lambda = 20, mu = 20;
  const double young = mu * (3 * lambda + 2 * mu) / (lambda + mu), nu = lambda / (2 * (lambda + mu));
  double g[3] = {0, 0, 0}, origin[3] = {0, 0, 0}, up[3] = {0, 0, 0};
  g[dim - 1] = -0.1;
  up[dim - 1] = 1;
  ND_OK_OR_FAIL(nd_problem_set_material(p, young, nu, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 1e-3));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_GENERALIZED_ALPHA, &rho_inf));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  double first = -1, last = -1, most_iterations = 0;
  const int steps = (int)lround(T / tau);
  for (int k = 1; k <= steps; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    most_iterations = fmax(most_iterations, scalar(p, ND_NEWTON_ITERATIONS));
    if (scalar(p, ND_ACTIVE_POINTS) > 0) {
      if (first < 0) first = k * tau;
      last = k * tau;
    }
  }
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *v = malloc(sizeof(double) * (size_t)(dim * n)), vz = 0;
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, n, v));
  for (int64_t i = 0; i < n; ++i) vz += v[dim * i + dim - 1] / (double)n;
  free(v);
  printf("%s P%d rho_inf %.1f: contact from t = %.1f to %.1f, at most %.0f Newton iterations a step; mean vertical "
         "velocity at t = %g: %.3f\n",
         mesh + sizeof ND_MESH_DIR, degree, rho_inf, first, last, most_iterations, T, vz);
  ck_assert_double_eq_tol(first, 10.0, 2 * tau);
  ck_assert_double_lt(last, T - 1.0);
  ck_assert_double_gt(vz, 0.0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}

START_TEST(disk_bounces_with_newton_converging) {
  drop(ND_MESH_DIR "/disk_h4.msh", 2, 1, 0.8, 0.2, 32.0);
  drop(ND_MESH_DIR "/disk_h4.msh", 2, 2, 0.5, 0.2, 32.0);
}
END_TEST

START_TEST(ball_bounces_with_newton_converging) {
  drop(ND_MESH_DIR "/ball_h4.msh", 3, 1, 0.8, 0.4, 32.0);
}
END_TEST

int main(void) {
  Suite *s = suite_create("generalized_alpha");
  TCase *tc = tcase_create("generalized_alpha");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, rho_inf_one_is_newmark_without_contact);
  tcase_add_test(tc, disk_bounces_with_newton_converging);
  tcase_add_test(tc, ball_bounces_with_newton_converging);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
