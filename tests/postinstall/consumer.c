/*
 * A program built against an installed libnitschedyn (pkg-config or
 * find_package): 40 steps of the 1D bar of docs/design.md §7 with the hybrid scheme.
 * Every nd_step must return ND_OK and E_Theta must stay finite and positive;
 * the run-time version must be the header's.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <nitschedyn.h>

static int check(int status, const char *what) {
  if (status != ND_OK) {
    fprintf(stderr, "consumer: %s returned %d (%s): %s\n", what, status, nd_strerror(status),
            nd_last_error());
    exit(EXIT_FAILURE);
  }
  return status;
}

int main(void) {
  const int64_t nx = 40;
  const double lo0 = -0.5, hi0 = 0.5, lo1 = 0.5, hi1 = 1.5, x0 = 0, up = 1;
  int major = -1, minor = -1, patch = -1;
  nd_mesh m = NULL;
  nd_problem p = NULL;
  int64_t n = 0;
  double x[41], u0[41], e = NAN;

  check(nd_version(&major, &minor, &patch), "nd_version");
  if (major != ND_VERSION_MAJOR || minor != ND_VERSION_MINOR || patch != ND_VERSION_PATCH) {
    fprintf(stderr, "consumer: library %d.%d.%d, header %s\n", major, minor, patch, ND_VERSION_STRING);
    return EXIT_FAILURE;
  }
  check(nd_mesh_create_interval(nx, 0.0, 1.0, &m), "nd_mesh_create_interval");
  check(nd_mesh_mark_boundary_box(m, 1, &lo0, &hi0), "nd_mesh_mark_boundary_box");
  check(nd_mesh_mark_boundary_box(m, 2, &lo1, &hi1), "nd_mesh_mark_boundary_box");
  check(nd_problem_create(m, 1, &p), "nd_problem_create");
  check(nd_mesh_destroy(&m), "nd_mesh_destroy");
  check(nd_problem_set_material(p, 1.0, 0.0, 1.0), "nd_problem_set_material");
  check(nd_problem_set_dirichlet(p, 2), "nd_problem_set_dirichlet");
  check(nd_problem_set_contact_plane(p, 1, &x0, &up), "nd_problem_set_contact_plane");
  check(nd_problem_set_nitsche(p, 1.0, 0.2), "nd_problem_set_nitsche");
  check(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL), "nd_problem_set_scheme");
  check(nd_problem_set_timestep(p, 1.0 / 80), "nd_problem_set_timestep");
  check(nd_problem_get_node_count(p, &n), "nd_problem_get_node_count");
  if (n != nx + 1) {
    fprintf(stderr, "consumer: %lld nodes, expected %lld\n", (long long)n, (long long)(nx + 1));
    return EXIT_FAILURE;
  }
  check(nd_problem_get_node_coordinates(p, n, x), "nd_problem_get_node_coordinates");
  for (int64_t i = 0; i < n; ++i) u0[i] = 0.5 * (1 - x[i]);
  check(nd_problem_set_initial_state(p, n, u0, NULL), "nd_problem_set_initial_state");
  for (int k = 0; k < 40; ++k) {
    check(nd_step(p), "nd_step");
    check(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &e), "nd_get_scalar");
    if (!isfinite(e) || !(e > 0)) {
      fprintf(stderr, "consumer: E_Theta = %g after step %d\n", e, k + 1);
      return EXIT_FAILURE;
    }
  }
  check(nd_problem_destroy(&p), "nd_problem_destroy");
  printf("consumer: libnitschedyn %d.%d.%d, 40 steps, E_Theta = %.9f\n", major, minor, patch, e);
  return EXIT_SUCCESS;
}
