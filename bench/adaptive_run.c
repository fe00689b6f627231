/* Adaptive time steps against fixed ones on the drop scene of docs/design.md
 * §7 (the disk or the ball; hybrid scheme, Theta = 1, automatic gamma0):
 * each run to T prints its steps, rejected tries, factorizations, wall time
 * and its error at T against a reference run of fixed step tau_ref (the
 * same mesh: the time error alone), max over the DOFs of |U - U_ref| over
 * max |U_ref|. One run a line; all measured in one process, one after the
 * other (the machine's noise is common to them).
 *   adaptive_run DIM MESH DEGREE T TAU_REF TAU [TOLERANCE ...]
 * TAU: the fixed runs' step (also halved twice) and the adaptive runs'
 * tau_max; each TOLERANCE one adaptive run (tau_min = 1e-4 TAU). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "drop_scene.h"
#include "nitschedyn.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double get(nd_problem p, int key) {
  double x = 0;
  nd_get_scalar(p, key, &x);
  return x;
}

/* to T: the last step cut to end there */
static int run(int dim, const char *mesh, int degree, double T, double tau, double tolerance, double *U,
               int64_t n, double *seconds) {
  nd_problem p = NULL;
  if (drop_scene_create(dim, mesh, degree, ND_SCHEME_HYBRID, NULL, 1.0, 0.0, tau, ND_SOLVER_AUTO, &p) != ND_OK)
    return 1;
  if (tolerance > 0 && nd_problem_set_adaptive_timestep(p, tolerance, 1e-4 * tau, tau) != ND_OK) return 1;
  const double t0 = now();
  double t = 0;
  while (T - t > 1e-9 * T) {
    const double next = get(p, ND_TIMESTEP);
    if (t + next > T) {
      if (tolerance > 0 && nd_problem_set_adaptive_timestep(p, 0, 0, 0) != ND_OK) return 1;
      if (nd_problem_set_timestep(p, T - t) != ND_OK) return 1;
    }
    if (nd_step(p) != ND_OK) return 1;
    t = get(p, ND_TIME);
  }
  *seconds = now() - t0;
  if (nd_get_field(p, ND_FIELD_DISPLACEMENT, n / dim, U) != ND_OK) return 1;
  if (tolerance >= 0)
    printf("%-10g %-9g %7.0f %8.0f %14.0f %9.3f", tolerance, tau, get(p, ND_STAT_STEPS_ACCEPTED),
           get(p, ND_STAT_STEPS_REJECTED), get(p, ND_STAT_FACTORIZATIONS), *seconds);
  nd_problem_destroy(&p);
  return 0;
}

int main(int argc, char **argv) {
  if (argc < 7) {
    fprintf(stderr, "usage: %s DIM MESH DEGREE T TAU_REF TAU [TOLERANCE ...]\n", argv[0]);
    return 2;
  }
  const int dim = atoi(argv[1]), degree = atoi(argv[3]);
  const double T = atof(argv[4]), tau_ref = atof(argv[5]), tau = atof(argv[6]);
  nd_problem p = NULL;
  int64_t nodes = 0;
  if (drop_scene_create(dim, argv[2], degree, ND_SCHEME_HYBRID, NULL, 1.0, 0.0, tau, ND_SOLVER_AUTO, &p) != ND_OK ||
      nd_problem_get_node_count(p, &nodes) != ND_OK) {
    fprintf(stderr, "adaptive_run: %s\n", nd_last_error());
    return 1;
  }
  nd_problem_destroy(&p);
  const int64_t n = nodes * dim;
  double *ref = malloc(sizeof(double) * (size_t)n), *U = malloc(sizeof(double) * (size_t)n), s = 0;
  if (!ref || !U) return 1;
  if (run(dim, argv[2], degree, T, tau_ref, -1, ref, n, &s)) {
    fprintf(stderr, "adaptive_run: the reference: %s\n", nd_last_error());
    return 1;
  }
  double scale = 0;
  for (int64_t i = 0; i < n; ++i) scale = fmax(scale, fabs(ref[i]));
  printf("# %s P%d, T = %g, reference tau = %g (%.2f s)\n", argv[2], degree, T, tau_ref, s);
  printf("%-10s %-9s %7s %8s %14s %9s %s\n", "tolerance", "tau", "steps", "rejected", "factorizations", "seconds",
         "error at T");
  const double fixed[3] = {tau, tau / 2, tau / 4};
  for (int k = 0; k < 3 + argc - 7; ++k) {
    const double tol = k < 3 ? 0 : atof(argv[7 + k - 3]), size = k < 3 ? fixed[k] : tau;
    if (run(dim, argv[2], degree, T, size, tol, U, n, &s)) {
      printf("%-10g %-9g failed: %s\n", tol, size, nd_last_error());
      continue;
    }
    double e = 0;
    for (int64_t i = 0; i < n; ++i) e = fmax(e, fabs(U[i] - ref[i]));
    printf(" %.3e\n", e / scale);
  }
  free(ref);
  free(U);
  return 0;
}
