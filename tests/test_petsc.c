/* The PETSc linear solvers through the public API (label petsc).
 *
 * Built with PETSc (-DND_WITH_PETSC=ON): whole trajectories with
 * ND_SOLVER_PETSC_MUMPS and ND_SOLVER_PETSC_GAMG against ND_SOLVER_CHOLMOD
 * (UMFPACK for the non-symmetric tangents): the 1D bar, the disk of docs/design.md §7
 * (examples/meshes/disk_h4.msh, P1 and P2) and the ball (ball_h4.msh, P1),
 * dropped onto the plane so that contact is active for most of the run,
 * Newmark (1/4, 1/2), Theta = 1 (SPD: MUMPS LDL^T, CG) and Theta = 0
 * (non-symmetric tangent: MUMPS LU, GMRES). Compared: the displacement at
 * the end and the histories of E_Theta and of the contact force, each
 * relative to its largest magnitude.
 *   MUMPS: a direct solver, round-off only: 1e-10, and the same Newton path.
 *   GAMG: every solve stops at ||b - A x|| <= 1e-12 ||b||, so its relative
 *     error is at most cond(A) 1e-12. cond(c M + K_Theta) is small here: CG's
 *     Lanczos estimates (PETSC_OPTIONS="-nd_pc_type none
 *     -nd_ksp_view_singularvalues") are 4.0 (bar P1), 7.4 and 12.3 (disk P1,
 *     P2), 36.5 (ball P1); we allow 1e3. The schemes do not amplify errors
 *     (bounded energy), so each of the N steps adds at most 1e-9: the
 *     histories must agree to N * 1e-9 (kGamgBoundPerStep), and Newton may
 *     take another number of iterations (its stopping test sees the solve
 *     error; it took the same in every scene here). Measured: 1.2e-9 at most
 *     (bar, contact force), 30 to 170 times below the bound.
 *
 * The host's own MPI or PETSc (separate processes, CTest test_petsc_host_*):
 *   test_petsc host-mpi    the program calls MPI_Init, steps with MUMPS, and
 *                          calls MPI_Finalize: the library initialized PETSc
 *                          only, and finalized it inside MPI_Finalize;
 *   test_petsc host-petsc  the program calls PetscInitialize and PetscFinalize
 *                          around a run with GAMG; afterwards a PETSc solver
 *                          is refused (ND_ERR_STATE), nothing crashes.
 *
 * Built without PETSc: both ids are refused by nd_problem_set_linear_solver
 * with ND_ERR_KEY and a message naming ND_WITH_PETSC, and the problem is
 * unchanged and steps with the default solver. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"
#ifdef ND_HAVE_PETSC
#include <petscsys.h>
#endif

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

#ifdef ND_HAVE_PETSC

static const double kGamgBoundPerStep = 1e-9;

/* A body (disk_h4 in 2D, ball_h4 in 3D) placed 0.2 above the plane and
   moving down at 0.5 under g = 0.1: contact from t = 0.4 on. */
static nd_problem drop(int dim, int degree, double theta) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(dim == 2 ? ND_MESH_DIR "/disk_h4.msh" : ND_MESH_DIR "/ball_h4.msh", &m));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  const double lambda = 20, mu = 20;
  const double young = mu * (3 * lambda + 2 * mu) / (lambda + mu), nu = lambda / (2 * (lambda + mu));
  double g[3] = {0, 0, 0}, origin[3] = {0, 0, 0}, up[3] = {0, 0, 0};
  g[dim - 1] = -0.1, up[dim - 1] = 1;
  const double nm[2] = {0.25, 0.5};
  ND_OK_OR_FAIL(nd_problem_set_material(p, young, nu, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, 1e-3));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.1));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * (size_t)(dim * n)), *u = calloc((size_t)(dim * n), sizeof(double)),
         *v = calloc((size_t)(dim * n), sizeof(double));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  double lowest = INFINITY;
  for (int64_t i = 0; i < n; ++i) lowest = fmin(lowest, x[dim * i + dim - 1]);
  for (int64_t i = 0; i < n; ++i) u[dim * i + dim - 1] = 0.2 - lowest, v[dim * i + dim - 1] = -0.5;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u, v));
  free(x), free(u), free(v);
  return p;
}

typedef struct {
  int dim, steps;
  double *energy, *force, *u, iterations, contact_steps;
  int64_t len;
} run_result;

static run_result run(nd_problem p, int dim, int solver, int steps) {
  run_result r = {dim, steps, NULL, NULL, NULL, 0, 0, 0};
  ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, solver));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  r.len = n * dim;
  r.energy = malloc(sizeof(double) * (size_t)steps);
  r.force = malloc(sizeof(double) * (size_t)steps);
  r.u = malloc(sizeof(double) * (size_t)r.len);
  for (int k = 0; k < steps; ++k) {
    const int status = nd_step(p);
    ck_assert_msg(status == ND_OK, "solver %d, step %d: %s", solver, k + 1, nd_last_error());
    r.energy[k] = scalar(p, ND_ENERGY_AUGMENTED);
    r.force[k] = scalar(p, ND_CONTACT_FORCE);
    if (scalar(p, ND_ACTIVE_POINTS) > 0) r.contact_steps += 1;
  }
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, r.u));
  r.iterations = scalar(p, ND_NEWTON_ITERATIONS_TOTAL);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return r;
}

static void free_result(run_result *r) { free(r->energy), free(r->force), free(r->u); }

/* max |a - b| / max |b| */
static double rel_diff(const double *a, const double *b, int64_t n) {
  double d = 0, s = 0;
  for (int64_t i = 0; i < n; ++i) d = fmax(d, fabs(a[i] - b[i])), s = fmax(s, fabs(b[i]));
  return s > 0 ? d / s : d;
}

static void compare(const char *scene, const run_result *ref, const run_result *r, int solver, double bound,
                    int same_newton) {
  const double du = rel_diff(r->u, ref->u, ref->len), de = rel_diff(r->energy, ref->energy, ref->steps),
               df = rel_diff(r->force, ref->force, ref->steps);
  printf("%-22s %-12s u %.2e  E_Theta %.2e  force %.2e  Newton %g (ref %g)  contact steps %g of %d  bound %.0e\n",
         scene, solver == ND_SOLVER_PETSC_MUMPS ? "PETSC_MUMPS" : "PETSC_GAMG", du, de, df, r->iterations,
         ref->iterations, ref->contact_steps, ref->steps, bound);
  ck_assert_msg(ref->contact_steps > 0, "%s: no contact in the run", scene);
  ck_assert_msg(du <= bound && de <= bound && df <= bound, "%s solver %d: u %g, E_Theta %g, force %g > %g", scene,
                solver, du, de, df, bound);
  if (same_newton)
    ck_assert_msg(r->iterations == ref->iterations, "%s solver %d: %g Newton iterations, reference %g", scene,
                  solver, r->iterations, ref->iterations);
}

/* one scene against CHOLMOD with both PETSc solvers */
static void against_cholmod(const char *scene, int dim, int degree, double theta, int steps) {
  const double nm[2] = {0.25, 0.5};
  nd_problem p[3];
  for (int i = 0; i < 3; ++i)
    p[i] = dim == 1 ? nd_test_bar(40, degree, ND_SCHEME_NEWMARK, nm, theta, 0.2, 1.0 / 80) : drop(dim, degree, theta);
  run_result ref = run(p[0], dim, ND_SOLVER_CHOLMOD, steps);
  run_result mumps = run(p[1], dim, ND_SOLVER_PETSC_MUMPS, steps);
  run_result gamg = run(p[2], dim, ND_SOLVER_PETSC_GAMG, steps);
  compare(scene, &ref, &mumps, ND_SOLVER_PETSC_MUMPS, 1e-10, 1);
  compare(scene, &ref, &gamg, ND_SOLVER_PETSC_GAMG, steps * kGamgBoundPerStep, 0);
  free_result(&ref), free_result(&mumps), free_result(&gamg);
}

START_TEST(bar_matches_cholmod) {
  against_cholmod("bar P1 Theta 1", 1, 1, 1.0, 240);
  against_cholmod("bar P2 Theta 0", 1, 2, 0.0, 240);
}
END_TEST

START_TEST(disk_matches_cholmod) {
  against_cholmod("disk_h4 P1 Theta 1", 2, 1, 1.0, 40);
  against_cholmod("disk_h4 P2 Theta 1", 2, 2, 1.0, 40);
  against_cholmod("disk_h4 P1 Theta 0", 2, 1, 0.0, 40);
}
END_TEST

START_TEST(ball_matches_cholmod) { against_cholmod("ball_h4 P1 Theta 1", 3, 1, 1.0, 30); }
END_TEST

/* An ill-posed step (c M + K_Theta indefinite: Theta = 1, gamma0 E = 100,
   tau = 1) is ND_ERR_INDEFINITE with MUMPS, as with every direct backend. */
START_TEST(mumps_reports_an_indefinite_step) {
  nd_problem p = drop(2, 1, 1.0);
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 5.0));
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_COERCIVITY, 0));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, ND_SOLVER_PETSC_MUMPS));
  const int status = nd_problem_setup(p);
  ck_assert_msg(status == ND_ERR_INDEFINITE, "setup returned %d (%s)", status, nd_last_error());
  ck_assert_msg(strstr(nd_last_error(), "negative pivots") != NULL, "%s", nd_last_error());
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* GAMG decides nothing about definiteness, so the coercivity check of
   K_Theta uses a direct factorization whatever the linear solver: the bar at
   1.01 times its exact limit gamma0* = 1/E (Theta = 1, P1) is refused with
   GAMG as with CHOLMOD, and just below it is accepted. */
START_TEST(gamg_keeps_the_coercivity_check) {
  const double limit = 1.0; /* 1/E, E = 1 */
  for (int k = 0; k < 2; ++k) {
    nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, (k ? 1.01 : 0.999) * limit, 1.0 / 40);
    ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, ND_SOLVER_PETSC_GAMG));
    const int status = nd_problem_setup(p);
    ck_assert_msg(status == (k ? ND_ERR_NOT_COERCIVE : ND_OK), "gamma0 = %g gamma0*: setup returned %d (%s)",
                  k ? 1.01 : 0.999, status, nd_last_error());
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* A short bar run with `solver`; the status of the first failing call. */
static int bar_run(int solver) {
  nd_problem p = nd_test_bar(40, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 1.0 / 80);
  int status = nd_problem_set_linear_solver(p, solver);
  for (int k = 0; k < 40 && status == ND_OK; ++k) status = nd_step(p);
  if (status != ND_OK) fprintf(stderr, "bar with solver %d: %s\n", solver, nd_last_error());
  nd_problem_destroy(&p);
  return status;
}

/* These two run in the test's own process (CK_NOFORK: MPI once per process). */
START_TEST(host_mpi) {
  ck_assert(MPI_Init(NULL, NULL) == MPI_SUCCESS);
  ck_assert_int_eq(bar_run(ND_SOLVER_PETSC_MUMPS), ND_OK);
  PetscBool petsc = PETSC_FALSE;
  ck_assert(PetscInitialized(&petsc) == 0 && petsc); /* by the library */
  ck_assert(!PetscBeganMPI);                         /* MPI stays the host's */
  int rank = -1;
  ck_assert(MPI_Comm_rank(MPI_COMM_WORLD, &rank) == MPI_SUCCESS && rank == 0);
  ck_assert(MPI_Finalize() == MPI_SUCCESS);
  ck_assert(PetscFinalized(&petsc) == 0 && petsc); /* inside MPI_Finalize */
  printf("host-mpi: the library initialized PETSc in the host's MPI and finalized it in MPI_Finalize\n");
}
END_TEST

START_TEST(host_petsc) {
  ck_assert(PetscInitialize(NULL, NULL, NULL, NULL) == 0);
  ck_assert_int_eq(bar_run(ND_SOLVER_PETSC_GAMG), ND_OK);
  ck_assert_int_eq(bar_run(ND_SOLVER_PETSC_MUMPS), ND_OK);
  ck_assert(PetscFinalize() == 0);
  ck_assert_int_eq(bar_run(ND_SOLVER_PETSC_MUMPS), ND_ERR_STATE); /* after the host's PetscFinalize */
  ck_assert_int_eq(bar_run(ND_SOLVER_CHOLMOD), ND_OK);
  printf("host-petsc: the library used the host's PETSc and refused to run after its PetscFinalize\n");
}
END_TEST

static int run_alone(const TTest *test) {
  Suite *s = suite_create("petsc-host");
  TCase *tc = tcase_create("host");
  tcase_add_test(tc, test);
  suite_add_tcase(s, tc);
  SRunner *sr = srunner_create(s);
  srunner_set_fork_status(sr, CK_NOFORK);
  srunner_run_all(sr, CK_NORMAL);
  const int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

#else

START_TEST(petsc_ids_are_refused_cleanly) {
  nd_problem p = nd_test_bar(40, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 1.0 / 80);
  const int ids[] = {ND_SOLVER_PETSC_MUMPS, ND_SOLVER_PETSC_GAMG};
  const char *names[] = {"ND_SOLVER_PETSC_MUMPS", "ND_SOLVER_PETSC_GAMG"};
  for (int i = 0; i < 2; ++i) {
    ck_assert_int_eq(nd_problem_set_linear_solver(p, ids[i]), ND_ERR_KEY);
    const char *msg = nd_last_error();
    ck_assert_msg(strstr(msg, "nd_problem_set_linear_solver") && strstr(msg, names[i]) &&
                      strstr(msg, "ND_WITH_PETSC"),
                  "message: %s", msg);
  }
  for (int k = 0; k < 10; ++k) ND_OK_OR_FAIL(nd_step(p)); /* the problem is unchanged: default solver */
  ck_assert_double_eq_tol(scalar(p, ND_TIME), 10.0 / 80, 1e-15);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

#endif

int main(int argc, char **argv) {
#ifdef ND_HAVE_PETSC
  if (argc > 1 && !strcmp(argv[1], "host-mpi")) return run_alone(host_mpi);
  if (argc > 1 && !strcmp(argv[1], "host-petsc")) return run_alone(host_petsc);
#else
  (void)argc, (void)argv;
#endif
  Suite *s = suite_create("petsc");
  TCase *tc = tcase_create("petsc");
  tcase_set_timeout(tc, 300);
#ifdef ND_HAVE_PETSC
  tcase_add_test(tc, bar_matches_cholmod);
  tcase_add_test(tc, disk_matches_cholmod);
  tcase_add_test(tc, ball_matches_cholmod);
  tcase_add_test(tc, mumps_reports_an_indefinite_step);
  tcase_add_test(tc, gamg_keeps_the_coercivity_check);
#else
  tcase_add_test(tc, petsc_ids_are_refused_cleanly);
#endif
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
