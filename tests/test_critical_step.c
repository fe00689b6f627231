/* The critical time step of explicit Newmark (beta = 0, gamma = 1/2) as the
 * library estimates it (nd_problem_estimate_critical_timestep): runs at 0.9
 * tau_c stay bounded (every step accepted, energy guard on), runs at 1.2
 * tau_c are refused at set-up, and with that guard off they grow until the
 * energy guard stops them. Scenes in contact from the first step, since the
 * contact tangent sets omega_max: the 1D bar (hitting the obstacle at t = 1
 * after a flight, so with Theta = 1 and two penalties also in flight), a 2D
 * block resting on the plane under gravity, and the disk of docs/design.md §7 in free
 * flight: with a contact plane the estimate counts every contact point
 * active, more than a disk touching the plane along a few facets has (it
 * then stays stable at 1.2 tau_c: the estimate is conservative); lumped and
 * consistent mass, P1 and P2. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "testutil.h"

static nd_problem scene(int which, int degree, int lumped, double gamma0) {
  const double cd[2] = {0, 0.5};
  nd_problem p = NULL;
  if (which == 0) {
    p = nd_test_bar(20, degree, ND_SCHEME_NEWMARK, cd, 1.0, gamma0, 1e-3);
  } else {
    nd_mesh m = NULL;
    const double o[2] = {0, 0}, up[2] = {0, 1}, g[2] = {0, -0.1};
    double young = 10, nu = 0.3;
    if (which == 1) {
      const double lo[2] = {0, 0}, hi[2] = {2, 1}, blo[2] = {-1, -1}, bhi[2] = {3, 1e-9};
      ND_OK_OR_FAIL(nd_mesh_create_rectangle(8, 4, lo, hi, &m));
      ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
    } else {
      ND_OK_OR_FAIL(nd_mesh_read_gmsh(ND_MESH_DIR "/disk_h4.msh", &m));
      young = 50, nu = 0.25;
    }
    ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
    ND_OK_OR_FAIL(nd_problem_set_material(p, young, nu, 1.0));
    ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
    if (which == 1) {
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, gamma0));
    }
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, cd));
  }
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
  return p;
}

static const char *names[] = {"bar", "block", "disk"};

START_TEST(runs_below_the_critical_step_are_bounded_above_it_grow) {
  for (int which = 0; which < 3; ++which)
    for (int degree = 1; degree <= 2; ++degree)
      for (int lumped = 0; lumped <= 1; ++lumped) {
        /* the bar with its usual gamma0 (its strain of 1/2 makes the automatic,
           softer one sink past half a cell); the others choose gamma0 */
        const double gamma0 = which == 0 ? 0.2 : 0.0;
        nd_problem p = scene(which, degree, lumped, gamma0);
        double tau_c = 0;
        ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
        const int steps = which == 0 ? (int)ceil(1.5 / (0.9 * tau_c)) : 400; /* the bar: through its impact */
        ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.9 * tau_c));
        double contact_steps = 0;
        for (int k = 0; k < steps; ++k) {
          double active = 0;
          ND_OK_OR_FAIL(nd_step(p));
          ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
          contact_steps += active > 0;
        }
        ck_assert_msg(which == 2 || contact_steps > 0, "%s: never in contact", names[which]);
        ND_OK_OR_FAIL(nd_problem_destroy(&p));

        p = scene(which, degree, lumped, gamma0);
        ND_OK_OR_FAIL(nd_problem_set_timestep(p, 1.2 * tau_c));
        ck_assert_int_eq(nd_problem_setup(p), ND_ERR_UNSTABLE);
        ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0));
        int status = ND_OK, k = 0;
        for (; k < steps && status == ND_OK; ++k) status = nd_step(p);
        printf("%-5s P%d %-10s tau_c = %.4g: 0.9 tau_c ran %d steps; 1.2 tau_c stopped at step %d (%s)\n",
               names[which], degree, lumped ? "lumped" : "consistent", tau_c, steps, k,
               status == ND_OK ? "still running" : nd_strerror(status));
        ck_assert_msg(status == ND_ERR_ENERGY_GROWTH || status == ND_ERR_PENETRATION,
                      "%s P%d lumped %d: 1.2 tau_c ran %d steps, status %d", names[which], degree, lumped, k, status);
        ND_OK_OR_FAIL(nd_problem_destroy(&p));
      }
}
END_TEST

/* a stiffer penalty lowers tau_c like sqrt(gamma0) once it dominates */
START_TEST(tau_c_scales_like_the_square_root_of_gamma0) {
  double tau[3];
  const double gamma0[3] = {1e-3, 1e-4, 1e-5};
  for (int i = 0; i < 3; ++i) {
    nd_problem p = scene(0, 1, 1, gamma0[i]);
    ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau[i]));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  printf("bar P1 lumped: tau_c = %.4g, %.4g, %.4g for gamma0 = 1e-3, 1e-4, 1e-5; ratios %.4f, %.4f (sqrt(10) = %.4f)\n",
         tau[0], tau[1], tau[2], tau[0] / tau[1], tau[1] / tau[2], sqrt(10.0));
  ck_assert_double_eq_tol(tau[1] / tau[2], sqrt(10.0), 0.01);
}
END_TEST

int main(void) {
  Suite *s = suite_create("critical_step");
  TCase *tc = tcase_create("explicit_newmark");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, runs_below_the_critical_step_are_bounded_above_it_grow);
  tcase_add_test(tc, tau_c_scales_like_the_square_root_of_gamma0);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
