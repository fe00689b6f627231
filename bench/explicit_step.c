/* An explicit step's cost: the central difference (Newmark(0, 1/2)) with
 * lumped mass on the disk or the ball of docs/design.md §7 (Theta = 1, gamma0 =
 * 1e-3), tau half the estimated critical step. Median wall time of a step
 * over STEPS steps after the first, and the passes over the contact points
 * they made (ND_STAT_CONTACT_EVALUATIONS).
 *   explicit_step DIM MESH DEGREE STEPS */
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

static int by_value(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

static int failed(void) {
  fprintf(stderr, "explicit_step: %s\n", nd_last_error());
  return 1;
}

int main(int argc, char **argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: %s DIM MESH DEGREE STEPS\n", argv[0]);
    return 2;
  }
  const int dim = atoi(argv[1]), degree = atoi(argv[3]), steps = atoi(argv[4]);
  const double central[2] = {0, 0.5};
  nd_problem p = NULL;
  double tc = 0, passes0 = 0, passes = 0;
  if (steps < 1) return 2;
  if (drop_scene_create(dim, argv[2], degree, ND_SCHEME_NEWMARK, central, 1.0, 1e-3, 1e-3, ND_SOLVER_AUTO, &p) !=
          ND_OK ||
      nd_problem_set_mass_lumping(p, 1) != ND_OK || nd_problem_estimate_critical_timestep(p, &tc) != ND_OK ||
      nd_problem_set_timestep(p, 0.5 * tc) != ND_OK || nd_step(p) != ND_OK ||
      nd_get_scalar(p, ND_STAT_CONTACT_EVALUATIONS, &passes0) != ND_OK)
    return failed();
  double *t = malloc(sizeof(double) * (size_t)steps);
  if (!t) return 1;
  for (int k = 0; k < steps; ++k) {
    const double t0 = now();
    if (nd_step(p) != ND_OK) return failed();
    t[k] = now() - t0;
  }
  if (nd_get_scalar(p, ND_STAT_CONTACT_EVALUATIONS, &passes) != ND_OK) return failed();
  qsort(t, (size_t)steps, sizeof(double), by_value);
  int64_t points = 0;
  if (nd_problem_get_contact_point_count(p, &points) != ND_OK) return failed();
  printf("%s P%d: %lld contact points, tau = %.3g, median explicit step %.4f ms, %.2f passes over the points a step\n",
         argv[2], degree, (long long)points, 0.5 * tc, 1e3 * t[steps / 2], (passes - passes0) / steps);
  free(t);
  nd_problem_destroy(&p);
  return 0;
}
