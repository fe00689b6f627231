/*
 * bar1d - the 1D bar of docs/design.md §7 through the public API of libnitschedyn,
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
#include "step_count.h"

/* ---- options ------------------------------------------------------------ */

typedef struct {
  int scheme;        /* ND_SCHEME_* */
  double params[2];  /* theta, beta and gamma, or rho_inf */
  int degree;
  double Theta, gamma0;
  int64_t nx;
  double tau, T; /* tau <= 0: default h/2 */
  int lumped, quiet;
  int redistribute; /* mass redistribution away from the contact node */
  int applied;      /* the stress is the pressure the step applied, not lambda at t^n */
  const char *csv;
  /* the work-precision report (tools/report): medians of repeated runs, a
     summary also at t = at, one CSV row per summary */
  int repeat;
  double at; /* <= 0: none */
  const char *row, *study;
  int critical_guard; /* refuse an explicit step above the estimated critical step */
} options;

static void usage(FILE *f, const char *prog) {
  fprintf(f,
          "usage: %s [SCHEME] [options]\n"
          "The 1D bar with an exact solution (docs/design.md §7), relative errors and energies.\n"
          "  SCHEME, or --scheme SCHEME   hybrid (default) | theta | newmark | galpha\n"
          "  --theta-param X   theta of the theta-scheme (default 0.5)\n"
          "  --rho-inf X       generalized-alpha's rho_inf in [0,1] (default 0.8)\n"
          "  --beta X          Newmark beta (default 0.25)\n"
          "  --gamma X         Newmark gamma (default 0.5)\n"
          "  --degree 1|2      polynomial degree (default 1)\n"
          "  --Theta X         Nitsche Theta (default 1)\n"
          "  --gamma0 X        Nitsche gamma0, gamma = gamma0 h (default 0.2)\n"
          "  --nx N            number of cells (default 40)\n"
          "  --tau X           time step (default h/2 = 1/(2 nx))\n"
          "  --T X             final time (default 3); steps = round(T/tau)\n"
          "  --lumped 0|1      lumped mass (default 0)\n"
          "  --redistribute 0|1  mass redistribution off the contact node (default 0)\n"
          "  --pressure end|applied  the contact stress: lambda at t^n (default) or\n"
          "                    the pressure the step applied\n"
          "  --critical-guard 0|1  refuse an explicit step above the estimated critical\n"
          "                    step (default 1; 0 runs e.g. CFL 1, tau = h, where the\n"
          "                    estimate's safety margin is below the exact step)\n"
          "  --csv FILE        write t,u(0),v(0),contact_stress,E,E_Theta per time level\n"
          "  --quiet           print the summary only\n"
          "  --repeat K        run K times: errors from the first, median times (default 1)\n"
          "  --at X            also summarize the run at t = X < T (same steps, norms up to X)\n"
          "  --row FILE        append one CSV summary row per summary time to FILE\n"
          "  --study NAME      the study column of those rows (default bar)\n"
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
  else if (strcmp(s, "galpha") == 0) *scheme = ND_SCHEME_GENERALIZED_ALPHA;
  else return 0;
  return 1;
}

/* Returns 0 to run, 1 after --help, 2 on a usage error. */
static int parse_args(int argc, char **argv, options *o) {
  double theta = 0.5, beta = 0.25, gamma = 0.5, rho_inf = 0.8;
  *o = (options){ND_SCHEME_HYBRID, {0, 0}, 1, 1.0, 0.2, 40, 0.0, 3.0, 0, 0, 0, 0, NULL, 1, 0.0, NULL, "bar", 1};
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
    else if (strcmp(key, "--rho-inf") == 0) ok = parse_double(val, &rho_inf);
    else if (strcmp(key, "--gamma") == 0) ok = parse_double(val, &gamma);
    else if (strcmp(key, "--Theta") == 0) ok = parse_double(val, &o->Theta);
    else if (strcmp(key, "--gamma0") == 0) ok = parse_double(val, &o->gamma0);
    else if (strcmp(key, "--tau") == 0) ok = parse_double(val, &o->tau) && o->tau > 0;
    else if (strcmp(key, "--T") == 0) ok = parse_double(val, &o->T) && o->T > 0;
    else if (strcmp(key, "--nx") == 0) ok = parse_int(val, &o->nx) && o->nx >= 1 && o->nx <= 100000000;
    else if (strcmp(key, "--at") == 0) ok = parse_double(val, &o->at) && o->at > 0;
    else if (strcmp(key, "--csv") == 0) {
      o->csv = val;
      ok = *val != '\0';
    } else if (strcmp(key, "--row") == 0) {
      o->row = val;
      ok = *val != '\0';
    } else if (strcmp(key, "--study") == 0) {
      o->study = val;
      ok = *val != '\0' && strpbrk(val, ",\"\n") == NULL;
    } else if (strcmp(key, "--repeat") == 0) {
      ok = parse_int(val, &iv) && iv >= 1 && iv <= 1000;
      o->repeat = (int)iv;
    } else if (strcmp(key, "--degree") == 0) {
      ok = parse_int(val, &iv) && (iv == 1 || iv == 2);
      o->degree = (int)iv;
    } else if (strcmp(key, "--lumped") == 0) {
      ok = parse_int(val, &iv) && (iv == 0 || iv == 1);
      o->lumped = (int)iv;
    } else if (strcmp(key, "--redistribute") == 0) {
      ok = parse_int(val, &iv) && (iv == 0 || iv == 1);
      o->redistribute = (int)iv;
    } else if (strcmp(key, "--critical-guard") == 0) {
      ok = parse_int(val, &iv) && (iv == 0 || iv == 1);
      o->critical_guard = (int)iv;
    } else if (strcmp(key, "--pressure") == 0) {
      ok = strcmp(val, "end") == 0 || strcmp(val, "applied") == 0;
      o->applied = strcmp(val, "applied") == 0;
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
  if (o->scheme == ND_SCHEME_GENERALIZED_ALPHA) o->params[0] = rho_inf;
  if (o->scheme == ND_SCHEME_NEWMARK) {
    o->params[0] = beta;
    o->params[1] = gamma;
  }
  const int64_t steps = nd_step_count(o->T, o->tau); /* (a double beyond int64_t: undefined in a cast) */
  if (steps < 0) {
    fprintf(stderr, "%s: T/tau = %g/%g is not a number of steps (0 to 2^63 - 1)\n", argv[0], o->T, o->tau);
    return 2;
  }
  if (steps < 1) {
    fprintf(stderr, "%s: T/tau rounds to zero steps\n", argv[0]);
    return 2;
  }
  if (o->at > 0 && (nd_step_count(o->at, o->tau) < 1 || nd_step_count(o->at, o->tau) >= steps)) {
    fprintf(stderr, "%s: --at must be at least one step and less than T\n", argv[0]);
    return 2;
  }
  return 0;
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
      check(nd_problem_set_mass_lumping(*p, o->lumped)) ||
      check(nd_problem_set_mass_redistribution(*p, o->redistribute)) || check(nd_problem_set_timestep(*p, o->tau)) ||
      check(nd_problem_set_guard(*p, ND_GUARD_CRITICAL_TIMESTEP, o->critical_guard)))
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

/* What is known of a run at one summary time. */
typedef struct {
  norm_acc norms;
  double E_min, E_max, ET_min, ET_max;
  double drift;   /* max |E_Theta - E_Theta(0) - W| / E(0) */
  double newton;  /* Newton iterations of all steps */
  double t_loop;  /* seconds in nd_step */
  int64_t steps;
} summary;

typedef struct {
  summary end, at; /* at T, and at --at (when given) */
  double t_setup, t_eval, E0, ET0;
  int failed_step; /* 0, or the step that failed */
  char error[256];
} run_summary;

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Samples time level n into rs->end, closing the --at summary at its step:
   errors, energies, the CSV row and the trace line. */
static int sample(nd_problem p, const grid *g, double *U, double *V, int64_t n, int64_t n_at, const options *o,
                  run_summary *rs, FILE *csv, int64_t trace_every) {
  double lam, E, ET, W;
  if (check(nd_get_field(p, ND_FIELD_DISPLACEMENT, g->n_nodes, U)) ||
      check(nd_get_field(p, ND_FIELD_VELOCITY, g->n_nodes, V)) ||
      check((o->applied ? nd_get_contact_pressure_applied : nd_get_contact_pressure)(p, 1, &lam)) ||
      check(nd_get_scalar(p, ND_ENERGY_MECHANICAL, &E)) || check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &ET)) ||
      check(nd_get_scalar(p, ND_WORK, &W)))
    return 1;
  const double t = (double)n * o->tau;
  const phase ph = phase_at(t);
  const space_norms s = norms_at(g, U, V, ph);
  /* the applied pressure is the step's (an impulse over tau): compared with
     the exact stress's mean over the step (midpoint rule on 64 parts; the
     exact stress is piecewise smooth in time) */
  double sigma = exact_stress(ph);
  if (o->applied && n > 0) {
    enum { PARTS = 64 };
    sigma = 0;
    for (int k = 0; k < PARTS; ++k) sigma += exact_stress(phase_at(t - o->tau + (k + 0.5) * o->tau / PARTS)) / PARTS;
  }
  summary *e = &rs->end;
  if (n == 0) {
    rs->E0 = E;
    rs->ET0 = ET;
    e->E_min = e->E_max = E;
    e->ET_min = e->ET_max = ET;
  }
  e->E_min = fmin(e->E_min, E);
  e->E_max = fmax(e->E_max, E);
  e->ET_min = fmin(e->ET_min, ET);
  e->ET_max = fmax(e->ET_max, ET);
  e->drift = fmax(e->drift, fabs(ET - rs->ET0 - W) / rs->E0);
  if (n == n_at) { /* the --at summary ends here: its last trapezoidal weight is a half */
    rs->at = *e;
    acc_add(&rs->at.norms, &s, lam - sigma, sigma, 0.5 * o->tau);
  }
  const double w = (n == 0 || n == e->steps) ? 0.5 * o->tau : o->tau; /* trapezoidal weight */
  acc_add(&e->norms, &s, lam - sigma, sigma, w);
  const double u0h = U[g->id[0]], v0h = V[g->id[0]]; /* sorted node 0 is x = 0 */
  if (csv) fprintf(csv, "%.10g,%.10g,%.10g,%.10g,%.10g,%.10g\n", t, u0h, v0h, lam, E, ET);
  if (!o->quiet && (n % trace_every == 0 || n == e->steps))
    printf("%8.4f %12.5e %12.5e %12.5e %12.5e %12.8f %12.8f\n", t, u0h, exact_at(ph, 0.0).u + 0.0, lam, sigma + 0.0, E,
           ET); /* + 0.0: print -0 as 0 */
  return 0;
}

/* One run. With evaluate = 0 only the steps are made and timed (the repeated
   runs of --repeat). Returns non-zero when the set-up failed; a failing step
   is recorded in rs->failed_step and rs->error and ends the run. */
static int run(const options *o, int evaluate, run_summary *rs) {
  nd_problem p = NULL;
  grid g = {0, 0, 0, NULL, NULL};
  double *U = NULL, *V = NULL;
  FILE *csv = NULL;
  int fail = 0;
  memset(rs, 0, sizeof *rs);
  rs->end.steps = nd_step_count(o->T, o->tau); /* (both checked by parse) */
  const int64_t n_at = o->at > 0 ? nd_step_count(o->at, o->tau) : -1;

  double t0 = now();
  fail = setup(o, &p, &g) || check(nd_problem_setup(p)); /* the first step's set-up, timed here */
  rs->t_setup = now() - t0;
  if (!fail && evaluate) {
    U = malloc((size_t)g.n_nodes * sizeof *U);
    V = malloc((size_t)g.n_nodes * sizeof *V);
    fail = !U || !V;
    if (fail) fprintf(stderr, "bar1d: out of memory\n");
  }
  if (!fail && evaluate && o->csv) {
    csv = fopen(o->csv, "w");
    fail = !csv;
    if (fail) fprintf(stderr, "bar1d: cannot open %s for writing\n", o->csv);
    else fprintf(csv, "t,u(0),v(0),contact_stress,E,E_Theta\n");
  }
  const int64_t trace_every = nd_step_count(0.25, o->tau) > 0 ? nd_step_count(0.25, o->tau) : 1;
  if (!fail && evaluate && !o->quiet)
    printf("%8s %12s %12s %12s %12s %12s %12s\n", "t", "u(0)", "exact", "stress", "exact", "E", "E_Theta");

  for (int64_t n = 0; !fail && n <= rs->end.steps; ++n) {
    if (n > 0) {
      t0 = now();
      const int status = nd_step(p); /* no monitor is set, so ND_MONITOR_STOP cannot come */
      rs->end.t_loop += now() - t0;
      if (status != ND_OK) {
        rs->failed_step = (int)n;
        snprintf(rs->error, sizeof rs->error, "%s", nd_last_error());
        if (!o->quiet || evaluate)
          fprintf(stderr, "bar1d: step %lld of %lld failed: %s\n", (long long)n, (long long)rs->end.steps, rs->error);
        break;
      }
      double it = 0;
      fail = check(nd_get_scalar(p, ND_NEWTON_ITERATIONS, &it));
      rs->end.newton += it;
    }
    if (evaluate) {
      t0 = now();
      fail = fail || sample(p, &g, U, V, n, n_at, o, rs, csv, trace_every);
      rs->t_eval += now() - t0;
    }
    if (n == n_at) {
      rs->at.steps = n;
      rs->at.t_loop = rs->end.t_loop;
      rs->at.newton = rs->end.newton;
    }
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

static int cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, int n) {
  qsort(v, (size_t)n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void scheme_label(const options *o, char *buf, size_t size) {
  if (o->scheme == ND_SCHEME_THETA) snprintf(buf, size, "theta(%g)", o->params[0]);
  else if (o->scheme == ND_SCHEME_NEWMARK) snprintf(buf, size, "newmark(%g,%g)", o->params[0], o->params[1]);
  else if (o->scheme == ND_SCHEME_GENERALIZED_ALPHA) snprintf(buf, size, "galpha(%g)", o->params[0]);
  else snprintf(buf, size, "hybrid");
}

static void print_summary(const options *o, const run_summary *rs, const summary *e, double t_setup,
                          double t_loop, int repeat) {
  char label[64];
  scheme_label(o, label, sizeof label);
  printf("scheme=%s degree=%d Theta=%g gamma0=%g nx=%lld tau=%g T=%g steps=%lld%s\n", label, o->degree, o->Theta,
         o->gamma0, (long long)o->nx, o->tau, (double)e->steps * o->tau, (long long)e->steps,
         o->lumped ? " lumped" : "");
  if (o->redistribute || o->applied)
    printf("mass %s, contact stress %s\n", o->redistribute ? "redistributed" : "as assembled",
           o->applied ? "applied by the step" : "lambda at t^n");
  for (int i = 0; i < N_NORMS; ++i) {
    const int relative = e->norms.ref[i] > 0;
    printf("%s error  %-18s %.6e%s\n", relative ? "rel." : "abs.", norm_names[i], acc_relative(&e->norms, i),
           relative ? "" : "  (exact norm is 0)");
  }
  printf("E        min %.8f max %.8f    E_Theta min %.8f max %.8f   (exact E = 0.125)\n", e->E_min, e->E_max,
         e->ET_min, e->ET_max);
  printf("energy drift max|E_Theta - E_Theta(0) - W|/E(0) %.3e\n", e->drift);
  printf("Newton iterations per step (mean) %.3f\n", e->newton / (double)e->steps);
  printf("run time%s: setup %.4f s, time loop %.4f s (%.4f ms/step; nd_step calls only), error evaluation %.4f s\n",
         repeat > 1 ? " (medians of the runs)" : "", t_setup, t_loop, 1e3 * t_loop / (double)e->steps, rs->t_eval);
}

/* One CSV row (tools/report reads them); a failed run has its error as status. */
static int append_row(const options *o, const run_summary *rs, const summary *e, double t_setup, double t_loop,
                      int repeat) {
  FILE *f = fopen(o->row, "a");
  if (!f) {
    fprintf(stderr, "bar1d: cannot open %s for appending\n", o->row);
    return 1;
  }
  if (ftell(f) == 0)
    fprintf(f, "code,study,scheme,degree,Theta,gamma0,lumped,redistributed,pressure,nx,tau,T,steps,setup_s,loop_s,repeats,newton_its,"
               "energy_drift,e_linf_l2_u,e_linf_h1_u,e_linf_l2_v,e_l2_l2_u,e_l2_h1_u,e_l2_l2_v,e_l2_stress,status\n");
  char label[64];
  scheme_label(o, label, sizeof label);
  fprintf(f, "nitschedyn,%s,\"%s\",%d,%g,%g,%d,%d,%s,%lld,%.10g,%.10g,%lld,", o->study, label, o->degree, o->Theta,
          o->gamma0, o->lumped, o->redistribute, o->applied ? "applied" : "end", (long long)o->nx, o->tau, (double)e->steps * o->tau, (long long)e->steps);
  if (rs->failed_step) { /* the step that failed, without commas or quotes */
    char msg[320];
    snprintf(msg, sizeof msg, "step %d: %s", rs->failed_step, rs->error);
    for (char *c = msg; *c; ++c)
      if (*c == ',' || *c == '"' || *c == '\n') *c = ';';
    fprintf(f, "%.6g,,%d,,,,,,,,,,%s\n", t_setup, repeat, msg);
  } else {
    fprintf(f, "%.6g,%.6g,%d,%.0f,%.6g", t_setup, t_loop, repeat, e->newton, e->drift);
    for (int i = 0; i < N_NORMS; ++i) fprintf(f, ",%.10g", acc_relative(&e->norms, i));
    fprintf(f, ",ok\n");
  }
  return fclose(f) != 0;
}

int main(int argc, char **argv) {
  options o;
  const int parsed = parse_args(argc, argv, &o);
  if (parsed) return parsed == 1 ? 0 : 2;
  if (!o.quiet) {
    const double h = 1.0 / (double)o.nx;
    printf("bar1d: 1D bar against its exact solution (docs/design.md §7), libnitschedyn %s\n", ND_VERSION_STRING);
    printf("Omega=(0,1) rho=1 E=1 clamped at x=1, obstacle at x=0; u0=(1-x)/2 v0=0; exact period 3, E=1/8\n");
    printf("h=%g gamma=gamma0*h=%g tau/h=%g mass=%s\n", h, o.gamma0 * h, o.tau / h,
           o.lumped ? "lumped" : "consistent");
  }
  /* the first run evaluates the errors; the others only time the steps */
  run_summary rs, timing;
  double *setup_s = malloc(sizeof(double) * (size_t)o.repeat * 3), *loop_s = setup_s + o.repeat,
         *at_s = setup_s + 2 * o.repeat;
  if (!setup_s) return 1;
  int fail = run(&o, 1, &rs);
  setup_s[0] = rs.t_setup, loop_s[0] = rs.end.t_loop, at_s[0] = rs.at.t_loop;
  for (int k = 1; !fail && !rs.failed_step && k < o.repeat; ++k) {
    fail = run(&o, 0, &timing) || timing.failed_step;
    setup_s[k] = timing.t_setup, loop_s[k] = timing.end.t_loop, at_s[k] = timing.at.t_loop;
  }
  const int runs = rs.failed_step ? 1 : o.repeat;
  const double t_setup = median(setup_s, runs), t_loop = median(loop_s, runs), t_at = median(at_s, runs);
  free(setup_s);
  if (fail) return 1;
  const int has_at = o.at > 0 && !rs.failed_step;
  if (!rs.failed_step) {
    if (has_at) print_summary(&o, &rs, &rs.at, t_setup, t_at, runs);
    print_summary(&o, &rs, &rs.end, t_setup, t_loop, runs);
  }
  if (o.row) {
    if (has_at && append_row(&o, &rs, &rs.at, t_setup, t_at, runs)) return 1;
    if (append_row(&o, &rs, &rs.end, t_setup, t_loop, runs)) return 1;
  }
  return rs.failed_step ? 1 : 0;
}
