/* Backend conformance: the same systems through every linear-solver backend
 * (dense and banded LAPACK, CHOLMOD, UMFPACK, KLU) give the same answers.
 * Scenes: the 1D bar and a 2D block dropped on the plane, for symmetric
 * (Theta = 1) and non-symmetric (Theta = 0, -1) tangents, P1 and P2, the
 * hybrid, theta and Newmark schemes. All are direct solvers of the same
 * systems, so they differ by round-off only, amplified over the run: the
 * displacements must agree to 1e-10 relative, and Newton must take the same
 * path (same total iteration count). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static const int backends[] = {ND_SOLVER_DENSE, ND_SOLVER_BANDED, ND_SOLVER_CHOLMOD, ND_SOLVER_UMFPACK,
                               ND_SOLVER_KLU, ND_SOLVER_AUTO};
enum { N_BACKENDS = sizeof backends / sizeof backends[0] };

/* A 4 x 2 block [0,2]x[0.1,1.1] (P1 or P2), 0.1 above the plane y = 0,
   falling under gravity: it hits the plane and rebounds. gamma0 E = 0.01:
   with gamma0 E = 0.1 K_Theta (Theta = 1, P2) is indefinite and the free
   flight grows exponentially (x1.3 per step), amplifying any round-off
   difference between backends to 1e-10 in 60 steps (docs/design.md §7). */
static nd_problem block_2d_cells(int64_t nx, int64_t ny, int degree, int scheme, const double *params,
                                 double theta, double gamma0, double tau);
static nd_problem block_2d_gamma0(int degree, int scheme, const double *params, double theta, double gamma0,
                                  double tau) {
  return block_2d_cells(4, 2, degree, scheme, params, theta, gamma0, tau);
}
static nd_problem block_2d(int degree, int scheme, const double *params, double theta) {
  return block_2d_gamma0(degree, scheme, params, theta, 0.0005, 0.02);
}
/* (the same block on nx x ny cells) */
static nd_problem block_2d_cells(int64_t nx, int64_t ny, int degree, int scheme, const double *params,
                                 double theta, double gamma0, double tau) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[2] = {0, 0.1}, hi[2] = {2, 1.1}, blo[2] = {-1, 0}, bhi[2] = {3, 0.1};
  const double origin[2] = {0, 0}, up[2] = {0, 1}, g[2] = {0, -0.5};
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(nx, ny, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 20.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, gamma0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  /* generalized-alpha, which applies the contact force at its alpha_f point,
     gains energy at the impact (x3.1 at rho_inf = 0.8, Theta = 0): the energy
     guard stops it at t = 1.02. This test compares backends, not schemes.
     The energy-balance guard refuses the smaller gains of the other schemes
     at this stiff impact (6.6 % of the energy in motion at t = 1.04) for
     the same reason. */
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY, 0));
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0));
  return p;
}

/* Runs `steps` steps; fills u (n nodes) and returns total Newton iterations. */
static double run(nd_problem p, int solver, int steps, double *u, int64_t n) {
  ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, solver));

  for (int k = 0; k < steps; ++k) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u));
  double iters = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_NEWTON_ITERATIONS_TOTAL, &iters));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return iters;
}

static void conform(int dim, int degree, int scheme, const double *params, double theta) {
  double *ref = NULL, ref_iters = 0, active = 0;
  int64_t n = 0;
  for (int b = 0; b < N_BACKENDS; ++b) {
    nd_problem p = dim == 1 ? nd_test_bar(40, degree, scheme, params, theta, 0.2, 1.0 / 80)
                            : block_2d(degree, scheme, params, theta);
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
    const int64_t len = n * dim, steps = dim == 1 ? 240 : 60;
    double *u = malloc(sizeof(double) * (size_t)len);
    if (dim == 2 && b == 0) { /* make sure the scene reaches contact */
      for (int k = 0; k < steps && active == 0; ++k) {
        ND_OK_OR_FAIL(nd_step(p));
        ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
      }
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      ck_assert_msg(active > 0, "the 2D block never touched the plane");
      p = block_2d(degree, scheme, params, theta);
    }
    const double iters = run(p, backends[b], (int)steps, u, n);
    if (b == 0) {
      ref = u;
      ref_iters = iters;
      continue;
    }
    double diff = 0, norm = 0;
    for (int64_t i = 0; i < len; ++i) {
      diff = fmax(diff, fabs(u[i] - ref[i]));
      norm = fmax(norm, fabs(ref[i]));
    }
    ck_assert_msg(diff <= 1e-10 * norm, "%dD P%d Theta %g scheme %d: backend %d differs from dense by %g", dim,
                  degree, theta, scheme, backends[b], diff / norm);
    ck_assert_msg(iters == ref_iters, "%dD P%d Theta %g scheme %d: backend %d took %g Newton iterations, dense %g",
                  dim, degree, theta, scheme, backends[b], iters, ref_iters);
    free(u);
  }
  free(ref);
}

START_TEST(every_backend_gives_the_same_answer) {
  const double thetas[] = {1.0, 0.0, -1.0}, half = 0.5, nm[2] = {0.25, 0.5}, rho_inf = 0.8;
  const int schemes[] = {ND_SCHEME_HYBRID, ND_SCHEME_THETA, ND_SCHEME_NEWMARK, ND_SCHEME_GENERALIZED_ALPHA};
  const double *params[] = {NULL, &half, nm, &rho_inf};
  for (int dim = 1; dim <= 2; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (int t = 0; t < 3; ++t)
        for (int s = 0; s < 4; ++s) conform(dim, degree, schemes[s], params[s], thetas[t]);
}
END_TEST

/* An ill-posed step (Theta = 1, gamma0 E = 100, tau = 1: c M + K_Theta has
   negative eigenvalues) is reported as ND_ERR_INDEFINITE by every backend,
   CHOLMOD's simplicial LDL^T and the LU backends included; the well-posed
   scene of the conformance test (gamma0 E = 0.01, tau = 0.02) is not. */
START_TEST(every_backend_reports_an_indefinite_step) {
  for (int degree = 1; degree <= 2; ++degree)
    for (int b = 0; b < N_BACKENDS; ++b) {
      nd_problem p = block_2d_gamma0(degree, ND_SCHEME_HYBRID, NULL, 1.0, 5.0, 1.0);
      ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, backends[b]));
      const int status = nd_problem_setup(p);
      ck_assert_msg(status == ND_ERR_INDEFINITE, "P%d backend %d: setup returned %d (%s)", degree, backends[b], status,
                    nd_last_error());
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      p = block_2d(degree, ND_SCHEME_HYBRID, NULL, 1.0);
      ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, backends[b]));
      ND_OK_OR_FAIL(nd_problem_setup(p));
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* The initial acceleration M A = F - K_Theta U - N(U) of an implicit scheme
   is solved once: with 2,048 unknowns or more by conjugate gradients instead
   of a factorization of M, whatever the solver (a factor of M would stay for
   the whole run; src/problem/discretization.cpp). It must be the factored
   solve's answer to round-off, from a state where the right-hand side is not
   M g (a deformed, moving block). The factored answer: the explicit Newmark
   scheme's (beta = 0), whose steps solve with M, so its set-up factors M for
   the same equation. The implicit runs with CHOLMOD and AUTO then agree. */
static nd_problem moving_block(int scheme_beta0, int solver, int64_t *n) {
  const double implicit[2] = {0.25, 0.5}, explicit_[2] = {0.0, 0.5};
  nd_problem p = block_2d_cells(48, 24, 1, ND_SCHEME_NEWMARK, scheme_beta0 ? explicit_ : implicit, 1.0, 0.0005,
                                0.02); /* 2,450 unknowns */
  ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, solver));
  if (scheme_beta0) ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0)); /* (no step taken) */
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, n));
  double *x = malloc(sizeof(double) * (size_t)(2 * *n)), *u0 = malloc(sizeof(double) * (size_t)(2 * *n)),
         *v0 = malloc(sizeof(double) * (size_t)(2 * *n));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, *n, x));
  for (int64_t i = 0; i < *n; ++i) { /* a bending mode and a spin: K U != 0 */
    u0[2 * i] = 0.01 * sin(2.0 * x[2 * i + 1]) * x[2 * i];
    u0[2 * i + 1] = 0.02 * x[2 * i] * x[2 * i] * (1 + 0.3 * cos(5.0 * x[2 * i]));
    v0[2 * i] = -0.1 * (x[2 * i + 1] - 0.6);
    v0[2 * i + 1] = 0.1 * (x[2 * i] - 1.0) - 0.2;
  }
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, *n, u0, v0));
  free(x);
  free(u0);
  free(v0);
  return p;
}

START_TEST(initial_acceleration_by_conjugate_gradients) {
  int64_t n = 0;
  /* the factored answer */
  nd_problem p = moving_block(1, ND_SOLVER_CHOLMOD, &n);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  double *ref = malloc(sizeof(double) * (size_t)(2 * n)), factored = 0;
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, n, ref));
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_STAT_FACTORIZATIONS, &factored));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ck_assert_msg(factored == 1, "the explicit set-up factored M %g times", factored);
  double na = 0;
  for (int64_t i = 0; i < 2 * n; ++i) na = fmax(na, fabs(ref[i]));
  /* the implicit scheme's, with a solver chosen and with the library's choice */
  const int solvers[2] = {ND_SOLVER_CHOLMOD, ND_SOLVER_AUTO};
  double *u[2] = {NULL, NULL};
  for (int b = 0; b < 2; ++b) {
    p = moving_block(0, solvers[b], &n);
    double *acc = malloc(sizeof(double) * (size_t)(2 * n)), factorizations = -1;
    u[b] = malloc(sizeof(double) * (size_t)(2 * n));
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, n, acc));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_STAT_FACTORIZATIONS, &factorizations));
    ck_assert_msg(factorizations == 0, "solver %d: %g factorizations before the first step", solvers[b],
                  factorizations);
    double da = 0;
    for (int64_t i = 0; i < 2 * n; ++i) da = fmax(da, fabs(acc[i] - ref[i]));
    ck_assert_msg(da <= 1e-13 * na, "solver %d: the initial acceleration by CG differs from M's factor by %g",
                  solvers[b], da / na);
    for (int k = 0; k < 10; ++k) ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u[b]));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    free(acc);
  }
  double du = 0, nu = 0;
  for (int64_t i = 0; i < 2 * n; ++i) du = fmax(du, fabs(u[1][i] - u[0][i])), nu = fmax(nu, fabs(u[0][i]));
  ck_assert_msg(du <= 1e-12 * nu, "10 steps after, CHOLMOD and AUTO: %g", du / nu);
  free(ref);
  for (int b = 0; b < 2; ++b) free(u[b]);
}
END_TEST

/* The hybrid scheme does not carry the acceleration: a caller reading it
   after every step asks for a mass solve each time. Each is a CG solve, and
   M is never factored: on disk_h0.5 P2 a read by CG took 9-12 ms, about a
   solve with M's factor (8-12 ms), while factoring M would cost 0.87 s once
   and hold a factor as large as A's for the run (measured 27 November
   2026). Two reads of one state give the same bits. */
START_TEST(acceleration_reads_of_the_hybrid_scheme_factor_nothing) {
  for (int b = 0; b < 2; ++b) {
    const int solver = b == 0 ? ND_SOLVER_CHOLMOD : ND_SOLVER_AUTO;
    nd_problem p = block_2d_cells(48, 24, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.0005, 0.02); /* 2,450 unknowns */
    ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, solver));
    int64_t n = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
    double *a = malloc(sizeof(double) * (size_t)(2 * n)), *again = malloc(sizeof(double) * (size_t)(2 * n));
    double before = -1, after = -1, setup = -1;
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, n, a));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_STAT_FACTORIZATIONS, &before));
    ck_assert_msg(before == 0, "solver %d: a read before the set-up factored %g times", solver, before);
    ND_OK_OR_FAIL(nd_problem_setup(p));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_STAT_FACTORIZATIONS, &setup)); /* A's */
    for (int k = 0; k < 3; ++k) {
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, n, a));
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, n, again));
      ck_assert_msg(memcmp(a, again, sizeof(double) * (size_t)(2 * n)) == 0, "solver %d: two reads differ", solver);
    }
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_STAT_FACTORIZATIONS, &after));
    ck_assert_msg(after == setup, "solver %d: 6 reads after 3 steps factored %g times", solver, after - setup);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    free(a);
    free(again);
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("solvers");
  TCase *tc = tcase_create("conformance");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, every_backend_gives_the_same_answer);
  tcase_add_test(tc, every_backend_reports_an_indefinite_step);
  tcase_add_test(tc, initial_acceleration_by_conjugate_gradients);
  tcase_add_test(tc, acceleration_reads_of_the_hybrid_scheme_factor_nothing);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
