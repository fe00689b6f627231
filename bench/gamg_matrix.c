/* Benchmark (not a test): the ball dropped on a plane, stepped side by side
 * with ND_SOLVER_PETSC_GAMG and CHOLMOD on one process, over the implicit
 * schemes, Theta = 1, 0, -1 and gamma0 from 1e-6 to 100: how GAMG's path
 * (the Newton tangent refactored, its multigrid hierarchy kept while it
 * serves, each step's solve started from the predictor) follows the direct
 * one where steps are stiff or refused. One CSV row per case: the statuses
 * where the runs stopped (0: all steps taken), the largest gaps of the
 * mechanical energy and the contact force relative to their largest values,
 * and GAMG's set-ups, tangents and Krylov iterations.
 *
 *   gamg_matrix MESH STEPS TAU      (e.g. examples/meshes/ball_h4.msh 60 0.25) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "drop_scene.h"
#include "nitschedyn.h"

static double get(nd_problem p, int key) {
  double x = 0;
  nd_get_scalar(p, key, &x);
  return x;
}

int main(int argc, char **argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: %s MESH STEPS TAU\n", argv[0]);
    return 2;
  }
  const int steps = atoi(argv[2]);
  const double tau = atof(argv[3]);
  const double thetas[] = {1, 0, -1}, gamma0s[] = {1e-6, 1e-3, 1, 100};
  const int schemes[] = {ND_SCHEME_HYBRID, ND_SCHEME_NEWMARK, ND_SCHEME_THETA, ND_SCHEME_GENERALIZED_ALPHA};
  const char *names[] = {"hybrid", "newmark", "theta1", "galpha"};
  const double params[4][2] = {{0.25, 0.5}, {0.25, 0.5}, {1.0, 0}, {0.8, 0}};
  printf("scheme,Theta,gamma0,steps,status_cholmod,status_gamg,energy_gap,force_gap,gamg_setups,tangents,"
         "krylov_iterations\n");
  for (int s = 0; s < 4; ++s)
    for (int t = 0; t < 3; ++t)
      for (int g = 0; g < 4; ++g) {
        nd_problem direct = NULL, gamg = NULL;
        int sd = drop_scene_create(3, argv[1], 1, schemes[s], params[s], thetas[t], gamma0s[g], tau,
                                   ND_SOLVER_CHOLMOD, &direct);
        int sg = drop_scene_create(3, argv[1], 1, schemes[s], params[s], thetas[t], gamma0s[g], tau,
                                   ND_SOLVER_PETSC_GAMG, &gamg);
        double de = 0, df = 0, e_max = 0, f_max = 0;
        int k = 0;
        for (; k < steps && sd == ND_OK && sg == ND_OK; ++k) {
          sd = nd_step(direct);
          sg = nd_step(gamg);
          if (sd != ND_OK || sg != ND_OK) break;
          const double e = get(direct, ND_ENERGY_MECHANICAL), f = get(direct, ND_CONTACT_FORCE);
          de = fmax(de, fabs(e - get(gamg, ND_ENERGY_MECHANICAL)));
          df = fmax(df, fabs(f - get(gamg, ND_CONTACT_FORCE)));
          e_max = fmax(e_max, fabs(e));
          f_max = fmax(f_max, fabs(f));
        }
        printf("%s,%g,%g,%d,%d,%d,%.2e,%.2e,%.0f,%.0f,%.0f\n", names[s], thetas[t], gamma0s[g], k, sd, sg,
               e_max > 0 ? de / e_max : de, f_max > 0 ? df / f_max : df, get(gamg, ND_STAT_FACTORIZATIONS),
               get(gamg, ND_STAT_TANGENT_UPDATES), get(gamg, ND_STAT_KRYLOV_ITERATIONS));
        fflush(stdout);
        nd_problem_destroy(&direct);
        nd_problem_destroy(&gamg);
      }
  return 0;
}
