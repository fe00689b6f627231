/* A linear elastic disk (2D, plane strain) or ball (3D) of radius 20, centre
 * 25 above the plane, lambda = mu = 20, rho = 1, falling under gravity
 * (0, -0.1): it hits the plane at t = 10 with speed 1, stays in contact for a
 * while and bounces off (docs/design.md §7). Prints the energies, the contact force,
 * the penetration and the Newton iterations per interval, and the run time. */
#include "drop_scene.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "nitschedyn.h"
#include "step_count.h"

typedef struct {
  const char *mesh, *vtu;
  int degree, scheme, solver, quiet;
  double params[2], Theta, gamma0, tau, T, every;
} options;

static void usage(const char *prog, int dim) {
  printf("usage: %s [options]\n"
         "  --mesh FILE       Gmsh mesh (default %s/%s_h4.msh; region 1 = contact boundary)\n"
         "  --degree 1|2      Lagrange degree (default 1)\n"
         "  --scheme S        hybrid (default) | newmark | theta | galpha\n"
         "  --beta B --gamma G   Newmark parameters (default 0.25, 0.5)\n"
         "  --theta-param T   theta of the theta-scheme (default 0.5)\n"
         "  --rho-inf R       generalized-alpha's rho_inf in [0,1] (default 0.8)\n"
         "  --Theta T         Nitsche's Theta (default 1)\n"
         "  --gamma0 G        Nitsche parameter, gamma = gamma0 h_K; 0 (default): automatic,\n"
         "                    half the coercivity bound of the mesh (1/50 of it with\n"
         "                    Theta <= 0 and the hybrid scheme; printed)\n"
         "  --tau T           time step (default 0.05)\n"
         "  --T T             final time (default 32)\n"
         "  --every D         print every D time units (default 1)\n"
         "  --solver S        auto (default) | dense | banded | cholmod | umfpack | klu\n"
         "  --vtu PREFIX      write PREFIX_NNNN.vtu every print interval and PREFIX.pvd\n"
         "  --quiet           summary only\n",
         prog, ND_MESH_DIR, dim == 2 ? "disk" : "ball");
}

static int parse(int argc, char **argv, int dim, options *o, char *default_mesh, size_t size) {
  snprintf(default_mesh, size, "%s/%s_h4.msh", ND_MESH_DIR, dim == 2 ? "disk" : "ball");
  *o = (options){default_mesh, NULL, 1, ND_SCHEME_HYBRID, ND_SOLVER_AUTO, 0, {0.25, 0.5}, 1.0, 0.0, 0.05, 32.0, 1.0};
  int theta_set = 0, rho_set = 0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!strcmp(a, "--help")) {
      usage(argv[0], dim);
      return 1;
    }
    if (!strcmp(a, "--quiet")) {
      o->quiet = 1;
      continue;
    }
    if (!v) {
      fprintf(stderr, "%s: %s needs a value (see --help)\n", argv[0], a);
      return 2;
    }
    ++i;
    if (!strcmp(a, "--mesh")) o->mesh = v;
    else if (!strcmp(a, "--vtu")) o->vtu = v;
    else if (!strcmp(a, "--degree")) o->degree = atoi(v);
    else if (!strcmp(a, "--beta")) o->params[0] = atof(v);
    else if (!strcmp(a, "--gamma")) o->params[1] = atof(v);
    else if (!strcmp(a, "--theta-param")) o->params[0] = atof(v), theta_set = 1;
    else if (!strcmp(a, "--rho-inf")) o->params[0] = atof(v), rho_set = 1;
    else if (!strcmp(a, "--Theta")) o->Theta = atof(v);
    else if (!strcmp(a, "--gamma0")) o->gamma0 = atof(v);
    else if (!strcmp(a, "--tau")) o->tau = atof(v);
    else if (!strcmp(a, "--T")) o->T = atof(v);
    else if (!strcmp(a, "--every")) o->every = atof(v);
    else if (!strcmp(a, "--scheme")) {
      o->scheme = !strcmp(v, "newmark") ? ND_SCHEME_NEWMARK : !strcmp(v, "theta") ? ND_SCHEME_THETA
                : !strcmp(v, "hybrid") ? ND_SCHEME_HYBRID : !strcmp(v, "galpha") ? ND_SCHEME_GENERALIZED_ALPHA : -1;
      if (o->scheme < 0) return fprintf(stderr, "%s: unknown scheme %s\n", argv[0], v), 2;
    } else if (!strcmp(a, "--solver")) {
      static const char *names[] = {"auto", "dense", "banded", "cholmod", "umfpack", "klu"};
      o->solver = -1;
      for (int k = 0; k < 6; ++k)
        if (!strcmp(v, names[k])) o->solver = k;
      if (o->solver < 0) return fprintf(stderr, "%s: unknown solver %s\n", argv[0], v), 2;
    } else {
      fprintf(stderr, "%s: unknown option %s (see --help)\n", argv[0], a);
      return 2;
    }
  }
  if (o->scheme == ND_SCHEME_THETA && !theta_set) o->params[0] = 0.5;
  if (o->scheme == ND_SCHEME_GENERALIZED_ALPHA && !rho_set) o->params[0] = 0.8;
  return 0;
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double get(nd_problem p, int key) {
  double x = 0;
  nd_get_scalar(p, key, &x);
  return x;
}

int drop_scene_create(int dim, const char *mesh, int degree, int scheme, const double *params, double Theta,
                      double gamma0, double tau, int solver, nd_problem *out) {
  const double lambda = 20, mu = 20; /* E and nu from the Lame coefficients */
  const double young = mu * (3 * lambda + 2 * mu) / (lambda + mu), nu = lambda / (2 * (lambda + mu));
  const double g[3] = {0, dim == 2 ? -0.1 : 0, dim == 3 ? -0.1 : 0}, origin[3] = {0, 0, 0};
  const double up[3] = {0, dim == 2 ? 1 : 0, dim == 3 ? 1 : 0};
  nd_mesh m = NULL;
  int mdim = 0, st = nd_mesh_read_gmsh(mesh, &m);
  if (st == ND_OK) st = nd_mesh_get_dimension(m, &mdim);
  if (st == ND_OK && mdim != dim) st = ND_ERR_DIMENSION;
  if (st == ND_OK) st = nd_problem_create(m, degree, out);
  nd_mesh_destroy(&m); /* the problem keeps its own copy */
  if (st == ND_OK) st = nd_problem_set_material(*out, young, nu, 1.0);
  if (st == ND_OK) st = nd_problem_set_body_force(*out, g);
  if (st == ND_OK) st = nd_problem_set_contact_plane(*out, 1, origin, up);
  if (st == ND_OK) st = nd_problem_set_nitsche(*out, Theta, gamma0);
  if (st == ND_OK) st = nd_problem_set_scheme(*out, scheme, params);
  if (st == ND_OK) st = nd_problem_set_timestep(*out, tau);
  if (st == ND_OK) st = nd_problem_set_linear_solver(*out, solver);
  if (st == ND_ERR_DIMENSION && mdim != dim && mdim > 0)
    fprintf(stderr, "%s is a %dD mesh, the scene is %dD\n", mesh, mdim, dim);
  return st;
}

#define TRY(call)                                                 \
  do {                                                            \
    if ((call) != ND_OK) {                                        \
      fprintf(stderr, "%s\n", nd_last_error());                   \
      goto done;                                                  \
    }                                                             \
  } while (0)

int drop_scene_main(int argc, char **argv, int dim) {
  options o;
  char default_mesh[512];
  const int parsed = parse(argc, argv, dim, &o, default_mesh, sizeof default_mesh);
  if (parsed) return parsed == 1 ? 0 : 2;
  int status = 1;
  nd_problem p = NULL;
  char **files = NULL;
  double *times = NULL;
  /* (a double beyond int64_t: undefined in a cast) */
  const int64_t steps = nd_step_count(o.T, o.tau), every_steps = nd_step_count(o.every, o.tau);
  if (steps < 0 || every_steps < 0) {
    fprintf(stderr, "%s: %s / tau = %g / %g is not a number of steps (0 to 2^63 - 1)\n", argv[0],
            steps < 0 ? "T" : "every", steps < 0 ? o.T : o.every, o.tau);
    return 2;
  }
  const int64_t every = every_steps > 0 ? every_steps : 1;
  int64_t n_nodes = 0, n_files = 0;
  double t0 = now(), t_setup = 0, t_loop = 0, max_pen = 0, newton = 0;

  TRY(drop_scene_create(dim, o.mesh, o.degree, o.scheme, o.params, o.Theta, o.gamma0, o.tau, o.solver, &p));
  TRY(nd_problem_get_node_count(p, &n_nodes));
  t_setup = now() - t0;
  if (!o.quiet) {
    double gamma0 = 0, limit = 0;
    TRY(nd_get_scalar(p, ND_GAMMA0, &gamma0));
    TRY(nd_get_scalar(p, ND_GAMMA0_LIMIT, &limit));
    printf("%dD %s: P%d, %lld FE nodes (%lld unknowns), Theta = %g, gamma0 = %g%s (coercive up to %g), tau = %g, "
           "T = %g\n",
           dim, dim == 2 ? "disk" : "ball", o.degree, (long long)n_nodes, (long long)(n_nodes * dim), o.Theta, gamma0,
           o.gamma0 == 0 ? " (automatic)" : "", limit, o.tau, o.T);
    printf("%8s %14s %14s %14s %12s %12s %7s\n", "t", "E", "E_Theta", "E_Theta-W", "force", "penetration", "Newton");
  }
  if (o.vtu) {
    files = calloc((size_t)(steps / every + 2), sizeof *files);
    times = calloc((size_t)(steps / every + 2), sizeof *times);
    if (!files || !times) {
      fprintf(stderr, "%s: no memory for the names of %lld VTU files\n", argv[0], (long long)(steps / every + 2));
      goto done;
    }
  }
  for (int64_t k = 0; k <= steps; ++k) {
    if (k > 0) {
      const double s0 = now();
      TRY(nd_step(p));
      t_loop += now() - s0;
      newton += get(p, ND_NEWTON_ITERATIONS);
    }
    const double pen = get(p, ND_MAX_PENETRATION);
    max_pen = pen > max_pen ? pen : max_pen;
    if (k % every != 0 && k != steps) continue;
    if (!o.quiet)
      printf("%8.3f %14.8g %14.8g %14.8g %12.6g %12.4e %7.0f\n", get(p, ND_TIME), get(p, ND_ENERGY_MECHANICAL),
             get(p, ND_ENERGY_AUGMENTED), get(p, ND_ENERGY_AUGMENTED) - get(p, ND_WORK), get(p, ND_CONTACT_FORCE), pen,
             get(p, ND_NEWTON_ITERATIONS));
    if (o.vtu) {
      const size_t len = strlen(o.vtu) + 16;
      files[n_files] = malloc(len);
      snprintf(files[n_files], len, "%s_%04lld.vtu", o.vtu, (long long)n_files);
      times[n_files] = get(p, ND_TIME);
      TRY(nd_problem_write_vtu(p, files[n_files++]));
    }
  }
  if (o.vtu) {
    char pvd[1024];
    snprintf(pvd, sizeof pvd, "%s.pvd", o.vtu);
    TRY(nd_write_pvd(pvd, n_files, (const char *const *)files, times));
  }
  printf("%dD %s P%d: %lld steps, %lld unknowns, mean Newton iterations %.3f, max penetration %.4e\n", dim,
         dim == 2 ? "disk" : "ball", o.degree, (long long)steps, (long long)(n_nodes * dim), newton / (double)steps,
         max_pen);
  printf("run time: setup %.4f s, time loop %.4f s (%.4f ms/step; includes assembly and factorization at step 1)\n",
         t_setup, t_loop, 1e3 * t_loop / (double)steps);
  status = 0;
done:
  for (int64_t i = 0; i < n_files; ++i) free(files[i]);
  free(files);
  free(times);
  nd_problem_destroy(&p);
  return status;
}
