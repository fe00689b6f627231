/*
 * bar1d - the 1D bar of DESIGN §7 through the public API of libnitschedyn,
 * compared with its exact solution.
 *
 * Omega = (0,1), rho = E = 1, clamped at x = 1, rigid obstacle at x = 0
 * (gap 0), u0(x) = (1-x)/2, v0 = 0. The bar flies down for t in (0,1),
 * stays in contact for t in (1,2), leaves for t in (2,3), and starts again.
 *
 * All error norms are relative (norm of the error / same norm of the exact
 * solution) and are sampled at every time level t_n = n tau, t_0 included;
 * time integrals use the trapezoidal rule over those levels, space integrals
 * are exact (Gauss rules on the pieces between the kinks of the exact field).
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bar1d_exact.h"
#include "nitschedyn.h"

/* ---- options ------------------------------------------------------------ */

typedef struct {
  int scheme;        /* ND_SCHEME_* */
  double params[2];  /* theta, or beta and gamma */
  int degree;
  double Theta, gamma0;
  int64_t nx;
  double tau, T; /* tau <= 0: default h/2 */
  int lumped, quiet;
  const char *csv;
} options;

static void usage(FILE *f, const char *prog) {
  fprintf(f,
          "usage: %s [SCHEME] [options]\n"
          "The 1D bar with an exact solution (DESIGN §7), relative errors and energies.\n"
          "  SCHEME, or --scheme SCHEME   hybrid (default) | theta | newmark\n"
          "  --theta-param X   theta of the theta-scheme (default 0.5)\n"
          "  --beta X          Newmark beta (default 0.25)\n"
          "  --gamma X         Newmark gamma (default 0.5)\n"
          "  --degree 1|2      polynomial degree (default 1)\n"
          "  --Theta X         Nitsche Theta (default 1)\n"
          "  --gamma0 X        Nitsche gamma0, gamma = gamma0 h (default 0.2)\n"
          "  --nx N            number of cells (default 40)\n"
          "  --tau X           time step (default h/2 = 1/(2 nx))\n"
          "  --T X             final time (default 3); steps = round(T/tau)\n"
          "  --lumped 0|1      lumped mass (default 0)\n"
          "  --csv FILE        write t,u(0),v(0),contact_stress,E,E_Theta per time level\n"
          "  --quiet           print the summary only\n"
          "  --help            this text\n"
          "Options also accept --key=value. Exit status: 0 ok, 1 library error, 2 usage.\n",
          prog);
}

static int parse_double(const char *s, double *out) {
  char *end;
  *out = strtod(s, &end);
  return end != s && *end == '\0' && isfinite(*out);
}

static int parse_int(const char *s, int64_t *out) {
  char *end;
  long long v = strtoll(s, &end, 10);
  *out = (int64_t)v;
  return end != s && *end == '\0';
}

static int parse_scheme(const char *s, int *scheme) {
  if (strcmp(s, "hybrid") == 0) *scheme = ND_SCHEME_HYBRID;
  else if (strcmp(s, "theta") == 0) *scheme = ND_SCHEME_THETA;
  else if (strcmp(s, "newmark") == 0) *scheme = ND_SCHEME_NEWMARK;
  else return 0;
  return 1;
}

/* Returns 0 to run, 1 after --help, 2 on a usage error. */
static int parse_args(int argc, char **argv, options *o) {
  double theta = 0.5, beta = 0.25, gamma = 0.5;
  *o = (options){ND_SCHEME_HYBRID, {0, 0}, 1, 1.0, 0.2, 40, 0.0, 3.0, 0, 0, NULL};
  for (int i = 1; i < argc; ++i) {
    const char *arg = argv[i];
    if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
      usage(stdout, argv[0]);
      return 1;
    }
    if (strcmp(arg, "--quiet") == 0) {
      o->quiet = 1;
      continue;
    }
    if (strncmp(arg, "--", 2) != 0) { /* the scheme as a bare word */
      if (!parse_scheme(arg, &o->scheme)) goto bad_value;
      continue;
    }
    /* --key value or --key=value */
    char key[32];
    const char *val;
    const char *eq = strchr(arg, '=');
    size_t klen = eq ? (size_t)(eq - arg) : strlen(arg);
    if (klen >= sizeof key) goto bad_key;
    memcpy(key, arg, klen);
    key[klen] = '\0';
    if (eq) {
      val = eq + 1;
    } else {
      if (i + 1 >= argc) {
        fprintf(stderr, "%s: %s needs a value\n", argv[0], key);
        return 2;
      }
      val = argv[++i];
    }
    int64_t iv = -1;
    int ok;
    if (strcmp(key, "--scheme") == 0) ok = parse_scheme(val, &o->scheme);
    else if (strcmp(key, "--theta-param") == 0) ok = parse_double(val, &theta);
    else if (strcmp(key, "--beta") == 0) ok = parse_double(val, &beta);
    else if (strcmp(key, "--gamma") == 0) ok = parse_double(val, &gamma);
    else if (strcmp(key, "--Theta") == 0) ok = parse_double(val, &o->Theta);
    else if (strcmp(key, "--gamma0") == 0) ok = parse_double(val, &o->gamma0);
    else if (strcmp(key, "--tau") == 0) ok = parse_double(val, &o->tau) && o->tau > 0;
    else if (strcmp(key, "--T") == 0) ok = parse_double(val, &o->T) && o->T > 0;
    else if (strcmp(key, "--nx") == 0) ok = parse_int(val, &o->nx) && o->nx >= 1 && o->nx <= 100000000;
    else if (strcmp(key, "--csv") == 0) {
      o->csv = val;
      ok = *val != '\0';
    } else if (strcmp(key, "--degree") == 0) {
      ok = parse_int(val, &iv) && (iv == 1 || iv == 2);
      o->degree = (int)iv;
    } else if (strcmp(key, "--lumped") == 0) {
      ok = parse_int(val, &iv) && (iv == 0 || iv == 1);
      o->lumped = (int)iv;
    } else {
      goto bad_key;
    }
    if (!ok) {
      arg = val;
      goto bad_value;
    }
    continue;
  bad_key:
    fprintf(stderr, "%s: unknown option %s (try --help)\n", argv[0], arg);
    return 2;
  bad_value:
    fprintf(stderr, "%s: bad value '%s' (try --help)\n", argv[0], arg);
    return 2;
  }
  if (o->tau <= 0) o->tau = 0.5 / (double)o->nx;
  if (o->scheme == ND_SCHEME_THETA) o->params[0] = theta;
  if (o->scheme == ND_SCHEME_NEWMARK) {
    o->params[0] = beta;
    o->params[1] = gamma;
  }
  if (llround(o->T / o->tau) < 1) {
    fprintf(stderr, "%s: T/tau rounds to zero steps\n", argv[0]);
    return 2;
  }
  return 0;
}

static const char *scheme_name(int scheme) {
  return scheme == ND_SCHEME_HYBRID ? "hybrid" : scheme == ND_SCHEME_THETA ? "theta" : "newmark";
}

/* ---- the problem -------------------------------------------------------- */

static int check(int status) {
  if (status != ND_OK) fprintf(stderr, "bar1d: %s\n", nd_last_error());
  return status != ND_OK;
}

enum { CLAMPED = 1, CONTACT = 2 };

/* Mesh, regions, material, contact, scheme and initial state u0 = (1-x)/2.
   Fills the sorted grid. Returns non-zero on failure (*p may need freeing). */
static int setup(const options *o, nd_problem *p, grid *g) {
  nd_mesh mesh = NULL;
  const double lo_d = 0.5, hi_d = 1.5, lo_c = -0.5, hi_c = 0.5, zero = 0.0, up = 1.0;
  int fail = check(nd_mesh_create_interval(o->nx, 0.0, 1.0, &mesh)) ||
             check(nd_mesh_mark_boundary_box(mesh, CLAMPED, &lo_d, &hi_d)) ||
             check(nd_mesh_mark_boundary_box(mesh, CONTACT, &lo_c, &hi_c)) ||
             check(nd_problem_create(mesh, o->degree, p));
  nd_mesh_destroy(&mesh); /* the problem keeps its own copy */
  if (fail) return 1;
  if (check(nd_problem_set_material(*p, 1.0, 0.0, 1.0)) || check(nd_problem_set_dirichlet(*p, CLAMPED)) ||
      check(nd_problem_set_contact_plane(*p, CONTACT, &zero, &up)) ||
      check(nd_problem_set_nitsche(*p, o->Theta, o->gamma0)) ||
      check(nd_problem_set_scheme(*p, o->scheme, o->params)) ||
      check(nd_problem_set_mass_lumping(*p, o->lumped)) || check(nd_problem_set_timestep(*p, o->tau)))
    return 1;

  int64_t n_nodes = 0;
  if (check(nd_problem_get_node_count(*p, &n_nodes))) return 1;
  double *x = malloc((size_t)n_nodes * sizeof *x);
  double *u0 = malloc((size_t)n_nodes * sizeof *u0);
  double *v0 = calloc((size_t)n_nodes, sizeof *v0); /* the bar starts at rest */
  fail = !x || !u0 || !v0;
  if (fail) fprintf(stderr, "bar1d: out of memory\n");
  if (!fail) fail = check(nd_problem_get_node_coordinates(*p, n_nodes, x));
  if (!fail && grid_init(g, o->degree, o->nx, x, n_nodes)) {
    fprintf(stderr, "bar1d: expected %lld FE nodes, got %lld (or out of memory)\n",
            (long long)(o->nx * o->degree + 1), (long long)n_nodes);
    fail = 1;
  }
  if (!fail) {
    for (int64_t i = 0; i < n_nodes; ++i) u0[i] = 0.5 * (1 - x[i]);
    fail = check(nd_problem_set_initial_state(*p, n_nodes, u0, v0));
  }
  int64_t n_contact = 0;
  if (!fail) fail = check(nd_problem_get_contact_point_count(*p, &n_contact));
  if (!fail && n_contact != 1) {
    fprintf(stderr, "bar1d: expected 1 contact point, got %lld\n", (long long)n_contact);
    fail = 1;
  }
  free(x);
  free(u0);
  free(v0);
  return fail;
}

/* ---- the run ------------------------------------------------------------ */

typedef struct {
  norm_acc norms;
  double E_min, E_max, ET_min, ET_max;
  double newton_sum;
  double t_setup, t_loop, t_eval; /* seconds */
  int64_t steps;
} run_summary;

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Samples time level n: errors, energies, the CSV row and the trace line. */
static int sample(nd_problem p, const grid *g, double *U, double *V, int64_t n, const options *o,
                  run_summary *rs, FILE *csv, int64_t trace_every) {
  double lam, E, ET;
  if (check(nd_get_field(p, ND_FIELD_DISPLACEMENT, g->n_nodes, U)) ||
      check(nd_get_field(p, ND_FIELD_VELOCITY, g->n_nodes, V)) || check(nd_get_contact_pressure(p, 1, &lam)) ||
      check(nd_get_scalar(p, ND_ENERGY_MECHANICAL, &E)) || check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &ET)))
    return 1;
  const double t = (double)n * o->tau;
  const phase ph = phase_at(t);
  const space_norms s = norms_at(g, U, V, ph);
  const double sigma = exact_stress(ph);
  const double w = (n == 0 || n == rs->steps) ? 0.5 * o->tau : o->tau; /* trapezoidal weight */
  acc_add(&rs->norms, &s, lam - sigma, sigma, w);
  rs->E_min = n == 0 ? E : fmin(rs->E_min, E);
  rs->E_max = n == 0 ? E : fmax(rs->E_max, E);
  rs->ET_min = n == 0 ? ET : fmin(rs->ET_min, ET);
  rs->ET_max = n == 0 ? ET : fmax(rs->ET_max, ET);
  const double u0h = U[g->id[0]], v0h = V[g->id[0]]; /* sorted node 0 is x = 0 */
  if (csv) fprintf(csv, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", t, u0h, v0h, lam, E, ET);
  if (!o->quiet && (n % trace_every == 0 || n == rs->steps))
    printf("%8.4f %12.5e %12.5e %12.5e %12.5e %12.8f %12.8f\n", t, u0h, exact_at(ph, 0.0).u + 0.0, lam, sigma + 0.0, E,
           ET); /* + 0.0: print -0 as 0 */
  return 0;
}

static int run(const options *o, run_summary *rs) {
  nd_problem p = NULL;
  grid g = {0, 0, 0, NULL, NULL};
  double *U = NULL, *V = NULL;
  FILE *csv = NULL;
  int fail = 0;
  memset(rs, 0, sizeof *rs);
  rs->steps = llround(o->T / o->tau);

  double t0 = now();
  fail = setup(o, &p, &g);
  rs->t_setup = now() - t0;
  if (!fail) {
    U = malloc((size_t)g.n_nodes * sizeof *U);
    V = malloc((size_t)g.n_nodes * sizeof *V);
    fail = !U || !V;
    if (fail) fprintf(stderr, "bar1d: out of memory\n");
  }
  if (!fail && o->csv) {
    csv = fopen(o->csv, "w");
    fail = !csv;
    if (fail) fprintf(stderr, "bar1d: cannot open %s for writing\n", o->csv);
    else fprintf(csv, "t,u(0),v(0),contact_stress,E,E_Theta\n");
  }
  const int64_t trace_every = llround(0.25 / o->tau) > 0 ? llround(0.25 / o->tau) : 1;
  if (!fail && !o->quiet)
    printf("%8s %12s %12s %12s %12s %12s %12s\n", "t", "u(0)", "exact", "stress", "exact", "E", "E_Theta");

  for (int64_t n = 0; !fail && n <= rs->steps; ++n) {
    if (n > 0) {
      t0 = now();
      fail = check(nd_step(p)); /* no monitor is set, so ND_MONITOR_STOP cannot come */
      rs->t_loop += now() - t0;
      double it = 0;
      if (!fail) fail = check(nd_get_scalar(p, ND_NEWTON_ITERATIONS, &it));
      rs->newton_sum += it;
      if (fail) {
        fprintf(stderr, "bar1d: step %lld of %lld failed\n", (long long)n, (long long)rs->steps);
        break;
      }
    }
    t0 = now();
    fail = sample(p, &g, U, V, n, o, rs, csv, trace_every);
    rs->t_eval += now() - t0;
  }

  if (csv && fclose(csv) != 0) {
    fprintf(stderr, "bar1d: error writing %s\n", o->csv);
    fail = 1;
  }
  free(U);
  free(V);
  grid_free(&g);
  nd_problem_destroy(&p);
  return fail;
}

static void print_summary(const options *o, const run_summary *rs) {
  printf("scheme=%s", scheme_name(o->scheme));
  if (o->scheme == ND_SCHEME_THETA) printf("(theta=%g)", o->params[0]);
  if (o->scheme == ND_SCHEME_NEWMARK) printf("(beta=%g,gamma=%g)", o->params[0], o->params[1]);
  printf(" degree=%d Theta=%g gamma0=%g nx=%lld tau=%g T=%g steps=%lld%s\n", o->degree, o->Theta, o->gamma0,
         (long long)o->nx, o->tau, (double)rs->steps * o->tau, (long long)rs->steps, o->lumped ? " lumped" : "");
  for (int i = 0; i < N_NORMS; ++i) {
    const int relative = rs->norms.ref[i] > 0;
    printf("%s error  %-18s %.6e%s\n", relative ? "rel." : "abs.", norm_names[i], acc_relative(&rs->norms, i),
           relative ? "" : "  (exact norm is 0)");
  }
  printf("E        min %.8f max %.8f    E_Theta min %.8f max %.8f   (exact E = 0.125)\n", rs->E_min, rs->E_max,
         rs->ET_min, rs->ET_max);
  printf("Newton iterations per step (mean) %.3f\n", rs->newton_sum / (double)rs->steps);
  printf("run time: setup %.4f s, time loop %.4f s (%.4f ms/step; nd_step calls only, lazy first-step setup included), "
         "error evaluation %.4f s\n",
         rs->t_setup, rs->t_loop, 1e3 * rs->t_loop / (double)rs->steps, rs->t_eval);
}

int main(int argc, char **argv) {
  options o;
  const int parsed = parse_args(argc, argv, &o);
  if (parsed) return parsed == 1 ? 0 : 2;
  if (!o.quiet) {
    const double h = 1.0 / (double)o.nx;
    printf("bar1d: 1D bar against its exact solution (DESIGN §7), libnitschedyn %s\n", ND_VERSION_STRING);
    printf("Omega=(0,1) rho=1 E=1 clamped at x=1, obstacle at x=0; u0=(1-x)/2 v0=0; exact period 3, E=1/8\n");
    printf("h=%g gamma=gamma0*h=%g tau/h=%g mass=%s\n", h, o.gamma0 * h, o.tau / h,
           o.lumped ? "lumped" : "consistent");
  }
  run_summary rs;
  if (run(&o, &rs)) return 1;
  print_summary(&o, &rs);
  return 0;
}
