/* Curved and moving obstacles (docs/design.md §10.1) on the 2D disk of
 * docs/design.md §7 (radius 20, centre (0, 25), contact region 1 its lower
 * half, h = 4, P1, gravity 0.1): the plane given as a distance callback is
 * the built-in plane; a circle of radius R tangent to the plane approaches
 * it as 1/R; body and obstacle translating together move as both at rest;
 * a rotating obstacle's work closes the energy ledger; a failed step (a
 * refresh made, or a callback that failed) leaves the problem as it was; a
 * restart is bitwise; a disk resting in a bowl carries its weight. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static const double kH = 4;  /* the mesh size of disk_h4 */
static const double kG = 0.1; /* gravity */

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* the disk (a mesh of examples/meshes, degree) with its material, gravity
   and Nitsche parameters; no obstacle */
static nd_problem disk_of(const char *mesh, int degree, int scheme, const double *params, double tau) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  char path[512];
  snprintf(path, sizeof path, "%s/%s", ND_MESH_DIR, mesh);
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(path, &m));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  const double lambda = 20, mu = 20;
  const double young = mu * (3 * lambda + 2 * mu) / (lambda + mu), nu = lambda / (2 * (lambda + mu));
  const double g[2] = {0, -kG};
  ND_OK_OR_FAIL(nd_problem_set_material(p, young, nu, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 1e-3));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  return p;
}
static nd_problem disk(int scheme, const double *params, double tau) {
  return disk_of("disk_h4.msh", 1, scheme, params, tau);
}

static int64_t nodes(nd_problem p) {
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  return n;
}

static void displacement(nd_problem p, double *u) { ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nodes(p), u)); }

static double max_abs(const double *a, int64_t n) {
  double m = 0;
  for (int64_t i = 0; i < n; ++i) m = fmax(m, fabs(a[i]));
  return m;
}

/* max over `steps` steps of max_i |u_a - u_b| (and of |u_b| in *scale) */
static double trajectory_difference(nd_problem a, nd_problem b, int steps, double *scale) {
  const int64_t n = 2 * nodes(a);
  double *ua = malloc(sizeof(double) * (size_t)n), *ub = malloc(sizeof(double) * (size_t)n), diff = 0;
  *scale = 0;
  for (int k = 0; k < steps; ++k) {
    ND_OK_OR_FAIL(nd_step(a));
    ND_OK_OR_FAIL(nd_step(b));
    displacement(a, ua);
    displacement(b, ub);
    for (int64_t i = 0; i < n; ++i) diff = fmax(diff, fabs(ua[i] - ub[i]));
    *scale = fmax(*scale, max_abs(ub, n));
  }
  free(ua);
  free(ub);
  return diff;
}

/* the plane y = 0 as a signed distance: d = y, nu = (0, 1) */
static int plane_distance(double t, const double *x, double *d, double *nu, void *user) {
  (void)t, (void)user;
  *d = x[1];
  nu[0] = 0, nu[1] = 1;
  return 0;
}

static const double kOrigin[2] = {0, 0}, kUp[2] = {0, 1};

START_TEST(plane_as_callback_is_the_plane) {
  nd_problem a = disk(ND_SCHEME_HYBRID, NULL, 0.1), b = disk(ND_SCHEME_HYBRID, NULL, 0.1);
  ND_OK_OR_FAIL(nd_problem_add_contact_distance(a, 1, plane_distance, NULL));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(b, 1, kOrigin, kUp));
  double scale;
  /* through the impact (t = 10) and the contact, to t = 20 */
  const double diff = trajectory_difference(a, b, 200, &scale);
  printf("plane as a callback: max |u - u_plane| = %.3g (max |u| %.3g) over 200 steps; %g refreshes\n", diff, scale,
         scalar(a, ND_STAT_NORMAL_REFRESHES));
  ck_assert_double_gt(scalar(b, ND_ACTIVE_POINTS) + scalar(a, ND_ACTIVE_POINTS), 0);
  /* the same normals, gaps equal to round-off: round-off amplified by the steps */
  ck_assert_double_le(diff, 1e-10 * scale);
  ck_assert_double_eq(scalar(a, ND_STAT_NORMAL_REFRESHES), 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

START_TEST(circle_approaches_the_plane_as_one_over_r) {
  /* a circle of radius R tangent to y = 0 at the origin, below it: its
     surface and normals differ from the plane's by O(x/R), x <= 20 the
     disk's half-width; the trajectories' difference falls as 1/R */
  double diff[3];
  for (int k = 0; k < 3; ++k) {
    const double R = pow(10.0, 4 + k) * kH, centre[2] = {0, -R};
    nd_problem a = disk(ND_SCHEME_HYBRID, NULL, 0.1), b = disk(ND_SCHEME_HYBRID, NULL, 0.1);
    ND_OK_OR_FAIL(nd_problem_add_contact_sphere(a, 1, centre, R, 0));
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(b, 1, kOrigin, kUp));
    double scale;
    diff[k] = trajectory_difference(a, b, 200, &scale);
    printf("circle R = 1e%d h: max |u - u_plane| = %.4g (max |u| %.3g)\n", 4 + k, diff[k], scale);
    ND_OK_OR_FAIL(nd_problem_destroy(&a));
    ND_OK_OR_FAIL(nd_problem_destroy(&b));
  }
  /* the leading term is 1/R, the next (x/R)^2 relative to it, x/R <= 5e-4:
     each tenfold radius divides the difference by 10 to well within 10% */
  for (int k = 0; k < 2; ++k) {
    const double ratio = diff[k] / diff[k + 1];
    printf("ratio R = 1e%d h / 1e%d h: %.4f\n", 4 + k, 5 + k, ratio);
    ck_assert_double_ge(ratio, 9);
    ck_assert_double_le(ratio, 11);
  }
}
END_TEST

START_TEST(galilean_invariance) {
  /* the ball of docs/design.md §7 (radius 20, centre (0, 0, 25), region 1
     its lower half; h = 4, P1) falls onto a horizontal cylinder of radius 40
     (axis x, top at z = 0); body and cylinder translating together along
     the axis at vx, vs both at rest: the relative motion is the same (a
     rigid translation has no strain; the cylinder's normals and distances
     do not depend on x): to round-off. _i = 1: the ball in hexahedra
     (ball_hex_h4), Q1 */
  const double vx = 0.5, tau = 0.1, point[3] = {0, 0, -40}, axis[3] = {1, 0, 0}, g[3] = {0, 0, -kG};
  const double down[3] = {0, 0, -1};
  nd_problem q[2];
  for (int k = 0; k < 2; ++k) {
    nd_mesh m = NULL;
    ND_OK_OR_FAIL(nd_mesh_read_gmsh(_i ? ND_MESH_DIR "/ball_hex_h4.msh" : ND_MESH_DIR "/ball_h4.msh", &m));
    ND_OK_OR_FAIL(nd_problem_create(m, 1, &q[k]));
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
    ND_OK_OR_FAIL(nd_problem_set_material(q[k], 100, 0.25, 1.0));
    ND_OK_OR_FAIL(nd_problem_set_body_force(q[k], g));
    ND_OK_OR_FAIL(nd_problem_set_nitsche(q[k], 1.0, 0));
    ND_OK_OR_FAIL(nd_problem_set_scheme(q[k], ND_SCHEME_HYBRID, NULL));
    ND_OK_OR_FAIL(nd_problem_set_timestep(q[k], tau));
    ND_OK_OR_FAIL(nd_problem_add_contact_cylinder(q[k], 1, point, axis, 40, 0));
  }
  nd_problem a = q[0], b = q[1];
  const int64_t n = nodes(a);
  double *v0 = calloc((size_t)(3 * n), sizeof(double)), *ua = malloc(sizeof(double) * (size_t)(3 * n)),
         *ub = malloc(sizeof(double) * (size_t)(3 * n));
  for (int64_t i = 0; i < n; ++i) v0[3 * i] = vx, v0[3 * i + 2] = -1; /* (falling: the impact at t ~ 4.6) */
  ND_OK_OR_FAIL(nd_problem_set_initial_state(a, n, NULL, v0));
  {
    double *w = malloc(sizeof(double) * (size_t)(3 * n));
    for (int64_t i = 0; i < n; ++i) memcpy(&w[3 * i], down, sizeof down);
    ND_OK_OR_FAIL(nd_problem_set_initial_state(b, n, NULL, w));
    free(w);
  }
  /* (the obstacle as added is where it is at t^0; each call places it at t^{n+1}) */
  double diff = 0, scale = 0, active = 0;
  for (int k = 1; k <= 80; ++k) {
    const double shift[3] = {vx * k * tau, 0, 0};
    ND_OK_OR_FAIL(nd_problem_move_obstacle(a, 1, 0, shift, NULL));
    ND_OK_OR_FAIL(nd_step(a));
    ND_OK_OR_FAIL(nd_step(b));
    ND_OK_OR_FAIL(nd_get_field(a, ND_FIELD_DISPLACEMENT, n, ua));
    ND_OK_OR_FAIL(nd_get_field(b, ND_FIELD_DISPLACEMENT, n, ub));
    const double t = scalar(a, ND_TIME);
    for (int64_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) {
        diff = fmax(diff, fabs(ua[3 * i + c] - (c == 0 ? vx * t : 0) - ub[3 * i + c]));
        scale = fmax(scale, fabs(ua[3 * i + c]));
      }
    active = fmax(active, scalar(b, ND_ACTIVE_POINTS));
  }
  printf("Galilean (ball of %s on a cylinder, along its axis): max |(u - vx t) - u_rest| = %.3g (max |u| %.3g), "
         "%g and %g refreshes, up to %g active points\n",
         _i ? "hexahedra" : "tetrahedra", diff, scale, scalar(a, ND_STAT_NORMAL_REFRESHES),
         scalar(b, ND_STAT_NORMAL_REFRESHES), active);
  fflush(stdout);
  ck_assert_double_gt(active, 0);
  ck_assert_double_gt(scalar(b, ND_STAT_NORMAL_REFRESHES), 0);
  /* round-off: K times the translation vx t is not exactly zero */
  ck_assert_double_le(diff, 1e-10 * scale);
  free(v0), free(ua), free(ub);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

START_TEST(rotating_obstacle_work_closes_the_ledger) {
  /* a circle of radius 40 below the disk, turning about the origin at
     omega: its centre swings sideways and pushes the disk. Hybrid, Theta =
     1: E_Theta - W - W_obstacle - W_geometry does not increase at any step,
     those that refresh the normals included (docs/design.md §10.1: the
     re-linearisations' change of E_Theta at U^n is W_geometry). _i: 0 the
     triangles, P1; 1, 2 the disk in quadrilaterals (disk_quad_h4), Q1, Q2 */
  const double tau = 0.1, omega = 0.01, centre[2] = {0, -40}, zero[2] = {0, 0};
  nd_problem p = disk_of(_i ? "disk_quad_h4.msh" : "disk_h4.msh", _i ? _i : 1, ND_SCHEME_HYBRID, NULL, tau);
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(p, 1, centre, 40, 0));
  double prev = scalar(p, ND_ENERGY_AUGMENTED) - scalar(p, ND_WORK) - scalar(p, ND_WORK_OBSTACLE), worst = 0;
  double refresh_jumps = 0, refresh_steps = 0; /* W_geometry's part at the steps that refreshed normals */
  ck_assert_double_eq(scalar(p, ND_WORK_GEOMETRY), 0);
  for (int k = 1; k <= 300; ++k) {
    const double a = omega * k * tau, R[4] = {cos(a), -sin(a), sin(a), cos(a)};
    ND_OK_OR_FAIL(nd_problem_move_obstacle(p, 1, 0, zero, R));
    const double refreshes = scalar(p, ND_STAT_NORMAL_REFRESHES), Wg = scalar(p, ND_WORK_GEOMETRY);
    ND_OK_OR_FAIL(nd_step(p));
    const double W = scalar(p, ND_WORK), Wo = scalar(p, ND_WORK_OBSTACLE), E = scalar(p, ND_ENERGY_AUGMENTED);
    const double e = E - W - Wo - scalar(p, ND_WORK_GEOMETRY), scale = fabs(E) + fabs(W) + fabs(Wo);
    if (scalar(p, ND_STAT_NORMAL_REFRESHES) > refreshes) refresh_jumps += fabs(scalar(p, ND_WORK_GEOMETRY) - Wg), ++refresh_steps;
    worst = fmax(worst, (e - prev) / scale);
    ck_assert_msg(e <= prev + 1e-12 * scale, "t = %.1f: E_Theta - W - W_obstacle - W_geometry rose by %.3g (scale %.3g)",
                  k * tau, e - prev, scale);
    prev = e;
  }
  printf("rotating circle (%s%d): W_obstacle = %.6g, W = %.6g, W_geometry = %.3g, largest relative rise %.3g; %g "
         "refreshes in %g steps, W_geometry changed by %.3g there\n",
         _i ? "Q" : "P", _i ? _i : 1, scalar(p, ND_WORK_OBSTACLE), scalar(p, ND_WORK), scalar(p, ND_WORK_GEOMETRY), worst,
         scalar(p, ND_STAT_NORMAL_REFRESHES), refresh_steps, refresh_jumps);
  ck_assert_double_ne(scalar(p, ND_WORK_OBSTACLE), 0);
  ck_assert_double_gt(refresh_steps, 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* ---- failures and restarts */


START_TEST(failed_step_after_a_refresh_keeps_the_problem) {
  /* one Newton iteration allowed: contact steps fail, some after their
     refresh made the operators again; each leaves the problem as it was,
     and the run, continued with the default limit for that step, is
     bitwise the run that never failed */
  const double centre[2] = {0, -40}, zero[2] = {0, 0};
  nd_problem p = disk(ND_SCHEME_HYBRID, NULL, 0.1), ref = disk(ND_SCHEME_HYBRID, NULL, 0.1);
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(p, 1, centre, 40, 0));
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(ref, 1, centre, 40, 0));
  int failures = 0, after_refresh = 0;
  for (int k = 0; k < 250; ++k) {
    /* the circle turning about the origin (rotating_obstacle_work_closes_the_ledger) */
    const double ang = 0.01 * (k + 1) * 0.1, R[4] = {cos(ang), -sin(ang), sin(ang), cos(ang)};
    ND_OK_OR_FAIL(nd_problem_move_obstacle(p, 1, 0, zero, R));
    ND_OK_OR_FAIL(nd_problem_move_obstacle(ref, 1, 0, zero, R));
    const int failed = nd_test_step_failing_once(p, ref, 2, k);
    failures += failed > 0, after_refresh += failed == 2;
  }
  printf("failed steps: %d, of which %d after a refresh\n", failures, after_refresh);
  ck_assert_int_gt(after_refresh, 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&ref));
}
END_TEST

/* a circle of radius 40 below, as a callback that fails at a given time */
typedef struct {
  double fail_at;
  int mode; /* 0 return 1, 1 NaN distance, 2 normal of length 2 */
} failing;

static int failing_circle(double t, const double *x, double *d, double *nu, void *user) {
  const failing *f = user;
  const double dx = x[0], dy = x[1] + 40, r = sqrt(dx * dx + dy * dy);
  *d = r - 40;
  nu[0] = dx / r, nu[1] = dy / r;
  if (t >= f->fail_at) {
    if (f->mode == 0) return 1;
    if (f->mode == 1) *d = NAN;
    if (f->mode == 2) nu[0] *= 2, nu[1] *= 2;
  }
  return 0;
}

START_TEST(callback_failure_fails_the_step) {
  const int expected[3] = {ND_ERR_CALLBACK, ND_ERR_NONFINITE, ND_ERR_VALUE};
  for (int mode = 0; mode < 3; ++mode) {
    failing f = {10.5, mode};
    nd_problem p = disk(ND_SCHEME_HYBRID, NULL, 0.1);
    ND_OK_OR_FAIL(nd_problem_add_contact_distance(p, 1, failing_circle, &f));
    int k = 0;
    for (; k < 200 && nd_step(p) == ND_OK; ++k) {
    }
    nd_test_snapshot before = nd_test_take(p, 2);
    const int status = nd_step(p);
    ck_assert_int_eq(status, expected[mode]);
    ck_assert_ptr_nonnull(strstr(nd_last_error(), "distance callback"));
    printf("callback mode %d: %s\n", mode, nd_last_error());
    nd_test_snapshot after = nd_test_take(p, 2);
    ck_assert(nd_test_same(&before, &after));
    free(before.fields), free(after.fields);
    f.fail_at = 1e9; /* the callback works again: the run goes on */
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

START_TEST(restart_is_bitwise) {
  /* a checkpoint in the middle of the contact (refreshes before and
     after) resumes bitwise: the frozen normals and the obstacle's place at
     t^n are in it */
  const double centre[2] = {0, -40};
  nd_problem a = disk(ND_SCHEME_HYBRID, NULL, 0.1);
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(a, 1, centre, 40, 0));
  unsigned char *saved = NULL;
  int64_t size = 0;
  const int steps = 160, at = 115;
  double refreshes_at = 0;
  for (int k = 1; k <= steps; ++k) {
    const double shift[2] = {0.01 * k * 0.1, 0};
    ND_OK_OR_FAIL(nd_problem_move_obstacle(a, 1, 0, shift, NULL));
    ND_OK_OR_FAIL(nd_step(a));
    if (k == at) saved = nd_test_checkpoint(a, &size), refreshes_at = scalar(a, ND_STAT_NORMAL_REFRESHES);
  }
  ck_assert_double_gt(refreshes_at, 0);
  ck_assert_double_gt(scalar(a, ND_STAT_NORMAL_REFRESHES), refreshes_at);
  nd_problem b = disk(ND_SCHEME_HYBRID, NULL, 0.1);
  ND_OK_OR_FAIL(nd_problem_add_contact_sphere(b, 1, centre, 40, 0));
  ND_OK_OR_FAIL(nd_problem_load_state(b, size, saved));
  for (int k = at + 1; k <= steps; ++k) {
    const double shift[2] = {0.01 * k * 0.1, 0};
    ND_OK_OR_FAIL(nd_problem_move_obstacle(b, 1, 0, shift, NULL));
    ND_OK_OR_FAIL(nd_step(b));
  }
  nd_test_snapshot sa = nd_test_take(a, 2), sb = nd_test_take(b, 2);
  /* the scalars up to the work (the counters differ: b did less work) */
  ck_assert(memcmp(sa.fields, sb.fields, sizeof(double) * (size_t)(3 * sa.n)) == 0);
  for (int k = 0; k < ND_WORK_OBSTACLE; ++k)
    ck_assert_msg(memcmp(&sa.scalars[k], &sb.scalars[k], sizeof(double)) == 0, "scalar %d: %.17g vs %.17g", k + 1,
                  sa.scalars[k], sb.scalars[k]);
  free(sa.fields), free(sb.fields), free(saved);
  /* a problem without the obstacle refuses the checkpoint */
  nd_problem c = disk(ND_SCHEME_HYBRID, NULL, 0.1);
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(c, 1, kOrigin, kUp));
  saved = nd_test_checkpoint(a, &size);
  ck_assert_int_eq(nd_problem_load_state(c, size, saved), ND_ERR_STATE);
  free(saved);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
  ND_OK_OR_FAIL(nd_problem_destroy(&c));
}
END_TEST

/* the vertical and horizontal resultants of the nodal contact force */
static void resultant(nd_problem p, double *fx, double *fy) {
  const int64_t n = nodes(p);
  double *f = malloc(sizeof(double) * (size_t)(2 * n));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_CONTACT_FORCE, n, f));
  *fx = *fy = 0;
  for (int64_t i = 0; i < n; ++i) *fx += f[2 * i], *fy += f[2 * i + 1];
  free(f);
}

START_TEST(disk_in_a_bowl_carries_its_weight) {
  /* The disk (bottom at y = 5) dropped 0.5 onto the plane y = 4.5 and into
     a circular bowl of radius 30.5 (bottom at y = 4.5), implicit Euler
     (theta = 1). Each step's rows summed, K's and s_q's vanishing on a
     rigid translation: (Pi^{n+1} - Pi^n)/tau = -weight + f^{n+1}, Pi the
     momentum and f the contact resultant, so over T = N tau
       mean_n f^n - weight = Pi^N / T,  |Pi^N| <= mass max|v^N| = weight max|v^N| / g.
     On the plane the disk comes to rest (f = weight to round-off: the weight);
     in the bowl, whose frozen normals lag the sliding disk by up to delta
     (docs/design.md §10.1), it keeps a small sliding oscillation: the identity
     holds for the means, to the bound. */
  const double theta = 1, tau = 2, centre[2] = {0, 35}, low[2] = {0, 4.5};
  const int steps = 1500;
  double mean[2][2], vmax[2];
  for (int k = 0; k < 2; ++k) {
    nd_problem p = disk(ND_SCHEME_THETA, &theta, tau);
    if (k == 0) ND_OK_OR_FAIL(nd_problem_add_contact_sphere(p, 1, centre, 30.5, 1));
    else ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, low, kUp));
    mean[k][0] = mean[k][1] = 0;
    for (int s = 0; s < steps; ++s) {
      ND_OK_OR_FAIL(nd_step(p));
      double fx, fy;
      resultant(p, &fx, &fy);
      mean[k][0] += fx / steps, mean[k][1] += fy / steps;
    }
    const int64_t n = nodes(p);
    double *v = malloc(sizeof(double) * (size_t)(2 * n));
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, n, v));
    vmax[k] = max_abs(v, 2 * n);
    double fx, fy;
    resultant(p, &fx, &fy);
    printf("%s: mean contact resultant (%.12g, %.12g), last (%.6g, %.12g), max |v| %.3g, %g refreshes\n",
           k ? "plane" : "bowl", mean[k][0], mean[k][1], fx, fy, vmax[k], scalar(p, ND_STAT_NORMAL_REFRESHES));
    fflush(stdout);
    if (k == 1) ck_assert_double_le(fabs(fy - mean[1][1]), 1e-9 * fy);  /* at rest */
    free(v);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  const double weight = mean[1][1], T = steps * tau, bound = weight * vmax[0] / (kG * T);
  printf("bowl: |mean - weight| = (%.3g, %.3g), bound %.3g\n", fabs(mean[0][0]), fabs(mean[0][1] - weight), bound);
  /* (1e-9: the plane's own mean, its first steps off rest) */
  ck_assert_double_le(fabs(mean[0][1] - weight), bound + 1e-9 * weight);
  ck_assert_double_le(fabs(mean[0][0]), bound + 1e-9 * weight);
}
END_TEST

int main(void) {
  Suite *s = suite_create("obstacles");
  TCase *tc = tcase_create("obstacles");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, plane_as_callback_is_the_plane);
  tcase_add_test(tc, circle_approaches_the_plane_as_one_over_r);
  tcase_add_loop_test(tc, galilean_invariance, 0, 2);
  tcase_add_loop_test(tc, rotating_obstacle_work_closes_the_ledger, 0, 3);
  tcase_add_test(tc, failed_step_after_a_refresh_keeps_the_problem);
  tcase_add_test(tc, callback_failure_fails_the_step);
  tcase_add_test(tc, restart_is_bitwise);
  tcase_add_test(tc, disk_in_a_bowl_carries_its_weight);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
