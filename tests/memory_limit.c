/* Issue 54, finding 3: a step under an address-space limit (ulimit -v)
   returns ND_ERR_NOMEM, never waits forever in OpenBLAS's buffer
   allocation. Run by memory_limit.sh:
     memory_limit vmsize          prints the process's size at start (KiB)
     memory_limit step SOLVER     one explicit Newmark step, consistent mass,
                                  of a 100 x 50 rectangle resting on a plane;
                                  exit 0 (ND_OK), 3 (ND_ERR_NOMEM), 1 (else) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "nitschedyn.h"

static long vmsize_kib(void) {
  long pages = 0;
  FILE *f = fopen("/proc/self/statm", "r");
  if (f) {
    if (fscanf(f, "%ld", &pages) != 1) pages = 0;
    fclose(f);
  }
  return pages * (sysconf(_SC_PAGESIZE) / 1024);
}

int main(int argc, char **argv) {
  if (argc == 2 && strcmp(argv[1], "vmsize") == 0) {
    printf("%ld\n", vmsize_kib());
    return 0;
  }
  if (argc != 3 || strcmp(argv[1], "step") != 0) {
    fprintf(stderr, "usage: memory_limit vmsize | step SOLVER\n");
    return 2;
  }
  const int solver = atoi(argv[2]);
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[2] = {0, 0}, hi[2] = {2, 1}, blo[2] = {-1, -1}, bhi[2] = {3, 0.001};
  const double o[2] = {0, 0}, up[2] = {0, 1}, grav[2] = {0, -1}, explicit_newmark[2] = {0.0, 0.5};
  int st = nd_mesh_create_rectangle(100, 50, lo, hi, &m);
  if (st == ND_OK) st = nd_mesh_mark_boundary_box(m, 1, blo, bhi);
  if (st == ND_OK) st = nd_problem_create(m, 1, &p);
  nd_mesh_destroy(&m);
  if (st == ND_OK) st = nd_problem_set_material(p, 1, 0.3, 1);
  if (st == ND_OK) st = nd_problem_set_body_force(p, grav);
  if (st == ND_OK) st = nd_problem_set_contact_plane(p, 1, o, up);
  if (st == ND_OK) st = nd_problem_set_nitsche(p, 1.0, 0.0);
  if (st == ND_OK) st = nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, explicit_newmark);
  if (st == ND_OK) st = nd_problem_set_mass_lumping(p, 0);
  if (st == ND_OK) st = nd_problem_set_linear_solver(p, solver);
  if (st == ND_OK) st = nd_problem_set_timestep(p, 1e-4);
  if (st == ND_OK) st = nd_step(p);
  printf("solver %d: %d%s%s\n", solver, st, st == ND_OK ? "" : ": ", st == ND_OK ? "" : nd_last_error());
  fflush(stdout); /* the answer is out before the exit, which OpenBLAS's worker threads may hang (memory_limit.sh) */
  nd_problem_destroy(&p);
  return st == ND_OK ? 0 : st == ND_ERR_NOMEM ? 3 : 1;
}
