/* stability_case - one run of the stability suite (tools/stability/run.py):
 * a scene, a degree, a scheme, Theta and gamma0 E, marched with the library's
 * default guards, and judged independently of them. Prints one CSV row:
 *
 *   scene,degree,scheme,Theta,gamma0E,tau,steps_planned,outcome,code,step,
 *   energy_growth,max_penetration_over_h,late,newton_per_step,wall_s,theory,message
 *
 * outcome: completed | refused_at_setup | stopped_at_step | silent_failure.
 * A run is a silent failure when every call returned ND_OK although, by this
 * program's own measurement, the mechanical energy passed 2 (E^0 + max_k W^k)
 * (the guard's default factor), became non-finite, or a contact point sank
 * deeper than 4 eps* min(h, L/8), eps* = sqrt(2 (E^0 + max_k W^k) / int E dx)
 * the strain of the energy put in and L = |Omega| / |Gamma_C| (the
 * penetration guard's default, docs/design.md §3b.5, measured here from the
 * scene's own dimensions): what the guards exist to catch. late: the
 * steps accepted past those limits before a guard stopped the run.
 * theory: for the hybrid scheme with Theta = 1, whether E_Theta + D - W never
 * increased (part 2 of the paper; D the damping's dissipation), else "-".
 *
 * With a 7th argument `unguarded` the run is made again with the guards that
 * act during the steps off (energy, energy balance, penetration; the set-up's
 * checks stay) to judge a refusal, and prints instead
 *
 *   outcome,code,step,energy_growth,balance_gain,penetration_ratio
 *
 * balance_gain: the largest rise of the balance L = E_Theta - W - W_obstacle
 * - W_prescribed - W_geometry + D_damping + D_friction at a state without
 * an active point above its lowest value at such a state before (t^0
 * included), relative to the largest of E^0 + max W and max E; and
 * penetration_ratio the deepest point over eps* min(h, L/8). run.py calls a
 * refusal justified when the unguarded run then fails (a non-finite state,
 * Newton), gains (energy_growth > 1.05 or balance_gain > 0.05) or sinks
 * (penetration_ratio > 4), and a false alarm otherwise.
 *
 * With `adaptive` instead, the run is made again with the guards on and
 * adaptive time steps (nd_problem_set_adaptive_timestep: tolerance 1e-2,
 * tau_min = 1e-4 tau, tau_max = tau) to T (within 20 times the fixed
 * steps), to see whether a step size the
 * library chooses mends a failure of the fixed step (Newton), and prints
 *
 *   outcome,code,steps,rejected
 *
 * outcome as above (a completed run past the limits: silent_failure).
 *
 * usage: stability_case SCENE DEGREE SCHEME THETA GAMMA0E MESH_DIR [unguarded|adaptive]
 *   SCENE   bar | rect | disk       SCHEME  hybrid | newmark | theta1 | explicit | galpha,
 *   each with the suffixes (any of them, in this order) _damped for Rayleigh
 *   damping alpha = 0.05, beta = 0.1 tau (damping ratio about 0.1 at the
 *   highest frequency the step resolves), _friction for Coulomb friction F =
 *   0.3 on the contact region (2D), _layered for two materials: the half of
 *   the bar's or the rectangle's cells at the obstacle 4 times as stiff and
 *   twice as dense.
 *   The energies then count D_f with D (ND_DISSIPATION_FRICTION). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "nitschedyn.h"
#include "step_count.h"

static double get(nd_problem p, int key) {
  double x = NAN;
  nd_get_scalar(p, key, &x);
  return x;
}

static const char *code_name(int code) {
#define ND_NAME_CASE_(name, value, text) \
  case name:                             \
    return #name;
  switch (code) { ND_STATUS_LIST(ND_NAME_CASE_) }
#undef ND_NAME_CASE_
  return "unknown";
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv) {
  if (argc != 7 && !(argc == 8 && (!strcmp(argv[7], "unguarded") || !strcmp(argv[7], "adaptive")))) {
    fprintf(stderr, "usage: %s SCENE DEGREE SCHEME THETA GAMMA0E MESH_DIR [unguarded|adaptive]\n", argv[0]);
    return 2;
  }
  const int unguarded = argc == 8 && !strcmp(argv[7], "unguarded");
  const char *scene = argv[1], *scheme_arg = argv[3];
  char scheme_name[32];
  snprintf(scheme_name, sizeof scheme_name, "%s", scheme_arg);
  /* the suffixes, cut off the scheme's name */
  int damped = 0, friction = 0, layered = 0;
  struct {
    const char *name;
    int *flag;
  } suffixes[] = {{"_layered", &layered}, {"_friction", &friction}, {"_damped", &damped}};
  for (size_t k = 0; k < sizeof suffixes / sizeof suffixes[0]; ++k) {
    char *at = strstr(scheme_name, suffixes[k].name);
    if (at) *suffixes[k].flag = 1, *at = '\0';
  }
  const int degree = atoi(argv[2]);
  const double Theta = atof(argv[4]), gamma0E = atof(argv[5]);
  nd_mesh m = NULL;
  nd_problem p = NULL;
  double E = 1, nu = 0.3, h = 0, tau = 0, T = 0;
  /* |Omega| and |Gamma_C| (the body's length across its contact region L
     is their ratio), for the penetration criterion */
  double volume = 0, contact_area = 0;
  int st = ND_OK;
  double g[3] = {0, 0, 0}, origin[3] = {0, 0, 0}, up[3] = {0, 0, 0};
  if (!strcmp(scene, "bar")) { /* docs/design.md §7: clamped at x = 1, u0 = (1-x)/2 */
    const double lo[2] = {-0.5, 0.5}, hi[2] = {0.5, 1.5};
    h = 1.0 / 40, tau = h / 2, T = 6;
    volume = 1, contact_area = 1;
    st = nd_mesh_create_interval(40, 0, 1, &m);
    if (!st) st = nd_mesh_mark_boundary_box(m, 1, &lo[0], &hi[0]);
    if (!st) st = nd_mesh_mark_boundary_box(m, 2, &lo[1], &hi[1]);
    up[0] = 1;
  } else if (!strcmp(scene, "rect")) { /* a free 16 x 4 block, 0.05 above the plane, falling at 0.5 */
    const double lo[2] = {0, 0.05}, hi[2] = {4, 1.05}, blo[2] = {-1, 0}, bhi[2] = {5, 0.05};
    h = 0.25 * sqrt(2.0), tau = 0.02, T = 4;
    volume = 4, contact_area = 4;
    st = nd_mesh_create_rectangle(16, 4, lo, hi, &m);
    if (!st) st = nd_mesh_mark_boundary_box(m, 1, blo, bhi);
    up[1] = 1;
  } else { /* the disk of docs/design.md §7, h = 4 */
    char path[1024];
    snprintf(path, sizeof path, "%s/disk_h4.msh", argv[6]);
    E = 50, nu = 0.25, h = 4, tau = 0.1, T = 32;
    volume = 3.14159265358979 * 20 * 20, contact_area = 3.14159265358979 * 20; /* radius 20, the lower half circle */
    g[1] = -0.1, up[1] = 1;
    st = nd_mesh_read_gmsh(path, &m);
  }
  /* _layered: the half of the cells numbered first (the generators number
     them from the origin: the bar's contact end, the rectangle's lower rows) */
  int64_t cells = 0;
  if (!st && layered) st = nd_mesh_get_cell_count(m, &cells);
  if (!st && layered) {
    int64_t *lower = malloc(sizeof(int64_t) * (size_t)(cells / 2 + 1));
    for (int64_t c = 0; c < cells / 2; ++c) lower[c] = c;
    st = nd_mesh_set_cell_region(m, 1, cells / 2, lower);
    free(lower);
  }
  if (!st) st = nd_problem_create(m, degree, &p);
  nd_mesh_destroy(&m);
  if (!st) st = nd_problem_set_material(p, E, nu, 1.0);
  if (!st && layered) st = nd_problem_set_material_region(p, 1, 4 * E, nu, 2.0);
  if (!st && !strcmp(scene, "bar")) st = nd_problem_set_dirichlet(p, 2);
  if (!st && !strcmp(scene, "disk")) st = nd_problem_set_body_force(p, g);
  if (!st) st = nd_problem_set_contact_plane(p, 1, origin, up);
  if (!st) st = nd_problem_set_nitsche(p, Theta, gamma0E / E);
  const double nm[2] = {0.25, 0.5}, nme[2] = {0, 0.5}, th1 = 1, rho = 0.8;
  int scheme = ND_SCHEME_HYBRID;
  const double *params = NULL;
  if (!strcmp(scheme_name, "newmark")) scheme = ND_SCHEME_NEWMARK, params = nm;
  if (!strcmp(scheme_name, "theta1")) scheme = ND_SCHEME_THETA, params = &th1;
  if (!strcmp(scheme_name, "galpha")) scheme = ND_SCHEME_GENERALIZED_ALPHA, params = &rho;
  if (!strcmp(scheme_name, "explicit")) { /* explicit Newmark, lumped mass, tau at a quarter of the node spacing */
    scheme = ND_SCHEME_NEWMARK, params = nme;
    tau = 0.25 * h / degree / sqrt(E);
    if (!st) st = nd_problem_set_mass_lumping(p, 1);
  }
  if (!st) st = nd_problem_set_scheme(p, scheme, params);
  if (!st) st = nd_problem_set_timestep(p, tau);
  if (!st && damped) st = nd_problem_set_damping(p, 0.05, 0.1 * tau);
  const double F = 0.3;
  if (!st && friction) st = nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F);
  const int adaptive = argc == 8 && !strcmp(argv[7], "adaptive");
  if (!st && adaptive) st = nd_problem_set_adaptive_timestep(p, 1e-2, 1e-4 * tau, tau);
  if (!st && unguarded) st = nd_problem_set_guard(p, ND_GUARD_ENERGY, 0);
  if (!st && unguarded) st = nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0);
  if (!st && unguarded) st = nd_problem_set_guard(p, ND_GUARD_PENETRATION, 0);
  if (st) {
    fprintf(stderr, "%s\n", nd_last_error());
    return 1;
  }
  /* a rectangle at rest needs its initial velocity: towards the plane */
  int64_t n = 0;
  nd_problem_get_node_count(p, &n);
  if (!strcmp(scene, "rect")) {
    double *v0 = calloc((size_t)(2 * n), sizeof(double));
    for (int64_t i = 0; i < n; ++i) v0[2 * i + 1] = -0.5;
    nd_problem_set_initial_state(p, n, NULL, v0);
    free(v0);
  } else if (!strcmp(scene, "bar")) {
    double *x = malloc(sizeof(double) * (size_t)n), *u0 = malloc(sizeof(double) * (size_t)n);
    nd_problem_get_node_coordinates(p, n, x);
    for (int64_t i = 0; i < n; ++i) u0[i] = 0.5 * (1 - x[i]);
    nd_problem_set_initial_state(p, n, u0, NULL);
    free(x);
    free(u0);
  }
  /* int E dx: _layered, the half of the volume at the obstacle 4 times as stiff */
  const double stiffness_volume = (layered ? 2.5 : 1.0) * E * volume;
  const double pen_length = fmin(h, volume / contact_area / 8);
  const int64_t steps = nd_step_count(T, tau);
  if (steps < 0) {
    fprintf(stderr, "%s: T / tau = %g / %g is not a number of steps (0 to 2^63 - 1)\n", argv[0], T, tau);
    nd_problem_destroy(&p);
    return 2;
  }
  const double t0 = now();
  const char *outcome = "completed";
  int code = ND_OK;
  int64_t k = 0;
  double E0 = get(p, ND_ENERGY_MECHANICAL), budget = E0, growth = 0, pen = 0, its = 0;
  double prev = get(p, ND_ENERGY_AUGMENTED) - get(p, ND_WORK), scale = fabs(prev);  /* (D = 0 at t = 0) */
  int theory_ok = 1, late = 0;
  /* the unguarded rerun's measures: the balance out of contact, its lowest
     value so far, its largest rise; the deepest point over eps* min(h, L/8) */
  double low = get(p, ND_ENERGY_AUGMENTED) - get(p, ND_WORK), rise = 0, Etop = E0, pen_ratio = 0;
  st = nd_problem_setup(p);
  if (st) {
    outcome = "refused_at_setup", code = st;
  } else {
    /* (adaptive: to T, within 20 times the fixed steps) */
    for (k = 1; adaptive ? get(p, ND_TIME) < T * (1 - 1e-12) && k <= 20 * steps : k <= steps; ++k) {
      st = nd_step(p);
      if (st) {
        outcome = "stopped_at_step", code = st;
        break;
      }
      const double Em = get(p, ND_ENERGY_MECHANICAL), W = get(p, ND_WORK),
                   D = get(p, ND_DISSIPATION_DAMPING) + get(p, ND_DISSIPATION_FRICTION);
      budget = fmax(budget, E0 + W);
      const double r = budget > 0 ? (Em + D) / budget : (Em + D > 0 ? INFINITY : 0);
      growth = fmax(growth, isfinite(r) ? r : INFINITY);
      pen = fmax(pen, get(p, ND_MAX_PENETRATION) / h);
      its += get(p, ND_NEWTON_ITERATIONS);
      const double strain = sqrt(2 * budget / stiffness_volume);
      if (!isfinite(Em) || r > 2 || get(p, ND_MAX_PENETRATION) > 4 * strain * pen_length) ++late;
      const double e = get(p, ND_ENERGY_AUGMENTED) + D - W;
      scale = fmax(scale, fabs(get(p, ND_ENERGY_AUGMENTED)) + fabs(W) + D);
      if (e > prev + 1e-10 * scale) theory_ok = 0;
      prev = e;
      const double L = e - get(p, ND_WORK_OBSTACLE) - get(p, ND_WORK_PRESCRIBED) - get(p, ND_WORK_GEOMETRY);
      const double in_motion = fmax(budget, Etop);
      Etop = fmax(Etop, Em);
      if (get(p, ND_ACTIVE_POINTS) == 0) {
        if (in_motion > 0) rise = fmax(rise, (L - low) / in_motion);
        low = fmin(low, L);
      }
      if (strain > 0) pen_ratio = fmax(pen_ratio, get(p, ND_MAX_PENETRATION) / (strain * pen_length));
    }
  }
  if (!code && late) outcome = "silent_failure";
  if (adaptive) {
    if (!code && get(p, ND_TIME) < T * (1 - 1e-12)) outcome = "stopped_at_step";  /* (out of steps) */
    printf("%s,%s,%" PRId64 ",%.0f\n", outcome, code_name(code), (int64_t)get(p, ND_STEP_INDEX),
           get(p, ND_STAT_STEPS_REJECTED));
    nd_problem_destroy(&p);
    return 0;
  }
  if (unguarded) {
    printf("%s,%s,%" PRId64 ",%.4g,%.4g,%.4g\n", outcome, code_name(code), code ? k : (int64_t)0, growth, rise,
           pen_ratio);
    nd_problem_destroy(&p);
    return 0;
  }
  const char *theory = scheme == ND_SCHEME_HYBRID && Theta == 1 ? (theory_ok ? "held" : "violated") : "-";
  char msg[256] = "";
  if (code) {
    snprintf(msg, sizeof msg, "%s", nd_last_error());
    for (char *c = msg; *c; ++c)
      if (*c == '"' || *c == ',' || *c == '\n') *c = ' ';
  }
  printf("%s,%d,%s,%g,%g,%g,%" PRId64 ",%s,%s,%" PRId64 ",%.4g,%.4g,%d,%.3f,%.3f,%s,\"%s\"\n", scene, degree, scheme_arg, Theta, gamma0E,
         tau, steps, outcome, code_name(code), code ? k : (int64_t)0, growth, pen, late,
         k > 0 ? its / (double)(code ? k - 1 : steps) : 0.0, now() - t0, theory, msg);
  nd_problem_destroy(&p);
  return 0;
}
