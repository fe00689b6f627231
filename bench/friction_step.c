/* friction_step - the frictional contact step against the frictionless one,
 * same mesh and scene (docs/performance.md, "Friction"): the disk and the
 * ball of docs/design.md §7 (disk_hH.msh, ball_hH.msh, P1, Theta = 1,
 * automatic gamma0, tau = 0.05) dropped on the plane with a tangential
 * velocity v_x = 0.5 (so that they slide as they land), frictionless and
 * with Coulomb's F = 0.3, to t = T. Each step is timed; a contact step is one
 * that starts or ends with an active point. Prints one line per run: contact
 * steps, their mean time, Newton iterations per contact step, and the ratio
 * to the frictionless mean contact step, and the whole time loop's time.
 * gamma0: Nitsche's (0: the library's automatic one; bench/friction_getfem.sh
 * gives GetFEM's runs the same).
 *
 *   friction_step MESH_DIR [h=4] [T=16] [scheme=hybrid|newmark] [gamma0=0]
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define BENCH_NAME "friction_step"
#include "step_timing.h"

static double run(const char *mesh, int dim, double F, int newmark, double T, double gamma0, int *contact_steps,
                  double *newton, double *loop) {
  nd_mesh m;
  nd_problem p;
  CHECK(nd_mesh_read_gmsh(mesh, &m));
  CHECK(nd_problem_create(m, 1, &p));
  CHECK(nd_mesh_destroy(&m));
  double g[3] = {0, 0, 0}, origin[3] = {0, 0, 0}, up[3] = {0, 0, 0};
  g[dim - 1] = -0.1, up[dim - 1] = 1;
  CHECK(nd_problem_set_material(p, 50, 0.25, 1));
  CHECK(nd_problem_set_body_force(p, g));
  CHECK(nd_problem_set_contact_plane(p, 1, origin, up));
  if (F > 0) CHECK(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
  CHECK(nd_problem_set_nitsche(p, 1, gamma0));
  const double nm[2] = {0.25, 0.5};
  CHECK(nd_problem_set_scheme(p, newmark ? ND_SCHEME_NEWMARK : ND_SCHEME_HYBRID, newmark ? nm : NULL));
  CHECK(nd_problem_set_timestep(p, 0.05));
  int64_t n = 0;
  CHECK(nd_problem_get_node_count(p, &n));
  double *v = calloc((size_t)(dim * n), sizeof *v);
  for (int64_t i = 0; i < n; ++i) v[dim * i] = 0.5;
  CHECK(nd_problem_set_initial_state(p, n, NULL, v));
  free(v);
  CHECK(nd_problem_setup(p));
  double total = 0;
  *loop = 0;
  *contact_steps = 0;
  *newton = 0;
  const int steps = (int)(T / 0.05 + 0.5);
  for (int k = 0; k < steps; ++k) {
    const double before = scalar(p, ND_ACTIVE_POINTS);
    const double t0 = now();
    CHECK(nd_step(p));
    const double dt = now() - t0;
    *loop += dt;
    if (before > 0 || scalar(p, ND_ACTIVE_POINTS) > 0)
      total += dt, ++*contact_steps, *newton += scalar(p, ND_NEWTON_ITERATIONS);
  }
  CHECK(nd_problem_destroy(&p));
  if (*contact_steps) *newton /= *contact_steps;
  return *contact_steps ? total / *contact_steps : 0;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: friction_step MESH_DIR [h=4] [T=16] [hybrid|newmark] [gamma0=0]\n");
    return 2;
  }
  const char *h = argc > 2 ? argv[2] : "4";
  const double T = argc > 3 ? atof(argv[3]) : 16;
  const int newmark = argc > 4 && strcmp(argv[4], "newmark") == 0;
  const double gamma0 = argc > 5 ? atof(argv[5]) : 0;
  for (int dim = 2; dim <= 3; ++dim) {
    char mesh[4096];
    snprintf(mesh, sizeof mesh, "%s/%s_h%s.msh", argv[1], dim == 2 ? "disk" : "ball", h);
    printf("%s_h%s P1, %s, tau = 0.05, T = %g, v_x = 0.5\n", dim == 2 ? "disk" : "ball", h,
           newmark ? "Newmark(1/4, 1/2)" : "hybrid", T);
    double frictionless = 0;
    for (int k = 0; k < 2; ++k) {
      int contact;
      double newton, loop;
      const double mean = run(mesh, dim, k ? 0.3 : 0, newmark, T, gamma0, &contact, &newton, &loop);
      if (k == 0) frictionless = mean;
      printf("%-16s contact steps %4d, mean %.5f s, Newton %.2f, ratio to frictionless %.2f, loop %.3f s\n",
             k ? "Coulomb F = 0.3" : "frictionless", contact, mean, newton, mean / frictionless, loop);
    }
  }
  return 0;
}
