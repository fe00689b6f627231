/*
 * bar_twin - the C twin of bar_history.f90: the 1D bar of docs/design.md §7 set up
 * with exactly the calls of examples/bar1d.c (hybrid scheme, Theta = 1,
 * gamma0 = 0.2, tau = h/2, T = 3), dumping u and v at every FE node at every
 * time level t_n = n tau, n = 0 .. steps, in the library's node order.
 *
 * usage: bar_twin OUT.bin [NX [DEGREE]]
 * OUT.bin (native byte order): int64 n_nodes, int64 n_levels, then per level
 * n_nodes doubles of u and n_nodes doubles of v.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "nitschedyn.h"

static int check(int status) {
  if (status != ND_OK) fprintf(stderr, "bar_twin: %s\n", nd_last_error());
  return status != ND_OK;
}

int main(int argc, char **argv) {
  if (argc < 2 || argc > 4) {
    fprintf(stderr, "usage: %s OUT.bin [NX [DEGREE]]\n", argv[0]);
    return 2;
  }
  const int64_t nx = argc > 2 ? strtoll(argv[2], NULL, 10) : 40;
  const int degree = argc > 3 ? atoi(argv[3]) : 1;
  const double tau = 0.5 / (double)nx, T = 3.0;
  const int64_t steps = llround(T / tau);
  const double lo_d = 0.5, hi_d = 1.5, lo_c = -0.5, hi_c = 0.5, zero = 0.0, up = 1.0;
  enum { CLAMPED = 1, CONTACT = 2 };

  nd_mesh mesh = NULL;
  nd_problem p = NULL;
  int fail = check(nd_mesh_create_interval(nx, 0.0, 1.0, &mesh)) ||
             check(nd_mesh_mark_boundary_box(mesh, CLAMPED, &lo_d, &hi_d)) ||
             check(nd_mesh_mark_boundary_box(mesh, CONTACT, &lo_c, &hi_c)) ||
             check(nd_problem_create(mesh, degree, &p));
  nd_mesh_destroy(&mesh);
  fail = fail || check(nd_problem_set_material(p, 1.0, 0.0, 1.0)) || check(nd_problem_set_dirichlet(p, CLAMPED)) ||
         check(nd_problem_set_contact_plane(p, CONTACT, &zero, &up)) || check(nd_problem_set_nitsche(p, 1.0, 0.2)) ||
         check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL)) || check(nd_problem_set_mass_lumping(p, 0)) ||
         check(nd_problem_set_timestep(p, tau));
  int64_t n = 0;
  fail = fail || check(nd_problem_get_node_count(p, &n));
  double *x = fail ? NULL : malloc((size_t)n * sizeof *x);
  double *u = fail ? NULL : malloc((size_t)n * sizeof *u);
  double *v = fail ? NULL : calloc((size_t)n, sizeof *v);
  fail = fail || !x || !u || !v || check(nd_problem_get_node_coordinates(p, n, x));
  if (!fail) {
    for (int64_t i = 0; i < n; ++i) u[i] = 0.5 * (1 - x[i]);
    fail = check(nd_problem_set_initial_state(p, n, u, v));
  }
  FILE *out = fail ? NULL : fopen(argv[1], "wb");
  if (!fail && !out) {
    fprintf(stderr, "bar_twin: cannot open %s\n", argv[1]);
    fail = 1;
  }
  const int64_t header[2] = {n, steps + 1};
  if (!fail) fail = fwrite(header, sizeof header[0], 2, out) != 2;
  for (int64_t k = 0; !fail && k <= steps; ++k) {
    if (k > 0) fail = check(nd_step(p));
    fail = fail || check(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u)) ||
           check(nd_get_field(p, ND_FIELD_VELOCITY, n, v));
    fail = fail || fwrite(u, sizeof *u, (size_t)n, out) != (size_t)n || fwrite(v, sizeof *v, (size_t)n, out) != (size_t)n;
  }
  if (out && fclose(out) != 0) fail = 1;
  if (!fail) printf("bar_twin: %lld nodes, %lld time levels written to %s\n", (long long)n, (long long)(steps + 1), argv[1]);
  free(x);
  free(u);
  free(v);
  nd_problem_destroy(&p);
  return fail;
}
