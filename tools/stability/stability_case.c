/* stability_case - one run of the stability suite (tools/stability/run.py):
 * a scene, a degree, a scheme, Theta and gamma0 E (and options), marched
 * with the library's default guards, and judged independently of them.
 * Prints one CSV row:
 *
 *   class,scene,degree,scheme,Theta,gamma0E,options,tau,steps_planned,outcome,
 *   code,step,energy_growth,max_penetration_over_h,late,newton_per_step,wall_s,
 *   theory,message
 *
 * class: the `class=NAME` option as given (run.py's class of the case; base
 * without it); options: the other options, separated by spaces (- if none).
 *
 * outcome: completed | refused_at_setup | stopped_at_step | silent_failure.
 * A run is a silent failure when every call returned ND_OK although, by this
 * program's own measurement, the mechanical energy passed 2 (E^0 + max_k W^k)
 * (the guard's default factor; W also counts the moving plane's work, which
 * this program sums itself: ND_CONTACT_FORCE_APPLIED, the force the step
 * applied to the body, times the plane's move over that step: not
 * ND_CONTACT_FORCE, the law at the end state, which generalized-alpha
 * (the law at its alpha level) and the hybrid scheme (the step's mean) do
 * not apply; and not the trapezoid of two steps' applied forces, which
 * the body feels each over its own step only: where a step jumps, as an
 * adaptive step shortened under a plane already placed at the step's
 * nominal end, the trapezoid counted 2.9 of a work of 91.7), became non-finite, or a contact point sank
 * deeper than 4 eps* min(h, L/8), eps* = sqrt(2 (E^0 + max_k W^k) / int E dx)
 * the strain of the energy put in and L = |Omega| / |Gamma_C| (the
 * penetration guard's default, docs/design.md §3b.5, measured here from the
 * scene's own dimensions), beyond the moving plane's approach over the step
 * (as the guard): what the guards exist to catch. late: the
 * steps accepted past those limits before a guard stopped the run.
 * theory: for the hybrid scheme with Theta = 1, whether E_Theta + D - W -
 * W_geometry never increased (part 2 of the paper; D the damping's
 * dissipation, W_geometry what a pair's re-pairing put in), else "-".
 *
 * With a 7th argument `unguarded` the run is made again with the guards that
 * act during the steps off (energy, energy balance, penetration) and the
 * set-up's critical-step check (the other set-up checks stay) to judge a
 * refusal, and prints instead
 *
 *   outcome,code,step,energy_growth,balance_gain,penetration_ratio,contact_gain
 *
 * balance_gain: the largest rise of the balance L = E_Theta - W - W_obstacle
 * - W_prescribed - W_geometry + D_damping + D_friction at a state without
 * an active point above its lowest value at such a state before (t^0
 * included), relative to the largest of E^0 + max W and max E;
 * penetration_ratio the deepest point (beyond the plane's approach) over
 * eps* min(h, L/8); contact_gain the same rise at every state, of the
 * balance with min(E, E_Theta) for E_Theta (the Nitsche term counted only where it lowers the balance: the
 * energy it holds in contact is no energy of the body, and for the hybrid
 * scheme with Theta = 1 this stays below its non-increasing L), above its
 * lowest value at a state without an active point before: a body that gains
 * while it stays in contact (at rest on the plane, a disk rocking on it)
 * never reaches a state without one, and E^0 + max W counts the potential
 * energy it took back by climbing (issue 57: "the reference must not count
 * potential energy the body has not turned into motion"). run.py calls a
 * refusal justified when the unguarded run then fails (a non-finite state,
 * Newton), gains (energy_growth > 1.05, balance_gain > 0.05 or contact_gain
 * > 0.05) or sinks (penetration_ratio > 4), and a false alarm otherwise.
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
 * usage: stability_case SCENE DEGREE SCHEME THETA GAMMA0E MESH_DIR [unguarded|adaptive] [KEY=VALUE ...]
 *   SCENE   bar | rect | disk | ball | sliver | rest
 *     bar     1D, 40 cells, clamped at x = 1, u0 = (1-x)/2, tau = h/2, T = 6
 *     rect    a free 16 x 4 block [0,4] x [0.05,1.05] falling at 0.5 onto y = 0
 *     disk    examples/meshes/disk_h4.msh (radius 20, 5 above the plane), E = 50,
 *             nu = 0.25, gravity 0.1, tau = 0.1, T = 32
 *     ball    the same in 3D: examples/meshes/ball_h4.msh (its regions as the disk's)
 *     sliver  rect's block with a first row of cells (at the contact) 1e-3 times
 *             as high as wide: flat and sliver contact cells
 *     rest    a static load: rect's block at rest on the plane (gap 0), gravity
 *             0.01, T = 200 (10^4 steps)
 *     pair    two deformable bodies (docs/design.md §10.3): the two disks of
 *             examples/meshes/two_disks_h4.msh (the disk's, 1 apart) meeting
 *             at 0.5 each (nd_problem_set_contact_pair, regions 1 and 2),
 *             no load, E = 50, nu = 0.25, tau = 0.1, T = 20; the penetration
 *             measured into the other body; with _friction (Coulomb F = 0.3
 *             on the pair) also sliding past each other at -+0.5 along x
 *   SCHEME  hybrid | newmark | theta1 | explicit | galpha,
 *   each with the suffixes (any of them, in this order) _damped for Rayleigh
 *   damping alpha = 0.05, beta = 0.1 tau (damping ratio about 0.1 at the
 *   highest frequency the step resolves), _friction for Coulomb friction F =
 *   0.3 on the contact region (2D; the pair's slave region), _layered for two materials: the half of
 *   the bar's or the rectangle's cells at the obstacle 4 times as stiff and
 *   twice as dense.
 *   The energies then count D_f with D (ND_DISSIPATION_FRICTION).
 *   KEY=VALUE options:
 *     class=NAME   the class printed in the first column (nothing else)
 *     mat=steel    SI units: E = 2.1e11 Pa, rho = 7850, nu = 0.3 (bar, rect):
 *                  the bar 1 m, u0 = 1e-3 (1-x) m; the block 4 m x 1 m falling
 *                  at 1 m/s; tau and T (and the block's gap) scaled by the
 *                  time the wave takes through 1 m, 1/sqrt(E/rho)
 *     mat=rubber   nu = 0.49; mat=rubber4999: nu = 0.4999 (E, rho the scene's)
 *     speed=F      the impact speed F times the default: the bar's u0, the
 *                  block's v0 times F; disk, ball: v0 = -sqrt(F^2 - 1) v_hit
 *                  (F >= 1; v_hit the speed gravity gives over the gap) or
 *                  gravity times F^2 (F < 1)
 *     tau=F        the time step F times the scene's (T rounded to a whole number
 *                  of steps, at least one)
 *     steps=N      T = N tau (the long runs)
 *     tau_c=F      explicit: the time step F times the library's estimate of the
 *                  critical step (nd_problem_estimate_critical_timestep), T the
 *                  scene's (rounded to a whole number of steps)
 *     plane=moving the plane moves towards the body at v_p (bar 0.1, else 0.5)
 *                  until T/2, then stays (nd_problem_set_contact_plane before
 *                  each step; rect and sliver start at rest) */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "nitschedyn.h"

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

/* sliver: rect's block (16 x 4 cells of [0,4] x [gap, gap + 1]) on a first
   row of cells 1e-3 times as high as wide (2.5e-4): triangles, each
   rectangle split into 2 */
static int block_mesh(double gap, nd_mesh *m) {
  enum { NX = 16 };
  const int ny = 5;
  double y[6];
  y[0] = gap;
  for (int j = 1; j <= ny; ++j) y[j] = j == 1 ? gap + 2.5e-4 : y[1] + 0.25 * (j - 1);
  double coords[2 * (NX + 1) * 6];
  int64_t cells[3 * 2 * NX * 5];
  int64_t n = 0, c = 0;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= NX; ++i) coords[2 * n] = 0.25 * i, coords[2 * n + 1] = y[j], ++n;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < NX; ++i) {
      const int64_t a = j * (NX + 1) + i, b = a + 1, d = a + NX + 1, e = d + 1;
      cells[c++] = a, cells[c++] = b, cells[c++] = e;
      cells[c++] = a, cells[c++] = e, cells[c++] = d;
    }
  return nd_mesh_create(2, n, coords, c / 3, cells, m);
}

int main(int argc, char **argv) {
  const char *mode = "", *cls = "base", *mat = "default", *plane = "fixed";
  double speed = 1, tau_factor = 1, critical_factor = 0;
  int64_t fixed_steps = 0;
  char options[512] = "";
  int bad = argc < 7;
  for (int a = 7; a < argc && !bad; ++a) {
    const char *v = strchr(argv[a], '=');
    if (!strcmp(argv[a], "unguarded") || !strcmp(argv[a], "adaptive")) {
      mode = argv[a];
      continue;
    }
    if (!v) {
      bad = 1;
      break;
    }
    ++v;
    if (!strncmp(argv[a], "class=", 6)) {
      cls = v;
      continue;
    }
    if (!strncmp(argv[a], "mat=", 4)) mat = v;
    else if (!strncmp(argv[a], "speed=", 6)) speed = atof(v);
    else if (!strncmp(argv[a], "tau=", 4)) tau_factor = atof(v);
    else if (!strncmp(argv[a], "steps=", 6)) fixed_steps = atoll(v);
    else if (!strncmp(argv[a], "tau_c=", 6)) critical_factor = atof(v);
    else if (!strncmp(argv[a], "plane=", 6)) plane = v;
    else bad = 1;
    snprintf(options + strlen(options), sizeof options - strlen(options), "%s%s", *options ? " " : "", argv[a]);
  }
  if (bad || !(speed > 0) || !(tau_factor > 0) || fixed_steps < 0 || critical_factor < 0 ||
      (strcmp(mat, "default") && strcmp(mat, "steel") && strcmp(mat, "rubber") && strcmp(mat, "rubber4999")) ||
      (strcmp(plane, "fixed") && strcmp(plane, "moving"))) {
    fprintf(stderr, "usage: %s SCENE DEGREE SCHEME THETA GAMMA0E MESH_DIR [unguarded|adaptive] [KEY=VALUE ...]\n",
            argv[0]);
    return 2;
  }
  const int unguarded = !strcmp(mode, "unguarded"), adaptive = !strcmp(mode, "adaptive");
  const int steel = !strcmp(mat, "steel"), moving = !strcmp(plane, "moving");
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
  const int is_block = !strcmp(scene, "rect") || !strcmp(scene, "sliver") || !strcmp(scene, "rest");
  const int is_round = !strcmp(scene, "disk") || !strcmp(scene, "ball");
  const int pair = !strcmp(scene, "pair");
  if (strcmp(scene, "bar") && !is_block && !is_round && !pair) {
    fprintf(stderr, "%s: unknown scene %s\n", argv[0], scene);
    return 2;
  }
  if (pair && (moving || layered || strcmp(mat, "default"))) {
    fprintf(stderr, "%s: the pair scene takes no moving plane, layers or material\n", argv[0]);
    return 2;
  }
  if (steel && !(strcmp(scene, "bar") == 0 || strcmp(scene, "rect") == 0 || strcmp(scene, "sliver") == 0)) {
    fprintf(stderr, "%s: mat=steel is for the bar and the block (rect, sliver)\n", argv[0]);
    return 2;
  }
  nd_mesh m = NULL;
  nd_problem p = NULL;
  double E = 1, nu = 0.3, rho = 1, h = 0, tau = 0, T = 0;
  if (steel) E = 2.1e11, rho = 7850;
  /* the time the wave takes through 1 (length unit): the scenes' time scale */
  const double wave = steel ? 1 / sqrt(E / rho) : 1;
  /* |Omega| and |Gamma_C| (the body's length across its contact region L
     is their ratio), for the penetration criterion */
  double volume = 0, contact_area = 0;
  int st = ND_OK, dim = 2;
  double g[3] = {0, 0, 0}, origin[3] = {0, 0, 0}, up[3] = {0, 0, 0}, v_plane = 0.5, v0_down = 0;
  if (!strcmp(scene, "bar")) { /* docs/design.md §7: clamped at x = 1, u0 = (1-x)/2 */
    const double lo[2] = {-0.5, 0.5}, hi[2] = {0.5, 1.5};
    h = 1.0 / 40, tau = h / 2 * wave, T = 6 * wave, dim = 1, v_plane = 0.1;
    volume = 1, contact_area = 1;
    st = nd_mesh_create_interval(40, 0, 1, &m);
    if (!st) st = nd_mesh_mark_boundary_box(m, 1, &lo[0], &hi[0]);
    if (!st) st = nd_mesh_mark_boundary_box(m, 2, &lo[1], &hi[1]);
    up[0] = 1;
  } else if (is_block) {
    /* rect, sliver: a free 16 x 4 block, 0.05 above the plane (steel: the gap
       the block at 1 m/s crosses in 0.1 wave times), falling at 0.5 (1 m/s);
       rest: on the plane, at rest, under gravity */
    const int rest = !strcmp(scene, "rest");
    const double v_ref = steel ? 1 : 0.5, gap = rest ? 0 : 0.1 * v_ref * wave;
    const double blo[2] = {-1, -1}, bhi[2] = {5, gap + (!strcmp(scene, "sliver") ? 1e-4 : 1e-3)};
    h = 0.25 * sqrt(2.0), tau = 0.02 * wave, T = (rest ? 200 : 4) * wave;
    volume = 4, contact_area = 4;
    v0_down = rest || moving ? 0 : v_ref * speed;
    if (rest) g[1] = -0.01;
    const double lo[2] = {0, gap}, hi[2] = {4, gap + 1};
    st = !strcmp(scene, "sliver") ? block_mesh(gap, &m) : nd_mesh_create_rectangle(16, 4, lo, hi, &m);
    if (!st) st = nd_mesh_mark_boundary_box(m, 1, blo, bhi);
    up[1] = 1;
  } else if (pair) { /* two disks of radius 20 meeting at 0.5 each (speed=F: F times) */
    char path[1024];
    snprintf(path, sizeof path, "%s/two_disks_h4.msh", argv[6]);
    E = 50, nu = 0.25, h = 4, tau = 0.1, T = 20;
    const double R = 20, pi = 3.14159265358979;
    volume = pi * R * R, contact_area = pi * R; /* each body's */
    v0_down = 0.5 * speed;
    st = nd_mesh_read_gmsh(path, &m);
  } else { /* the disk of docs/design.md §7, h = 4, or the ball */
    char path[1024];
    const int ball = !strcmp(scene, "ball");
    dim = ball ? 3 : 2;
    snprintf(path, sizeof path, "%s/%s_h4.msh", argv[6], scene);
    E = 50, nu = 0.25, h = 4, tau = 0.1, T = 32;
    const double R = 20, pi = 3.14159265358979, gravity = 0.1, gap = 5;
    volume = ball ? 4.0 / 3 * pi * R * R * R : pi * R * R; /* radius 20, the lower half sphere (circle) */
    contact_area = ball ? 2 * pi * R * R : pi * R;
    g[dim - 1] = -gravity * (speed < 1 ? speed * speed : 1), up[dim - 1] = 1;
    v0_down = speed > 1 ? sqrt(speed * speed - 1) * sqrt(2 * gravity * gap) : 0;
    st = nd_mesh_read_gmsh(path, &m);
  }
  if (!strcmp(mat, "rubber")) nu = 0.49;
  if (!strcmp(mat, "rubber4999")) nu = 0.4999;
  tau *= tau_factor;
  int64_t steps = fixed_steps ? fixed_steps : (int64_t)fmax(1, floor(T / tau + 0.5));
  T = (double)steps * tau;
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
  if (!st) st = nd_problem_set_material(p, E, nu, rho);
  if (!st && layered) st = nd_problem_set_material_region(p, 1, 4 * E, nu, 2.0 * rho);
  if (!st && !strcmp(scene, "bar")) st = nd_problem_set_dirichlet(p, 2);
  if (!st && (g[0] != 0 || g[1] != 0 || g[2] != 0)) st = nd_problem_set_body_force(p, g);
  if (!st) st = pair ? nd_problem_set_contact_pair(p, 1, 2) : nd_problem_set_contact_plane(p, 1, origin, up);
  if (!st) st = nd_problem_set_nitsche(p, Theta, gamma0E / E);
  const double nm[2] = {0.25, 0.5}, nme[2] = {0, 0.5}, th1 = 1, rho_inf = 0.8;
  int scheme = ND_SCHEME_HYBRID;
  const double *params = NULL;
  if (!strcmp(scheme_name, "newmark")) scheme = ND_SCHEME_NEWMARK, params = nm;
  if (!strcmp(scheme_name, "theta1")) scheme = ND_SCHEME_THETA, params = &th1;
  if (!strcmp(scheme_name, "galpha")) scheme = ND_SCHEME_GENERALIZED_ALPHA, params = &rho_inf;
  if (!strcmp(scheme_name, "explicit")) { /* explicit Newmark, lumped mass, tau at a quarter of the node spacing */
    scheme = ND_SCHEME_NEWMARK, params = nme;
    tau = 0.25 * h / degree / sqrt(E / rho) * tau_factor;
    steps = fixed_steps ? fixed_steps : (int64_t)fmax(1, floor(T / tau + 0.5));
    T = (double)steps * tau;
    if (!st) st = nd_problem_set_mass_lumping(p, 1);
  }
  if (!st) st = nd_problem_set_scheme(p, scheme, params);
  if (!st && critical_factor > 0 && scheme_name[0] != 'e') {
    fprintf(stderr, "%s: tau_c= is for the explicit scheme\n", argv[0]);
    return 2;
  }
  if (!st && critical_factor > 0) { /* (the estimate reads the scheme and the mass, not tau) */
    double tau_c = 0;
    st = nd_problem_estimate_critical_timestep(p, &tau_c);
    tau = critical_factor * tau_c;
    steps = fixed_steps ? fixed_steps : (int64_t)fmax(1, floor(T / tau + 0.5));
    T = (double)steps * tau;
  }
  if (!st) st = nd_problem_set_timestep(p, tau);
  if (!st && damped) st = nd_problem_set_damping(p, 0.05, 0.1 * tau);
  const double F = 0.3;
  if (!st && friction) st = nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F);
  if (!st && adaptive) st = nd_problem_set_adaptive_timestep(p, 1e-2, 1e-4 * tau, tau);
  if (!st && unguarded) st = nd_problem_set_guard(p, ND_GUARD_ENERGY, 0);
  if (!st && unguarded) st = nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0);
  if (!st && unguarded) st = nd_problem_set_guard(p, ND_GUARD_PENETRATION, 0);
  /* (and the set-up's critical-step check, to judge its refusals) */
  if (!st && unguarded) st = nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0);
  if (st) {
    fprintf(stderr, "%s\n", nd_last_error());
    return 1;
  }
  /* the initial state: the block's velocity towards the plane, the bar's stretch */
  int64_t n = 0;
  nd_problem_get_node_count(p, &n);
  if (v0_down > 0) { /* (pair: the upper disk down, the lower one up; with
                         friction also sliding along x at -+v0, so that they
                         meet at gross slip and roll apart) */
    double *v0 = calloc((size_t)(dim * n), sizeof(double)), *x = malloc(sizeof(double) * (size_t)(dim * n));
    nd_problem_get_node_coordinates(p, n, x);
    for (int64_t i = 0; i < n; ++i) {
      const int lower = pair && x[dim * i + dim - 1] < 0;
      v0[dim * i + dim - 1] = lower ? v0_down : -v0_down;
      if (pair && friction) v0[dim * i] = lower ? -v0_down : v0_down;
    }
    free(x);
    nd_problem_set_initial_state(p, n, NULL, v0);
    free(v0);
  } else if (!strcmp(scene, "bar")) {
    const double amplitude = (steel ? 1e-3 : 0.5) * speed;
    double *x = malloc(sizeof(double) * (size_t)n), *u0 = malloc(sizeof(double) * (size_t)n);
    nd_problem_get_node_coordinates(p, n, x);
    for (int64_t i = 0; i < n; ++i) u0[i] = amplitude * (1 - x[i]);
    nd_problem_set_initial_state(p, n, u0, NULL);
    free(x);
    free(u0);
  }
  if (steel) v_plane *= !strcmp(scene, "bar") ? 1e-3 / 0.5 / wave : 2; /* (steel: as the scene's speeds) */
  /* int E dx: _layered, the half of the volume at the obstacle 4 times as stiff */
  const double stiffness_volume = (layered ? 2.5 : 1.0) * E * volume;
  const double pen_length = fmin(h, volume / contact_area / 8);
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
  /* the balance with min(E, E_Theta): its lowest value without an active
     point (t^0 included), its largest rise at any state */
  double low_c = fmin(E0, get(p, ND_ENERGY_AUGMENTED)) - get(p, ND_WORK), rise_c = 0;
  /* the moving plane: where it is (along up), the work it has done (this
     program's sum) */
  double d_plane = 0, work_plane = 0;
  st = nd_problem_setup(p);
  if (st) {
    outcome = "refused_at_setup", code = st;
  } else {
    /* (adaptive: to T, within 20 times the fixed steps) */
    for (k = 1; adaptive ? get(p, ND_TIME) < T * (1 - 1e-12) && k <= 20 * steps : k <= steps; ++k) {
      double d_next = d_plane;
      if (moving) {
        d_next = v_plane * fmin(get(p, ND_TIME) + get(p, ND_TIMESTEP), T / 2);
        double point[3] = {0, 0, 0};
        point[dim - 1] = d_next;
        nd_problem_set_contact_plane(p, 1, point, up);
      }
      st = nd_step(p);
      if (st) {
        outcome = "stopped_at_step", code = st;
        break;
      }
      const double force = get(p, ND_CONTACT_FORCE_APPLIED);
      work_plane += force * (d_next - d_plane);
      /* the plane's approach over the step: a depth no force has answered yet
         where the scheme applies the law before the step's end (generalized-
         alpha), with no energy put in if the body was at rest (the guard
         allows it too) */
      const double approach = fmax(0, d_next - d_plane);
      d_plane = d_next;
      const double Em = get(p, ND_ENERGY_MECHANICAL), W = get(p, ND_WORK) + work_plane,
                   D = get(p, ND_DISSIPATION_DAMPING) + get(p, ND_DISSIPATION_FRICTION);
      budget = fmax(budget, E0 + W);
      const double r = budget > 0 ? (Em + D) / budget : (Em + D > 0 ? INFINITY : 0);
      growth = fmax(growth, isfinite(r) ? r : INFINITY);
      pen = fmax(pen, get(p, ND_MAX_PENETRATION) / h);
      its += get(p, ND_NEWTON_ITERATIONS);
      const double strain = sqrt(2 * budget / stiffness_volume), sunk = get(p, ND_MAX_PENETRATION) - approach;
      if (!isfinite(Em) || r > 2 || sunk > 4 * strain * pen_length) ++late;
      /* (W_geometry: what re-linearisations put in, a pair's re-pairing) */
      const double e = get(p, ND_ENERGY_AUGMENTED) + D - get(p, ND_WORK) - get(p, ND_WORK_GEOMETRY);
      scale = fmax(scale, fabs(get(p, ND_ENERGY_AUGMENTED)) + fabs(W) + D);
      if (e > prev + 1e-10 * scale) theory_ok = 0;
      prev = e;
      const double L = e - get(p, ND_WORK_OBSTACLE) - get(p, ND_WORK_PRESCRIBED);
      const double in_motion = fmax(budget, Etop);
      Etop = fmax(Etop, Em);
      const double Lc = L - get(p, ND_ENERGY_AUGMENTED) + fmin(Em, get(p, ND_ENERGY_AUGMENTED));
      if (in_motion > 0) rise_c = fmax(rise_c, (Lc - low_c) / in_motion);
      if (get(p, ND_ACTIVE_POINTS) == 0) {
        if (in_motion > 0) rise = fmax(rise, (L - low) / in_motion);
        low = fmin(low, L), low_c = fmin(low_c, Lc);
      }
      if (sunk > 0) pen_ratio = fmax(pen_ratio, strain > 0 ? sunk / (strain * pen_length) : INFINITY);
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
    printf("%s,%s,%" PRId64 ",%.4g,%.4g,%.4g,%.4g\n", outcome, code_name(code), code ? k : (int64_t)0, growth, rise,
           pen_ratio, rise_c);
    nd_problem_destroy(&p);
    return 0;
  }
  /* (the theory's balance E_Theta + D - W: the moving plane works on the body) */
  const char *theory = scheme == ND_SCHEME_HYBRID && Theta == 1 && !moving ? (theory_ok ? "held" : "violated") : "-";
  char msg[256] = "";
  if (code) {
    snprintf(msg, sizeof msg, "%s", nd_last_error());
    for (char *c = msg; *c; ++c)
      if (*c == '"' || *c == ',' || *c == '\n') *c = ' ';
  }
  printf("%s,%s,%d,%s,%g,%g,%s,%g,%" PRId64 ",%s,%s,%" PRId64 ",%.4g,%.4g,%d,%.3f,%.3f,%s,\"%s\"\n", cls, scene,
         degree, scheme_arg, Theta, gamma0E, *options ? options : "-", tau, steps, outcome, code_name(code),
         code ? k : (int64_t)0, growth, pen, late, k > 0 ? its / (double)(code ? k - 1 : steps) : 0.0, now() - t0,
         theory, msg);
  nd_problem_destroy(&p);
  return 0;
}
