/* obstacle_step - the contact step on a curved obstacle against the plane,
 * same mesh (docs/performance.md, "Curved obstacles"): the ball of
 * docs/design.md §7 (ball_hH.msh, P1, hybrid, Theta = 1, automatic gamma0,
 * tau = 0.05) dropped on the plane z = 0, and on spheres tangent to it at
 * the origin (outside: the ball on a dome; inside: into a bowl), to t = T.
 * Each step is timed; a contact step is one that starts or ends with an
 * active point. Prints one line per obstacle: contact steps, their mean
 * time, the rebuilds (steps that refreshed normals) and the ratio to the
 * plane's mean contact step.
 *
 *   obstacle_step MESH_DIR [h=4] [T=16] [R=100]
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define BENCH_NAME "obstacle_step"
#include "step_timing.h"

/* kind 0: the plane; 1: a sphere of radius R below (outside); 2: a bowl of radius R above */
static double run(const char *mesh, int kind, double R, double T, double *rebuilds, int *contact_steps) {
  nd_mesh m;
  nd_problem p;
  CHECK(nd_mesh_read_gmsh(mesh, &m));
  CHECK(nd_problem_create(m, 1, &p));
  CHECK(nd_mesh_destroy(&m));
  const double g[3] = {0, 0, -0.1}, origin[3] = {0, 0, 0}, up[3] = {0, 0, 1}, below[3] = {0, 0, -R},
               above[3] = {0, 0, R};
  CHECK(nd_problem_set_material(p, 50, 0.25, 1));
  CHECK(nd_problem_set_body_force(p, g));
  if (kind == 0) CHECK(nd_problem_set_contact_plane(p, 1, origin, up));
  if (kind == 1) CHECK(nd_problem_add_contact_sphere(p, 1, below, R, 0));
  if (kind == 2) CHECK(nd_problem_add_contact_sphere(p, 1, above, R, 1));
  CHECK(nd_problem_set_nitsche(p, 1, 0));
  CHECK(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  CHECK(nd_problem_set_timestep(p, 0.05));
  CHECK(nd_problem_setup(p));
  double total = 0;
  *contact_steps = 0;
  *rebuilds = 0;
  const int steps = (int)(T / 0.05 + 0.5);
  for (int k = 0; k < steps; ++k) {
    const double before = scalar(p, ND_ACTIVE_POINTS), refreshes = scalar(p, ND_STAT_NORMAL_REFRESHES);
    const double t0 = now();
    CHECK(nd_step(p));
    const double dt = now() - t0;
    if (before > 0 || scalar(p, ND_ACTIVE_POINTS) > 0) total += dt, ++*contact_steps;
    if (scalar(p, ND_STAT_NORMAL_REFRESHES) > refreshes) ++*rebuilds;
  }
  CHECK(nd_problem_destroy(&p));
  return *contact_steps ? total / *contact_steps : 0;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: obstacle_step MESH_DIR [h=4] [T=16] [R=100]\n");
    return 2;
  }
  const char *h = argc > 2 ? argv[2] : "4";
  const double T = argc > 3 ? atof(argv[3]) : 16, R = argc > 4 ? atof(argv[4]) : 100;
  char mesh[4096];
  snprintf(mesh, sizeof mesh, "%s/ball_h%s.msh", argv[1], h);
  const char *names[3] = {"plane", "sphere (outside)", "bowl (inside)"};
  double plane = 0;
  printf("ball_h%s P1, hybrid, tau = 0.05, T = %g, sphere radius %g\n", h, T, R);
  for (int kind = 0; kind < 3; ++kind) {
    double rebuilds;
    int contact;
    const double mean = run(mesh, kind, R, T, &rebuilds, &contact);
    if (kind == 0) plane = mean;
    printf("%-17s contact steps %4d, mean %.4f s, steps with a rebuild %4.0f, ratio to the plane %.2f\n", names[kind],
           contact, mean, rebuilds, mean / plane);
  }
  return 0;
}
