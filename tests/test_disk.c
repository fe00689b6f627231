/* The 2D disk of docs/design.md §7 (h = 4 mesh, P1 and P2, hybrid scheme, Theta = 1,
 * gamma0 = 1e-3): falling under gravity, it hits the plane at t = 10, stays in
 * contact and bounces off. Through the whole bounce E_Theta - W must not
 * increase (the hybrid scheme's energy identity with loads, docs/design.md §2), and
 * the disk must leave the obstacle moving up. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

START_TEST(disk_bounces_without_energy_gain) {
  for (int degree = 1; degree <= 2; ++degree) {
    nd_mesh m = NULL;
    nd_problem p = NULL;
    ND_OK_OR_FAIL(nd_mesh_read_gmsh(ND_MESH_DIR "/disk_h4.msh", &m));
    ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
    const double lambda = 20, mu = 20; /* E = mu (3 lambda + 2 mu)/(lambda + mu), nu = lambda/(2(lambda + mu)) */
    const double young = mu * (3 * lambda + 2 * mu) / (lambda + mu), nu = lambda / (2 * (lambda + mu));
    const double g[2] = {0, -0.1}, origin[2] = {0, 0}, up[2] = {0, 1}, tau = 0.1;
    ND_OK_OR_FAIL(nd_problem_set_material(p, young, nu, 1.0));
    ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
    ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 1e-3));
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
    double prev = scalar(p, ND_ENERGY_AUGMENTED) - scalar(p, ND_WORK);
    double first_contact = -1, last_contact = -1;
    const int steps = (int)lround(32.0 / tau);
    for (int k = 1; k <= steps; ++k) {
      ND_OK_OR_FAIL(nd_step(p));
      const double W = scalar(p, ND_WORK), e = scalar(p, ND_ENERGY_AUGMENTED) - W;
      /* round-off: 1e-12 of the energies in play (E_Theta and W reach ~600) */
      const double scale = fabs(scalar(p, ND_ENERGY_AUGMENTED)) + fabs(W);
      ck_assert_msg(e <= prev + 1e-12 * scale, "P%d t = %.1f: E_Theta - W rose by %.3g (scale %.3g)", degree, k * tau,
                    e - prev, scale);
      prev = e;
      if (scalar(p, ND_ACTIVE_POINTS) > 0) {
        if (first_contact < 0) first_contact = k * tau;
        last_contact = k * tau;
      }
    }
    int64_t n = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
    double *v = malloc(sizeof(double) * (size_t)(2 * n)), vy = 0;
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, n, v));
    for (int64_t i = 0; i < n; ++i) vy += v[2 * i + 1] / (double)n;
    free(v);
    printf("P%d: contact from t = %.1f to %.1f; mean vertical velocity at t = 32: %.3f\n", degree, first_contact,
           last_contact, vy);
    /* free fall of 5 under g = 0.1 takes 10; the disk left before T = 32 */
    ck_assert_double_eq_tol(first_contact, 10.0, 2 * tau);
    ck_assert_double_lt(last_contact, 32.0 - 1.0);
    ck_assert_double_gt(vy, 0.0);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("disk");
  TCase *tc = tcase_create("bounce");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, disk_bounces_without_energy_gain);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
