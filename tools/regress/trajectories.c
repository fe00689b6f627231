/* trajectories - a hash of every state (U, V, A and the scalars, bit for bit)
 * of 88 runs through the public API: the bar for every scheme, P1/P2,
 * Theta = 1, 0, -1 and every solver, the disk and the ball through their
 * impact. A refactoring of the step path must leave every line the same.
 * Run it against two builds of the library and diff the outputs:
 *
 *   cc -O2 -Iinclude tools/regress/trajectories.c -o /tmp/traj -Lbuild -lnitschedyn
 *   LD_LIBRARY_PATH=build /tmp/traj ND_MESH_DIR > after.txt   (same with the old build)
 *
 * The hashes depend on the BLAS kernels (OpenBLAS picks them by CPU): compare
 * two builds on one machine, never against numbers from another. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include "nitschedyn.h"
static uint64_t h;
static void mix(const void *p, size_t n) { const unsigned char *c = p; for (size_t i = 0; i < n; ++i) { h ^= c[i]; h *= 1099511628211ull; } }
static void run_bar(int deg, int scheme, const double *prm, double Th, int lumped, int steps, int solver) {
  nd_mesh m; nd_problem p; int64_t n; const double zero = 0, up = 1, lo[] = {-0.5, 0.5}, hi[] = {0.5, 1.5};
  nd_mesh_create_interval(20, 0.0, 1.0, &m);
  nd_mesh_mark_boundary_box(m, 1, &lo[0], &hi[0]); nd_mesh_mark_boundary_box(m, 2, &lo[1], &hi[1]);
  nd_problem_create(m, deg, &p); nd_problem_set_material(p, 1.0, 0.0, 1.0); nd_problem_set_dirichlet(p, 2);
  nd_problem_set_contact_plane(p, 1, &zero, &up); nd_problem_set_nitsche(p, Th, 0.2);
  nd_problem_set_scheme(p, scheme, prm); nd_problem_set_timestep(p, lumped ? 1.0 / 160 : 1.0 / 40);
  nd_problem_set_mass_lumping(p, lumped); nd_problem_set_linear_solver(p, solver);
  nd_problem_get_node_count(p, &n); double *x = malloc(n * sizeof *x), *u = malloc(n * sizeof *u);
  nd_problem_get_node_coordinates(p, n, x); for (int i = 0; i < n; ++i) u[i] = 0.5 * (1 - x[i]);
  nd_problem_set_initial_state(p, n, u, NULL); h = 1469598103934665603ull;
  for (int k = 0; k < steps; ++k) {
    int st = nd_step(p); if (st) { printf("  step %d failed: %s\n", k, nd_last_error()); break; }
    for (int f = 1; f <= 3; ++f) { nd_get_field(p, f, n, u); mix(u, n * sizeof *u); }
    for (int key = 3; key <= 10; ++key) { double v; nd_get_scalar(p, key, &v); mix(&v, sizeof v); }
  }
  double E; nd_get_scalar(p, ND_ENERGY_AUGMENTED, &E);
  printf("bar deg %d scheme %d prm %g %g Theta %g lumped %d solver %d: %016llx E_Theta %.17g\n", deg, scheme, prm ? prm[0] : -1, prm ? prm[1] : -1, Th, lumped, solver, (unsigned long long)h, E);
  free(x); free(u); nd_problem_destroy(&p); nd_mesh_destroy(&m);
}
static void run_drop(const char *mesh, int deg, int scheme, const double *prm, int steps, int solver, double Th) {
  nd_mesh m; nd_problem p; int64_t n; int dim;
  if (nd_mesh_read_gmsh(mesh, &m)) { printf("%s\n", nd_last_error()); return; }
  nd_mesh_get_dimension(m, &dim);
  double zero[3] = {0, 0, 0}, up[3] = {0, 0, 0}, f[3] = {0, 0, 0}; up[dim - 1] = 1; f[dim - 1] = -0.1;
  nd_problem_create(m, deg, &p); nd_problem_set_material(p, 50.0, 0.25, 1.0);
  nd_problem_set_body_force(p, f); nd_problem_set_contact_plane(p, 1, zero, up); nd_problem_set_nitsche(p, Th, 1e-3);
  nd_problem_set_scheme(p, scheme, prm); nd_problem_set_timestep(p, 0.25); nd_problem_set_linear_solver(p, solver);
  nd_problem_get_node_count(p, &n); double *u = malloc(3 * n * sizeof *u); h = 1469598103934665603ull;
  for (int k = 0; k < steps; ++k) {
    int st = nd_step(p); if (st) { printf("  step %d failed: %s\n", k, nd_last_error()); break; }
    for (int fl = 1; fl <= 3; ++fl) { nd_get_field(p, fl, n, u); mix(u, dim * n * sizeof *u); }
    for (int key = 3; key <= 10; ++key) { double v; nd_get_scalar(p, key, &v); mix(&v, sizeof v); }
  }
  double E, F; nd_get_scalar(p, ND_ENERGY_AUGMENTED, &E); nd_get_scalar(p, ND_CONTACT_FORCE, &F);
  printf("%s deg %d scheme %d solver %d Theta %g: %016llx E_Theta %.17g F %.17g\n", strrchr(mesh, '/') + 1, deg, scheme, solver, Th, (unsigned long long)h, E, F);
  free(u); nd_problem_destroy(&p); nd_mesh_destroy(&m);
}
int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s MESH_DIR (examples/meshes)\n", argv[0]);
    return 2;
  }
  const double th5[] = {0.5}, th1[] = {1.0}, th0[] = {0.0}, nm[] = {0.25, 0.5}, nm1[] = {0.5, 1.0}, nme[] = {0.0, 0.5}, nmd[] = {0.3, 0.6};
  const double Ths[] = {1, 0, -1};
  for (int deg = 1; deg <= 2; ++deg)
    for (int t = 0; t < 3; ++t) {
      run_bar(deg, ND_SCHEME_HYBRID, NULL, Ths[t], 0, 300, 0);
      run_bar(deg, ND_SCHEME_NEWMARK, nm, Ths[t], 0, 300, 0);
      run_bar(deg, ND_SCHEME_NEWMARK, nm1, Ths[t], 0, 300, 0);
      run_bar(deg, ND_SCHEME_NEWMARK, nmd, Ths[t], 0, 300, 0);
      run_bar(deg, ND_SCHEME_THETA, th5, Ths[t], 0, 300, 0);
      run_bar(deg, ND_SCHEME_THETA, th1, Ths[t], 0, 300, 0);
      run_bar(deg, ND_SCHEME_NEWMARK, nme, Ths[t], 1, 600, 0);
      run_bar(deg, ND_SCHEME_THETA, th0, Ths[t], 1, 100, 0);
      for (int s = 1; s <= 5; ++s) run_bar(deg, ND_SCHEME_NEWMARK, nm, Ths[t], 0, 150, s);
    }
  const char *dir = argv[1];
  char path[512];
  snprintf(path, sizeof path, "%s/disk_h4.msh", dir);
  for (int deg = 1; deg <= 2; ++deg) {
    run_drop(path, deg, ND_SCHEME_HYBRID, NULL, 80, 0, 1);
    run_drop(path, deg, ND_SCHEME_NEWMARK, nm, 80, 0, 1);
    run_drop(path, deg, ND_SCHEME_NEWMARK, nm, 80, 0, -1);
    run_drop(path, deg, ND_SCHEME_THETA, th1, 80, 4, 0);
  }
  snprintf(path, sizeof path, "%s/ball_h4.msh", dir);
  run_drop(path, 1, ND_SCHEME_HYBRID, NULL, 70, 0, 1);
  run_drop(path, 1, ND_SCHEME_NEWMARK, nm, 70, 5, 1);
  return 0;
}
