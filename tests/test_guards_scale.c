/* The guards during stepping that measure the run against its own scale
 * (docs/design.md §3b, issue 57):
 *  - the penetration guard, u_n - g0 <= f eps* min(h_K, L/8) with eps* =
 *    sqrt(2 E_in / int E dx) the strain of the energy put in and L =
 *    |Omega|/|Gamma_C|: a block whose penalty is too weak to stop it
 *    (Theta = 0, gamma0 E = 1e4) is refused once it has sunk f eps* L/8 =
 *    4 (1/2) (1/8) = 1/4, half its elastic motion eps* L = 1/2 (the old
 *    absolute limit h_K/2 = 0.177 came earlier here, but not at a smaller
 *    speed: 1e-3 of it sinks a thousand times its motion first); the same run in other
 *    units (lengths x 1e-3, times x 10, masses x 1e6), and at 1e-3 of the
 *    speed with 1e-3 of the gap (the problem is positively homogeneous), is
 *    refused at the same step; the bar of §7 with every default runs 1e5
 *    steps without a refusal (the old limit stopped it at step 17,634);
 *  - the energy-balance guard, E_Theta - W - ... + D against its lowest value
 *    out of contact: Theta = -1 with gamma0 at half the bound gamma0* (the
 *    automatic value of Theta = 1, and of every Theta before issue 57)
 *    gains energy at the impact of the block (refused, the message names
 *    Theta = -1; with the guard off the same run ends with more energy than
 *    it started with); Theta = -1 with its own automatic gamma0 (1/50 of gamma0*
 *    with the hybrid scheme) and Theta = 1 complete;
 *  - a moving obstacle's approach over the step: a resting block that a
 *    rising plane reaches with generalized-alpha is inside it before any
 *    force acted, with no energy put in (a limit of 0): it runs on, and a
 *    penalty too weak to stop it is still refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* The block of the stability suite: 16 x 4 cells on [0, 4] x [g, 1 + g] (g =
   0.05 a), falling at 0.5 a onto the plane y = 0, E = rho = 1, nu = 0.3,
   hybrid scheme, tau = 0.02, in units where lengths are `length` times,
   times `time` times and masses `mass` times those (plane strain: per unit
   thickness, itself a length) */
static nd_problem block(double theta, double gamma0E, double a, double length, double time, double mass) {
  const double g = 0.05 * a;
  const double lo[2] = {0, g * length}, hi[2] = {4 * length, (1 + g) * length};
  const double blo[2] = {-length, 0}, bhi[2] = {5 * length, g * length};
  const double origin[2] = {0, 0}, up[2] = {0, 1};
  const double stress = mass / (length * time * time); /* E's unit */
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(16, 4, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, stress, 0.3, mass / (length * length * length)));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, gamma0E / stress));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.02 * time));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *v0 = calloc((size_t)(2 * n), sizeof(double));
  for (int64_t i = 0; i < n; ++i) v0[2 * i + 1] = -0.5 * a * length / time;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v0));
  free(v0);
  return p;
}

/* steps until a refusal (its code in *code) or `steps`; the deepest
   penetration of the last accepted state in *last_pen */
static int64_t run(nd_problem p, int64_t steps, int *code, double *last_pen) {
  *code = ND_OK;
  *last_pen = 0;
  for (int64_t k = 1; k <= steps; ++k) {
    const int st = nd_step(p);
    if (st != ND_OK) {
      *code = st;
      return k;
    }
    *last_pen = scalar(p, ND_MAX_PENETRATION);
  }
  return steps + 1;
}

START_TEST(a_sinking_block_is_refused_early) {
  nd_problem p = block(0.0, 1e4, 1.0, 1.0, 1.0, 1.0);
  int code;
  double pen;
  const int64_t k = run(p, 200, &code, &pen);
  printf("refused at step %lld: %s\n", (long long)k, nd_last_error());
  ck_assert_int_eq(code, ND_ERR_PENETRATION);
  /* eps* = sqrt(2 E0 / (E |Omega|)) = sqrt(2 (1/2)(4)(1/4) / 4) = 1/2, L = 4/4:
     the limit 4 (1/2)(1/8) = 1/4, half the motion eps* L */
  ck_assert(pen <= 0.25);
  ck_assert(pen > 0.25 - 0.5 * 0.02); /* within a step's fall of it (the body sinks at <= 1/2) */
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(the_verdict_does_not_depend_on_the_units) {
  int code0, code;
  double pen0, pen;
  nd_problem p = block(0.0, 1e4, 1.0, 1.0, 1.0, 1.0);
  const int64_t k0 = run(p, 200, &code0, &pen0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ck_assert_int_eq(code0, ND_ERR_PENETRATION);
  /* other units: every displacement scales with the length unit */
  p = block(0.0, 1e4, 1.0, 1e-3, 10.0, 1e6);
  const int64_t k1 = run(p, 200, &code, &pen);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ck_assert_int_eq(code, code0);
  ck_assert_int_eq(k1, k0);
  ck_assert(fabs(pen / 1e-3 - pen0) <= 1e-9 * pen0);
  /* 1e-3 of the speed and of the gap: the same motion at 1e-3 of its size
     (the absolute limit h_K/2 accepted it: it never sinks 0.177) */
  p = block(0.0, 1e4, 1e-3, 1.0, 1.0, 1.0);
  const int64_t k2 = run(p, 200, &code, &pen);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ck_assert_int_eq(code, code0);
  ck_assert_int_eq(k2, k0);
  ck_assert(fabs(pen / 1e-3 - pen0) <= 1e-9 * pen0);
}
END_TEST

START_TEST(the_reference_bar_runs_1e5_steps) {
  /* docs/design.md §7 with every default: Theta = 1, the automatic gamma0,
     the hybrid scheme, tau = h/2; energy at round-off all along */
  nd_problem p = nd_test_bar(40, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.0, 1.0 / 80);
  const double E0 = scalar(p, ND_ENERGY_AUGMENTED);
  double prev = E0, deepest = 0;
  for (int k = 1; k <= 100000; ++k) {
    const int st = nd_step(p);
    ck_assert_msg(st == ND_OK, "step %d: %s", k, nd_last_error());
    const double E = scalar(p, ND_ENERGY_AUGMENTED);
    ck_assert(E <= prev + 1e-13 * E0); /* E_Theta never rises (part 2 of the paper) */
    prev = E;
    deepest = fmax(deepest, scalar(p, ND_MAX_PENETRATION));
  }
  /* past the old absolute limit h_K/2 = 1/80, within the new one 4 eps* h_K = 2 h_K */
  printf("deepest penetration over 1e5 steps: %g h_K\n", deepest * 40);
  ck_assert(deepest > 0.5 / 40);
  ck_assert(deepest <= 2.0 / 40);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(theta_minus_one_gaining_energy_is_refused) {
  int code;
  double pen;
  /* half the bound: Theta = 1's automatic gamma0 (E = 1: gamma0 E = gamma0) */
  nd_problem p = block(1.0, 0.0, 1.0, 1.0, 1.0, 1.0);
  const double half = scalar(p, ND_GAMMA0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  p = block(-1.0, half, 1.0, 1.0, 1.0, 1.0);
  const int64_t k = run(p, 200, &code, &pen);
  printf("refused at step %lld: %s\n", (long long)k, nd_last_error());
  ck_assert_int_eq(code, ND_ERR_ENERGY_GROWTH);
  ck_assert(strstr(nd_last_error(), "Theta = -1 gains energy at impacts") != NULL);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  /* the refusal is justified: without the guard the block leaves the
     obstacle with more energy than it came with (no load: E_Theta - W is E_Theta) */
  p = block(-1.0, half, 1.0, 1.0, 1.0, 1.0);
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0));
  const double E0 = scalar(p, ND_ENERGY_MECHANICAL);
  double top = 0;
  for (int i = 0; i < 200; ++i) {
    ND_OK_OR_FAIL(nd_step(p));
    if (scalar(p, ND_ACTIVE_POINTS) == 0) top = fmax(top, scalar(p, ND_ENERGY_AUGMENTED));
  }
  printf("Theta = -1 without the balance guard: E_Theta out of contact up to %g E0\n", top / E0);
  ck_assert(top > 1.05 * E0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  /* Theta = 1: the hybrid scheme never gains; Theta = -1 with its own
     automatic gamma0 (docs/design.md §3b.1) runs through the impact */
  for (int t = 0; t < 2; ++t) {
    p = block(t == 0 ? 1.0 : -1.0, 0.0, 1.0, 1.0, 1.0, 1.0);
    const int64_t k1 = run(p, 200, &code, &pen);
    ck_assert_msg(code == ND_OK, "Theta = %d, step %lld: %s", t == 0 ? 1 : -1, (long long)k1, nd_last_error());
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* The block at rest, generalized-alpha (rho_inf = 0.8), the plane y = d(t) rising into it
   at 0.5 from below (moved before each step, as the stability suite does).
   Its first contact step applies the law at the scheme's shifted point,
   where P <= 0 yet: no force, no work, no energy put in, while the plane
   has come up into the block by part of its approach over the step. */
static char refusal[1024];
static int64_t pushed(double theta, double gamma0E, double tau, int64_t steps, int *code, double *first_pen,
                      double *first_force) {
  nd_problem p = block(theta, gamma0E, 1.0, 1.0, 1.0, 1.0);
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, NULL));
  const double rho_inf = 0.8;
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_GENERALIZED_ALPHA, &rho_inf));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  const double up[2] = {0, 1};
  *code = ND_OK, *first_pen = -1, *first_force = -1;
  for (int64_t k = 1; k <= steps; ++k) {
    const double plane[2] = {0, 0.5 * (double)k * tau};
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, plane, up));
    const int st = nd_step(p);
    if (st != ND_OK) {
      *code = st;
      snprintf(refusal, sizeof refusal, "%s", nd_last_error());
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      return k;
    }
    const double pen = scalar(p, ND_MAX_PENETRATION);
    if (*first_pen < 0 && pen > 0) *first_pen = pen, *first_force = scalar(p, ND_CONTACT_FORCE_APPLIED);
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return steps + 1;
}

START_TEST(a_plane_reaching_a_resting_block_is_no_sinking) {
  /* the stability suite's false alarm (rect, galpha, Theta = 1, gamma0 E =
     2.57e-4, tau = 0.0233 of the scene's): the plane reaches the block in
     step 215, whose state lies 9.5e-5 inside the plane (3.7e-8 m in the
     suite's steel units) with no energy put in; the guard refused it (a limit of 4 eps* l = 0). A point may sink by
     the obstacle's approach over the step besides (docs/design.md §3b.5) */
  const double tau = 0.0233 * 0.02;
  int code;
  double first, force;
  const int64_t k = pushed(1.0, 2.57e-4, tau, 400, &code, &first, &force);
  ck_assert_msg(code == ND_OK, "refused at step %lld: %s", (long long)k, refusal);
  printf("pushed block: first penetration %g (the approach 0.5 tau = %g), force applied %g\n", first, 0.5 * tau,
         force);
  ck_assert(first > 0 && first <= 0.5 * tau); /* the first contact: the plane's own approach, no more */
  ck_assert(force == 0);                      /* the case: inside before any force acted */
  /* the allowance is one step's approach: a penalty too weak to stop the
     block (Theta = 0, gamma0 E = 1e4) lets it sink step after step, and is
     still refused for it */
  pushed(0.0, 1e4, 0.02, 200, &code, &first, &force);
  printf("weak penalty: %s\n", refusal);
  ck_assert_int_eq(code, ND_ERR_PENETRATION);
}
END_TEST

int main(void) {
  Suite *s = suite_create("guards_scale");
  TCase *tc = tcase_create("during_the_steps");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, a_sinking_block_is_refused_early);
  tcase_add_test(tc, the_verdict_does_not_depend_on_the_units);
  tcase_add_test(tc, the_reference_bar_runs_1e5_steps);
  tcase_add_test(tc, theta_minus_one_gaining_energy_is_refused);
  tcase_add_test(tc, a_plane_reaching_a_resting_block_is_no_sinking);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
