/* The critical time step of explicit Newmark (beta = 0, gamma = 1/2) as the
 * library estimates it (nd_problem_estimate_critical_timestep, every contact
 * point active): runs at 0.9 tau_c stay bounded (every step accepted, energy
 * guard on); at 1.2 tau_c a run is refused at set-up when the step is above
 * the free motion's critical step too (no active set can make it stable),
 * else it is stopped by the energy guards once contact makes it grow, their
 * message naming the estimate; with every guard off it grows. Scenes in
 * contact from the first step, since the contact tangent sets omega_max: the
 * 1D bar (hitting the obstacle at t = 1 after a flight, so with Theta = 1 and
 * two penalties also in flight), a 2D block resting on the plane under
 * gravity, and the disk of docs/design.md §7 in free flight (no contact
 * point: refused at set-up); lumped and consistent mass, P1 and P2. And the
 * run the set-up must not refuse: the disk dropped on the plane touches it
 * along a few facets, fewer than the estimate counts, and stays bounded
 * through its impact at 1.05 tau_c (issue 57: refused before). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

        /* 1.2 tau_c with the guards: refused at set-up, or stopped by an
           energy guard that names the estimate */
        p = scene(which, degree, lumped, gamma0);
        ND_OK_OR_FAIL(nd_problem_set_timestep(p, 1.2 * tau_c));
        int status = nd_problem_setup(p), k = 0;
        const int at_setup = status != ND_OK;
        for (; k < steps && status == ND_OK; ++k) status = nd_step(p);
        if (at_setup) ck_assert_int_eq(status, ND_ERR_UNSTABLE);
        else
          ck_assert_msg((status == ND_ERR_ENERGY_GROWTH || status == ND_ERR_PENETRATION) &&
                            strstr(nd_last_error(), "critical step with every contact point active"),
                        "%s P%d lumped %d: 1.2 tau_c ran %d steps, status %d: %s", names[which], degree, lumped, k,
                        status, nd_last_error());
        ck_assert_msg(which != 2 || at_setup, "the free disk at 1.2 tau_c was not refused at set-up");
        printf("%-5s P%d %-10s tau_c = %.4g: 0.9 tau_c ran %d steps; 1.2 tau_c %s at step %d (%s)\n",
               names[which], degree, lumped ? "lumped" : "consistent", tau_c, steps,
               at_setup ? "refused at set-up" : "stopped", k, nd_strerror(status));
        ND_OK_OR_FAIL(nd_problem_destroy(&p));

        /* and without the critical-step guard (the energy guards on) it grows */
        p = scene(which, degree, lumped, gamma0);
        ND_OK_OR_FAIL(nd_problem_set_timestep(p, 1.2 * tau_c));
        ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0));
        status = ND_OK, k = 0;
        for (; k < steps && status == ND_OK; ++k) status = nd_step(p);
        ck_assert_msg(status == ND_ERR_ENERGY_GROWTH || status == ND_ERR_PENETRATION,
                      "%s P%d lumped %d: 1.2 tau_c ran %d steps, status %d", names[which], degree, lumped, k, status);
        ND_OK_OR_FAIL(nd_problem_destroy(&p));
      }
}
END_TEST

/* The disk dropped on the plane at 1.05 tau_c (explicit, lumped, P1 and
   P2): not refused, and through its impact (t = 10) to t = 14 every step is
   accepted, the guards on, with E/(E^0 + W) at most 1.05 (the stability
   suite's judge of a gain, tools/stability/run.py) -- the run at 0.9 tau_c
   printed beside it. */
static double disk_drop(int degree, double fraction, int *contact_steps) {
  nd_problem p = scene(2, degree, 1, 0.0);
  const double o[2] = {0, 0}, up[2] = {0, 1};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  double tau_c = 0, E = 0, E0 = 0, W = 0, active = 0, growth = 0;
  ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, fraction * tau_c));
  ND_OK_OR_FAIL(nd_problem_setup(p));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_MECHANICAL, &E0));
  const int steps = (int)ceil(14 / (fraction * tau_c));
  *contact_steps = 0;
  for (int k = 0; k < steps; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_MECHANICAL, &E));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_WORK, &W));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
    *contact_steps += active > 0;
    growth = fmax(growth, E / (E0 + W));
  }
  printf("disk on the plane P%d at %.2f tau_c: %d steps, %d in contact, max E/(E0 + W) = %.4f\n", degree, fraction,
         steps, *contact_steps, growth);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return growth;
}

START_TEST(a_stable_run_above_the_estimate_is_not_refused) {
  for (int degree = 1; degree <= 2; ++degree) {
    int contact = 0;
    disk_drop(degree, 0.9, &contact);
    const double growth = disk_drop(degree, 1.05, &contact);
    ck_assert_int_gt(contact, 0);
    ck_assert_double_le(growth, 1.05);
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
  tcase_add_test(tc, a_stable_run_above_the_estimate_is_not_refused);
  tcase_add_test(tc, tau_c_scales_like_the_square_root_of_gamma0);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
