/* The distributed solve (issue 15, slices 2 to 6), run under mpiexec -n 1, 2 and 4
 * (tests/CMakeLists.txt, builds with PETSc). Every rank builds the same
 * problem; nd_problem_set_comm spreads the PETSc solves over the ranks.
 *  - the disk and the ball of docs/design.md §7 through the impact: the energy and
 *    contact-force histories of MUMPS and GAMG over all ranks against the
 *    serial CHOLMOD solve of the same scene in the same process;
 *  - a load refused on the last rank only: nd_step fails on every rank with
 *    the same code and no rank's state moves; likewise an overflow in the
 *    rows of some ranks only (their own assembly);
 *  - the contact points and the rows of the products computed by their
 *    ranks (slice 4): with CHOLMOD on every rank, bitwise one process's state;
 *  - checkpoint/restart over the same ranks restores the state bitwise;
 *  - each rank's part of every field (nd_get_field_owned): disjoint, covering
 *    every node, bitwise the gathered field; the whole field gathered on one
 *    rank (nd_get_field_gathered) bitwise, and refused on every rank when
 *    refused on one;
 *  - the operators M, K, K_Theta held by rows (slice 5), with the energy
 *    and the coercivity check that need every rank's rows;
 *  - on split rows the right-hand side and the Newton residual stay on
 *    their rows (slice 6): what a step receives from the other ranks, and
 *    the Newmark, generalized-alpha and theta histories against one process;
 *  - ND_PARTITION_KIND: which partition ran (PT-Scotch or the slabs);
 *  - bad input: MPI_COMM_NULL, a communicator after the set-up, another mesh
 *    on one rank.
 * CK_FORK=no (MPI is initialized once per process): every check runs in
 * this process, on every rank. */
#include <inttypes.h>
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "drop_scene.h"
#include "nitschedyn_mpi.h"
#include "testutil_mpi.h"

enum { kSteps = 44 }; /* tau = 0.25: free fall, the impact at t = 10, and contact until t = 11 */
static const double kTau = 0.25;

static int g_rank, g_size;
static int g_thread_multiple; /* MPI_THREAD_MULTIPLE provided: PT-Scotch partitions */

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

static nd_problem scene(int dim, int solver, int distributed) {
  char mesh[512];
  snprintf(mesh, sizeof mesh, "%s/%s_h4.msh", ND_MESH_DIR, dim == 2 ? "disk" : "ball");
  nd_problem p = NULL;
  ND_OK_OR_FAIL(drop_scene_create(dim, mesh, 1, ND_SCHEME_HYBRID, NULL, 1.0, 1e-3, kTau, solver, &p));
  if (distributed) ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
  return p;
}

typedef struct {
  double energy[kSteps], force[kSteps], active[kSteps];
  double solves; /* ND_STAT_SOLVES after the run */
} history;

static void run(nd_problem p, history *h) {
  for (int k = 0; k < kSteps; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    h->energy[k] = scalar(p, ND_ENERGY_AUGMENTED);
    h->force[k] = scalar(p, ND_CONTACT_FORCE);
    h->active[k] = scalar(p, ND_ACTIVE_POINTS);
  }
  h->solves = scalar(p, ND_STAT_SOLVES);
}

static double max_abs(const double *x, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) m = fmax(m, fabs(x[i]));
  return m;
}

/* the larger of two gaps, NaN if either is (fmax passes over a NaN) */
static double worse(double a, double b) { return isnan(a) || isnan(b) ? NAN : fmax(a, b); }

/* the largest difference of two histories relative to the largest value of
 * the reference (NaN if a value is) */
static double relative_gap(const double *ref, const double *x, int n) {
  double d = 0;
  for (int i = 0; i < n; ++i) d = worse(d, fabs(x[i] - ref[i]));
  return d / max_abs(ref, n);
}

/* The Krylov stopping rule of ND_SOLVER_PETSC_GAMG is ||b - A x|| <= rtol ||b||,
 * rtol = 1e-12 (src/linalg/petsc.cpp), so one solve is off the exact one by
 * ||dx|| <= ||A^-1|| rtol ||b|| <= kappa(A) rtol ||x||. A = c M + K_Theta with
 * c = 4/tau^2 for the hybrid scheme (Newmark(1/4, 1/2) in the interior): in M's
 * metric its spectrum is c + omega^2, omega <= omega_max, so kappa(A) <=
 * kappa(M) (1 + (tau omega_max)^2 / 4); kappa(M) <= (d + 2) q for P1 (the
 * element mass matrix's eigenvalue ratio d + 2 times q, the ratio of the
 * largest to the smallest vertex patch volume; q <= 10 for the committed
 * Gmsh meshes, whose cells are within a factor ~2 of h in size). The scheme is
 * energy-stable, so errors add up at most: after S solves (ND_STAT_SOLVES,
 * counted) the state is off by S kappa rtol relatively, and a quadratic
 * energy or the force (linear in U) by twice that. */
static double krylov_bound(nd_problem p, int dim, double solves) {
  double tau_c = 0;
  ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
  const double omega_max = 2 / tau_c; /* tau_c = 2 / omega_max for an implicit scheme */
  const double kappa = (dim + 2) * 10.0 * (1 + kTau * omega_max * kTau * omega_max / 4);
  return 2 * solves * kappa * 1e-12;
}

START_TEST(histories_match_the_serial_solve) {
  for (int dim = 2; dim <= 3; ++dim) {
    history serial, mumps, gamg;
    nd_problem p = scene(dim, ND_SOLVER_CHOLMOD, 0);
    run(p, &serial);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    ck_assert_msg(max_abs(serial.force, kSteps) > 0, "%dD: no impact within the horizon", dim);

    p = scene(dim, ND_SOLVER_PETSC_MUMPS, 1);
    run(p, &mumps);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    p = scene(dim, ND_SOLVER_PETSC_GAMG, 1);
    run(p, &gamg);
    const double bound = krylov_bound(p, dim, serial.solves);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));

    const double e_m = relative_gap(serial.energy, mumps.energy, kSteps);
    const double f_m = relative_gap(serial.force, mumps.force, kSteps);
    const double e_g = relative_gap(serial.energy, gamg.energy, kSteps);
    const double f_g = relative_gap(serial.force, gamg.force, kSteps);
    if (g_rank == 0)
      printf("%dD, %d rank(s): MUMPS energy %.2e force %.2e; GAMG energy %.2e force %.2e (bound %.2e)\n", dim,
             g_size, e_m, f_m, e_g, f_g, bound);
    ck_assert_msg(e_m <= 1e-8 && f_m <= 1e-8, "%dD MUMPS: energy %.3g, force %.3g off the serial solve", dim, e_m, f_m);
    ck_assert_msg(e_g <= bound && f_g <= bound, "%dD GAMG: energy %.3g, force %.3g > %.3g", dim, e_g, f_g, bound);
    ck_assert_msg(memcmp(serial.active, mumps.active, sizeof serial.active) == 0, "%dD: MUMPS's active sets differ",
                  dim);
    /* the ranks agree exactly: the solution is gathered, everything else is replicated */
    ck_assert(nd_test_same_on_all_ranks(&mumps, (int)sizeof mumps - (int)sizeof mumps.solves));
    ck_assert(nd_test_same_on_all_ranks(&gamg, (int)sizeof gamg - (int)sizeof gamg.solves));
  }
}
END_TEST

/* Through the release (the disk with Newmark(1/4, 1/2) to t = 28: impact
 * at t = 10.25, release at t = 27.5 with tau = 0.25): the step that starts
 * in contact and ends free makes the condensed Newton's U = A^-1 r from a
 * y0 solved at the columns' rows only (points active at the predictor),
 * completed from the other ranks. MUMPS on split rows against one process
 * with CHOLMOD, to 1e-8 as above. */
START_TEST(contact_release_on_split_rows) {
  enum { kRelease = 112 };
  /* Newmark: [P]_+ of the new state, no force once every point has left
     (the hybrid scheme's Phi still reads P^n at the release step) */
  const double newmark[2] = {0.25, 0.5};
  char mesh[512];
  snprintf(mesh, sizeof mesh, "%s/disk_h4.msh", ND_MESH_DIR);
  nd_problem alone = NULL, split = NULL;
  ND_OK_OR_FAIL(drop_scene_create(2, mesh, 1, ND_SCHEME_NEWMARK, newmark, 1.0, 1e-3, kTau, ND_SOLVER_CHOLMOD, &alone));
  ND_OK_OR_FAIL(drop_scene_create(2, mesh, 1, ND_SCHEME_NEWMARK, newmark, 1.0, 1e-3, kTau, ND_SOLVER_PETSC_MUMPS,
                                  &split));
  ND_OK_OR_FAIL(nd_problem_set_comm(split, MPI_COMM_WORLD));
  double e[kRelease], e_split[kRelease], f[kRelease], f_split[kRelease];
  int contact = 0, released = 0;
  for (int k = 0; k < kRelease; ++k) {
    ND_OK_OR_FAIL(nd_step(alone));
    ND_OK_OR_FAIL(nd_step(split));
    e[k] = scalar(alone, ND_ENERGY_AUGMENTED), e_split[k] = scalar(split, ND_ENERGY_AUGMENTED);
    f[k] = scalar(alone, ND_CONTACT_FORCE), f_split[k] = scalar(split, ND_CONTACT_FORCE);
    const double active = scalar(alone, ND_ACTIVE_POINTS);
    ck_assert_msg(nd_test_on_all_ranks(scalar(split, ND_ACTIVE_POINTS) == active), "step %d: active sets differ", k);
    released += contact && active == 0;
    contact = active > 0;
  }
  const double de = relative_gap(e, e_split, kRelease), df = relative_gap(f, f_split, kRelease);
  if (g_rank == 0) printf("release, %d rank(s): energy %.2e, force %.2e off one process\n", g_size, de, df);
  ck_assert_msg(released == 1, "%d releases within the horizon", released);
  ck_assert_msg(nd_test_on_all_ranks(de <= 1e-8 && df <= 1e-8), "energy %.3g, force %.3g off one process", de, df);
  ND_OK_OR_FAIL(nd_problem_destroy(&alone));
  ND_OK_OR_FAIL(nd_problem_destroy(&split));
}
END_TEST

/* The schemes that carry an acceleration (their right-hand sides read M A^n
 * as well: with split operators a rank holds its rows of it only), and the
 * theta scheme, on split rows with MUMPS: the same histories as one process
 * with CHOLMOD, to 1e-8, and the same active sets. On the disk and ball of
 * simplices, and of quadrilaterals and hexahedra (Q1: disk_quad_h4,
 * ball_hex_h4). */
START_TEST(implicit_schemes_on_split_rows) {
  const int schemes[] = {ND_SCHEME_NEWMARK, ND_SCHEME_GENERALIZED_ALPHA, ND_SCHEME_THETA};
  const double params[][2] = {{0.25, 0.5}, {0.8, 0}, {0.75, 0}};
  static const char *const meshes[] = {"disk_h4", "ball_h4", "disk_quad_h4", "ball_hex_h4"};
  for (int m = 0; m < 4; ++m) {
    const int dim = 2 + m % 2;
    char mesh[512];
    snprintf(mesh, sizeof mesh, "%s/%s.msh", ND_MESH_DIR, meshes[m]);
    for (int k = 0; k < 3; ++k) {
      history serial, split;
      for (int distributed = 0; distributed <= 1; ++distributed) {
        nd_problem p = NULL;
        ND_OK_OR_FAIL(drop_scene_create(dim, mesh, 1, schemes[k], params[k], 1.0, 1e-3, kTau,
                                        distributed ? ND_SOLVER_PETSC_MUMPS : ND_SOLVER_CHOLMOD, &p));
        if (distributed) ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
        run(p, distributed ? &split : &serial);
        ND_OK_OR_FAIL(nd_problem_destroy(&p));
      }
      ck_assert_msg(max_abs(serial.force, kSteps) > 0, "%s scheme %d: no impact within the horizon", meshes[m],
                    schemes[k]);
      const double e = relative_gap(serial.energy, split.energy, kSteps);
      const double f = relative_gap(serial.force, split.force, kSteps);
      if (g_rank == 0)
        printf("%s scheme %d, %d rank(s): energy %.2e force %.2e off one process\n", meshes[m], schemes[k], g_size, e,
               f);
      ck_assert_msg(nd_test_on_all_ranks(e <= 1e-8 && f <= 1e-8), "%s scheme %d: energy %.3g, force %.3g", meshes[m],
                    schemes[k], e, f);
      ck_assert_msg(nd_test_on_all_ranks(memcmp(serial.active, split.active, sizeof serial.active) == 0),
                    "%s scheme %d: the active sets differ", meshes[m], schemes[k]);
    }
  }
}
END_TEST

typedef struct {
  double t;
  double *u, *v;
  int64_t n; /* values per field: nodes times the dimension */
} snapshot;

static snapshot take_in(nd_problem p, int dim) {
  snapshot s = {scalar(p, ND_TIME), NULL, NULL, 0};
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  s.n = dim * nodes;
  s.u = malloc(sizeof(double) * (size_t)s.n);
  s.v = malloc(sizeof(double) * (size_t)s.n);
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nodes, s.u));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, nodes, s.v));
  return s;
}

static snapshot take(nd_problem p) { return take_in(p, 2); }

static int same_snapshot(const snapshot *a, const snapshot *b) {
  const size_t bytes = sizeof(double) * (size_t)a->n;
  return a->n == b->n && memcmp(&a->t, &b->t, sizeof a->t) == 0 && memcmp(a->u, b->u, bytes) == 0 &&
         memcmp(a->v, b->v, bytes) == 0;
}

/* the largest difference of the displacements relative to the largest displacement */
static double snapshot_gap(const snapshot *a, const snapshot *b) {
  double d = 0, m = 0;
  for (int64_t i = 0; i < a->n; ++i) d = worse(d, fabs(a->u[i] - b->u[i])), m = fmax(m, fabs(a->u[i]));
  return d / m;
}

static void drop(snapshot *s) {
  free(s->u);
  free(s->v);
}

/* The work outside the solves split over the ranks (slice 4): each contact
 * point evaluated by the rank of its cell, each row of the step's products,
 * of the Newton residual's A U and M U and of an explicit step's K_Theta U
 * by the rank of its node, and gathered. With CHOLMOD every rank solves the
 * whole system itself, the same systems as one process, so what the split
 * changes can be seen exactly:
 *  - the displacements and velocities are bitwise those of one process
 *    (every gathered value was computed by the code of one process) and the
 *    active sets equal;
 *  - the energy differs only by the order of its sum (the ranks' parts added
 *    rank after rank): relatively at most n u kappa, n the unknowns, u the
 *    unit round-off and kappa = sum |V_i (MV)_i| / V'MV (<= 10 here: M is an
 *    M-matrix's neighbour, its off-diagonal entries a fraction of the
 *    diagonal); the bound below takes kappa = 10;
 *  - the counts: the ranks' point evaluations add up to one process's, which
 *    every rank reports as ND_STAT_POINT_EVALUATIONS, and every other
 *    statistic is the same on every rank, and one process's but for the
 *    SpMV of the condensed Newton's last residual (one process checks it
 *    from the new state's products).
 * The scenes: the disk (condensed Newton, its residual checked at the end of
 * a contact step) and the ball (full Newton with the updated factor: the
 * residual at every iteration), hybrid scheme; and the disk with the
 * explicit central difference and lumped mass (K_Theta U every step, no
 * solve), at 0.9 times its critical step. */
static void compare_split(nd_problem alone, nd_problem split, int dim, int steps, const char *what) {
  double worst = 0, active_alone = 0, contact_steps = 0;
  for (int k = 0; k < steps; ++k) {
    ND_OK_OR_FAIL(nd_step(alone));
    ND_OK_OR_FAIL(nd_step(split));
    const double e = scalar(alone, ND_ENERGY_MECHANICAL), e_split = scalar(split, ND_ENERGY_MECHANICAL);
    worst = worse(worst, fabs(e_split - e) / e);
    ck_assert_msg(scalar(alone, ND_ACTIVE_POINTS) == scalar(split, ND_ACTIVE_POINTS), "%s step %d: active sets differ",
                  what, k);
    active_alone = fmax(active_alone, scalar(alone, ND_ACTIVE_POINTS));
    contact_steps += scalar(alone, ND_ACTIVE_POINTS) > 0;
    ck_assert(nd_test_same_on_all_ranks(&e_split, (int)sizeof e_split));
  }
  ck_assert_msg(active_alone > 0, "%s: no contact within the horizon", what);
  snapshot a = take_in(alone, dim), b = take_in(split, dim);
  ck_assert_msg(same_snapshot(&a, &b), "%s: the split run's state is not bitwise one process's", what);
  const double bound = (double)a.n * 1.1e-16 * 10;
  ck_assert_msg(worst <= bound, "%s: energy %.3g off one process's (bound %.3g)", what, worst, bound);

  const double points = scalar(alone, ND_STAT_POINT_EVALUATIONS), own = scalar(split, ND_STAT_POINT_EVALUATIONS_OWN);
  double sum = 0, most = 0;
  MPI_Allreduce(&own, &sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  MPI_Allreduce(&own, &most, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  ck_assert_double_eq(scalar(split, ND_STAT_POINT_EVALUATIONS), points);
  ck_assert_double_eq(sum, points);
  if (g_rank == 0)
    printf("%s, %d rank(s): energy %.2e off one process's (bound %.2e); point evaluations %.0f, the busiest "
           "rank %.0f\n", what, g_size, worst, bound, points, most);
  const int keys[] = {ND_STAT_FACTORIZATIONS, ND_STAT_SOLVES, ND_STAT_MATRIX_ASSEMBLIES, ND_STAT_TANGENT_UPDATES,
                      ND_STAT_CONTACT_EVALUATIONS, ND_STAT_SPMV, ND_NEWTON_ITERATIONS_TOTAL};
  for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i) {
    const double x = scalar(split, keys[i]);
    ck_assert_msg(nd_test_same_on_all_ranks(&x, (int)sizeof x), "%s: statistic %d differs between the ranks", what, keys[i]);
    /* one process checks the condensed Newton's last residual from the new
       state's products, the ranks with a pass over A and M of their own: at
       most one SpMV more per step that ends in contact */
    if (keys[i] == ND_STAT_SPMV) {
      const double more = x - scalar(alone, keys[i]);
      ck_assert_msg(more >= 0 && more <= contact_steps, "%s: %g SpMV more than one process, %g steps in contact",
                    what, more, contact_steps);
    } else {
      ck_assert_double_eq(x, scalar(alone, keys[i]));
    }
  }
  drop(&a), drop(&b);
  /* queries between steps are not collective: rank 0 alone reads the
     monitors and the fields that may need work (the acceleration and the
     reactions at equilibrium), from the gathered state: one process's values
     (the energies aside, whose sums are the ranks' parts: above). The
     outcome is shared after, so that a failure fails every rank. */
  int differs = 0;
  if (g_rank == 0) {
    const int monitors[] = {ND_ENERGY_NITSCHE, ND_CONTACT_FORCE, ND_ACTIVE_POINTS, ND_MAX_PENETRATION,
                            ND_CONTACT_FORCE_APPLIED};
    for (size_t i = 0; i < sizeof monitors / sizeof monitors[0]; ++i)
      if (scalar(split, monitors[i]) != scalar(alone, monitors[i])) differs = monitors[i];
    int64_t nodes = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(alone, &nodes));
    const size_t bytes = sizeof(double) * (size_t)(dim * nodes);
    double *x = malloc(bytes), *y = malloc(bytes);
    const int fields[] = {ND_FIELD_ACCELERATION, ND_FIELD_REACTION, ND_FIELD_CONTACT_FORCE};
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; ++i)
      if (nd_get_field(alone, fields[i], nodes, x) != ND_OK || nd_get_field(split, fields[i], nodes, y) != ND_OK ||
          memcmp(x, y, bytes) != 0)
        differs = 100 + fields[i];
    free(x), free(y);
  }
  MPI_Bcast(&differs, 1, MPI_INT, 0, MPI_COMM_WORLD);
  ck_assert_msg(differs == 0, "%s: queried alone on rank 0, monitor (or 100 + field) %d differs", what, differs);
}

static nd_problem explicit_disk(int distributed, double tau) {
  const double central[2] = {0.0, 0.5};
  char mesh[512];
  snprintf(mesh, sizeof mesh, "%s/disk_h4.msh", ND_MESH_DIR);
  nd_problem p = NULL;
  ND_OK_OR_FAIL(drop_scene_create(2, mesh, 1, ND_SCHEME_NEWMARK, central, 1.0, 1e-3, tau, ND_SOLVER_CHOLMOD, &p));
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  if (distributed) ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
  return p;
}

START_TEST(contact_points_and_rows_on_their_ranks) {
  for (int dim = 2; dim <= 3; ++dim) {
    nd_problem alone = scene(dim, ND_SOLVER_CHOLMOD, 0), split = scene(dim, ND_SOLVER_CHOLMOD, 1);
    compare_split(alone, split, dim, kSteps, dim == 2 ? "2D hybrid" : "3D hybrid");
    ND_OK_OR_FAIL(nd_problem_destroy(&alone));
    ND_OK_OR_FAIL(nd_problem_destroy(&split));
  }
  nd_problem alone = explicit_disk(0, 1.0);
  double tau_c = 0;
  ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(alone, &tau_c));
  ND_OK_OR_FAIL(nd_problem_destroy(&alone));
  const double tau = 0.9 * tau_c;
  alone = explicit_disk(0, tau);
  nd_problem split = explicit_disk(1, tau);
  compare_split(alone, split, 2, (int)(10.5 / tau), "2D explicit");
  ND_OK_OR_FAIL(nd_problem_destroy(&alone));
  ND_OK_OR_FAIL(nd_problem_destroy(&split));
}
END_TEST

START_TEST(a_load_refused_on_one_rank_fails_the_step_everywhere) {
  nd_problem p = scene(2, ND_SOLVER_PETSC_MUMPS, 1);
  for (int k = 0; k < 3; ++k) ND_OK_OR_FAIL(nd_step(p));
  snapshot before = take(p);
  const int64_t nodes = before.n / 2;
  double *f = calloc((size_t)before.n, sizeof(double));
  for (int64_t i = 0; i < nodes; ++i) f[2 * i + 1] = -0.01;
  const int last = g_rank == g_size - 1;
  if (last) f[1] = NAN; /* the guard refuses it there: that rank keeps the previous (no) nodal forces */
  const int set = nd_problem_set_nodal_forces(p, nodes, f);
  ck_assert_int_eq(set, last ? ND_ERR_NONFINITE : ND_OK);
  const int status = nd_step(p);
  char message[512];
  snprintf(message, sizeof message, "%s", nd_last_error());
  int lo = 0, hi = 0;
  MPI_Allreduce(&status, &lo, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  MPI_Allreduce(&status, &hi, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  ck_assert_msg(lo == hi, "the ranks' statuses differ: %d .. %d", lo, hi);
  snapshot after = take(p);
  if (g_size > 1) {
    ck_assert_msg(status == ND_ERR_STATE, "nd_step returned %d: %s", status, message);
    ck_assert_msg(strstr(message, "nd_step: the ranks") == message, "%s", message);
    ck_assert_msg(same_snapshot(&before, &after), "a rank's state moved in a refused step");
  } else {
    ND_OK_OR_FAIL(status); /* alone, the refused load is simply not there */
  }
  /* once every rank has the same load again, the ranks step together */
  f[1] = -0.01;
  ND_OK_OR_FAIL(nd_problem_set_nodal_forces(p, nodes, f));
  ND_OK_OR_FAIL(nd_step(p));
  snapshot next = take(p);
  ck_assert(next.t > before.t);
  ck_assert(nd_test_same_on_all_ranks(next.u, (int)(sizeof(double) * (size_t)next.n)));
  drop(&before), drop(&after), drop(&next);
  free(f);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* An overflow in the rows of some ranks only: a strip of 8 cells whose last
 * is a sliver (height 1e-9), with E = 1e300, overflows the stiffness in the
 * sliver's rows alone. The ranks assemble their own rows alone, then agree
 * before any of them factors (Problem::discretization_agreed): every rank's
 * nd_step fails with the overflow's code (the ranks without it point to the
 * others), the time stays 0, and with E = 1 the same problem steps. Without
 * the agreement the ranks that assembled would wait in the factorization. */
START_TEST(an_overflow_in_one_ranks_rows_fails_the_step_everywhere) {
  const double xy[] = {0, 0, 1, 0, 2, 0, 3, 0, 4, 0, 0, 1, 1, 1, 2, 1, 3, 1, 4, 1e-9};
  const int64_t cells[] = {0, 1, 6, 0, 6, 5, 1, 2, 7, 1, 7, 6, 2, 3, 8, 2, 8, 7, 3, 4, 9, 3, 9, 8};
  const double newmark[] = {0.25, 0.5};
  int alone = 0;
  for (int solver = ND_SOLVER_PETSC_MUMPS; solver <= ND_SOLVER_PETSC_GAMG; ++solver) {
    nd_mesh m = NULL;
    nd_problem p = NULL;
    ND_OK_OR_FAIL(nd_mesh_create(2, 10, xy, 8, cells, &m));
    ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
    ND_OK_OR_FAIL(nd_problem_set_material(p, 1e300, 0.3, 1.0));
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, newmark));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.01));
    ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, solver));
    ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
    const int status = nd_step(p);
    char message[512];
    snprintf(message, sizeof message, "%s", nd_last_error());
    const int own = strstr(message, "nd_step: the stiffness matrix overflows") == message;
    const int told = strstr(message, "failed on another rank") != NULL;
    ck_assert_msg(nd_test_on_all_ranks(status == ND_ERR_MATERIAL && (own || told)), "solver %d, rank %d: %d %s", solver,
                  g_rank, status, message);
    alone += told;
    double t = -1; /* the clock needs no operators: readable on every rank, still 0 */
    const int read = nd_get_scalar(p, ND_TIME, &t);
    ck_assert_msg(nd_test_on_all_ranks(read == ND_OK && t == 0), "solver %d, rank %d: ND_TIME %d, t = %g", solver,
                  g_rank, read, t);
    /* the first step again (t = tau) */
    ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.3, 1.0));
    ND_OK_OR_FAIL(nd_step(p));
    ck_assert(nd_test_on_all_ranks(scalar(p, ND_TIME) == 0.01));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  int told_somewhere = 0;
  MPI_Allreduce(&alone, &told_somewhere, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (g_rank == 0) printf("a sliver's overflow, %d rank(s): %d rank-solver pair(s) failed for another rank\n", g_size, told_somewhere);
}
END_TEST

/* A checkpoint restores the state bitwise on every rank. The run resumed from
 * it is bitwise the uninterrupted one on one rank; on several, MUMPS's and
 * PETSc's parallel reductions add contributions in the order messages arrive
 * (MUMPS schedules dynamically), so two runs of the same steps may differ in
 * the last bits, and the resumed run is held to the bound of the histories:
 * 1e-8 for MUMPS, the Krylov bound for GAMG. */
START_TEST(checkpoint_restores_bitwise) {
  for (int solver = ND_SOLVER_PETSC_MUMPS; solver <= ND_SOLVER_PETSC_GAMG; ++solver) {
    nd_problem p = scene(2, solver, 1);
    for (int k = 0; k < 36; ++k) ND_OK_OR_FAIL(nd_step(p));
    int64_t nbytes = 0;
    ND_OK_OR_FAIL(nd_problem_get_state_size(p, &nbytes));
    unsigned char *buf = malloc((size_t)nbytes), *again = malloc((size_t)nbytes);
    ND_OK_OR_FAIL(nd_problem_save_state(p, nbytes, buf));
    ck_assert_msg(nd_test_same_on_all_ranks(buf, (int)nbytes), "the checkpoints of the ranks differ");
    snapshot saved = take(p);
    for (int k = 0; k < 8; ++k) ND_OK_OR_FAIL(nd_step(p)); /* through the impact at t = 10 */
    snapshot straight = take(p);
    const double solves = scalar(p, ND_STAT_SOLVES);
    const double bound = solver == ND_SOLVER_PETSC_MUMPS ? 1e-8 : krylov_bound(p, 2, solves);

    /* in the same problem and in a new one on the same ranks */
    nd_problem q = scene(2, solver, 1);
    nd_problem targets[2] = {p, q};
    for (int which = 0; which < 2; ++which) {
      nd_problem r = targets[which];
      ND_OK_OR_FAIL(nd_problem_load_state(r, nbytes, buf));
      snapshot loaded = take(r);
      ck_assert_msg(same_snapshot(&saved, &loaded), "solver %d, problem %d: the loaded state differs", solver, which);
      ND_OK_OR_FAIL(nd_problem_save_state(r, nbytes, again));
      ck_assert_msg(memcmp(buf, again, (size_t)nbytes) == 0, "solver %d: saved again, the checkpoint differs", solver);
      for (int k = 0; k < 8; ++k) ND_OK_OR_FAIL(nd_step(r));
      snapshot resumed = take(r);
      const double gap = snapshot_gap(&straight, &resumed);
      if (g_size == 1)
        ck_assert_msg(same_snapshot(&straight, &resumed), "solver %d, problem %d: the resumed run differs (%.3g)",
                      solver, which, gap);
      else
        ck_assert_msg(resumed.t == straight.t && gap <= bound, "solver %d, problem %d: resumed %.3g off (bound %.3g)",
                      solver, which, gap, bound);
      drop(&loaded), drop(&resumed);
    }
    drop(&saved), drop(&straight);
    free(buf), free(again);
    ND_OK_OR_FAIL(nd_problem_destroy(&q));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* One field of p: this rank's part (nd_get_field_owned) against the whole
 * field (nd_get_field). The parts of all ranks, gathered, are disjoint, cover
 * every node, and placed at their node numbers are the whole field bitwise. */
static void check_owned_part(nd_problem p, int field, int dim) {
  int64_t n = 0, own = -1;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
  ck_assert(own >= 0 && own <= n);
  double *whole = malloc(sizeof(double) * (size_t)(n * dim));
  double *part = malloc(sizeof(double) * (size_t)(own * dim + 1));
  int64_t *nodes = malloc(sizeof(int64_t) * (size_t)(own + 1));
  /* gathered on each rank in turn (first: a field that needs a solve makes
   * it here, collectively): bitwise every rank's copy, nothing written elsewhere */
  double *gathered = malloc(sizeof(double) * (size_t)(n * dim));
  for (int root = 0; root < g_size; ++root) {
    for (int64_t i = 0; i < n * dim; ++i) gathered[i] = -7;
    ND_OK_OR_FAIL(nd_get_field_gathered(p, field, root, n, gathered));
    ND_OK_OR_FAIL(nd_get_field(p, field, n, whole));
    int as_expected = 1;
    for (int64_t i = 0; i < n * dim; ++i)
      as_expected &= g_rank == root ? memcmp(&gathered[i], &whole[i], sizeof(double)) == 0 : gathered[i] == -7;
    ck_assert_msg(nd_test_on_all_ranks(as_expected), "field %d gathered on rank %d: not the field there, or written elsewhere",
                  field, root);
  }
  free(gathered);
  ND_OK_OR_FAIL(nd_get_field_owned(p, field, own, part, nodes));
  for (int64_t i = 0; i < own; ++i) ck_assert(nodes[i] >= 0 && nodes[i] < n && (i == 0 || nodes[i] > nodes[i - 1]));

  int *counts = malloc(sizeof(int) * (size_t)g_size), *first = malloc(sizeof(int) * (size_t)g_size);
  int *vcounts = malloc(sizeof(int) * (size_t)g_size), *vfirst = malloc(sizeof(int) * (size_t)g_size);
  const int mine = (int)own;
  MPI_Allgather(&mine, 1, MPI_INT, counts, 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int r = 0; r < g_size; ++r) first[r] = total, vfirst[r] = total * dim, vcounts[r] = counts[r] * dim, total += counts[r];
  ck_assert_msg(total == n, "field %d: the ranks own %d nodes of %lld", field, total, (long long)n);
  int64_t *all_nodes = malloc(sizeof(int64_t) * (size_t)n);
  double *all_values = malloc(sizeof(double) * (size_t)(n * dim));
  MPI_Allgatherv(nodes, mine, MPI_INT64_T, all_nodes, counts, first, MPI_INT64_T, MPI_COMM_WORLD);
  MPI_Allgatherv(part, mine * dim, MPI_DOUBLE, all_values, vcounts, vfirst, MPI_DOUBLE, MPI_COMM_WORLD);
  char *seen = calloc((size_t)n, 1);
  for (int64_t k = 0; k < n; ++k) {
    const int64_t i = all_nodes[k];
    ck_assert_msg(i >= 0 && i < n && !seen[i], "field %d: node %lld owned twice or out of range", field, (long long)i);
    seen[i] = 1;
    ck_assert_msg(memcmp(&all_values[k * dim], &whole[i * dim], sizeof(double) * (size_t)dim) == 0,
                  "field %d: node %lld differs from nd_get_field", field, (long long)i);
  }
  free(seen), free(all_values), free(all_nodes);
  free(vfirst), free(vcounts), free(first), free(counts);
  free(nodes), free(part), free(whole);
}

/* the initial acceleration, M A = F - K_Theta U - N(U): a solve with the mass
 * matrix, whose rows the ranks fill from their copies (Factorization::factor) */
static double *initial_acceleration(nd_problem p, int dim, int64_t *n) {
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, n));
  double *a = malloc(sizeof(double) * (size_t)(*n * dim));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, *n, a));
  return a;
}

START_TEST(each_rank_reads_its_part_of_a_field) {
  for (int dim = 2; dim <= 3; ++dim) {
    /* the distributed mass solve against the serial one (the bound of the histories, MUMPS) */
    int64_t n = 0;
    nd_problem serial = scene(dim, ND_SOLVER_CHOLMOD, 0);
    double *a_serial = initial_acceleration(serial, dim, &n);
    ND_OK_OR_FAIL(nd_problem_destroy(&serial));
    nd_problem p = scene(dim, ND_SOLVER_PETSC_MUMPS, 1);
    double *a = initial_acceleration(p, dim, &n);
    const double gap = relative_gap(a_serial, a, (int)(n * dim));
    if (g_rank == 0) printf("%dD, %d rank(s): initial acceleration (MUMPS) %.2e off the serial solve\n", dim, g_size, gap);
    ck_assert_msg(gap <= 1e-8, "%dD: the initial acceleration is %.3g off the serial solve", dim, gap);
    free(a), free(a_serial);
    /* before the first step (the acceleration solves: collective) and after the impact at t = 10 */
    for (int stage = 0; stage < 2; ++stage) {
      for (int k = 0; stage == 1 && k < 42; ++k) ND_OK_OR_FAIL(nd_step(p));
      for (int field = ND_FIELD_DISPLACEMENT; field <= ND_FIELD_REACTION; ++field) check_owned_part(p, field, dim);
    }
    ck_assert_msg(scalar(p, ND_CONTACT_FORCE) > 0, "%dD: no contact at t = %g", dim, scalar(p, ND_TIME));
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }

  /* bad input fails and leaves the output arrays as they were */
  nd_problem p = scene(2, ND_SOLVER_PETSC_MUMPS, 1);
  int64_t own = 0;
  ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
  double *values = malloc(sizeof(double) * (size_t)(2 * own + 2));
  int64_t *nodes = malloc(sizeof(int64_t) * (size_t)(own + 1));
  for (int64_t i = 0; i < 2 * own + 2; ++i) values[i] = -7;
  for (int64_t i = 0; i < own + 1; ++i) nodes[i] = -7;
  ck_assert_int_eq(nd_problem_get_owned_node_count(p, NULL), ND_ERR_NULL);
  ck_assert_int_eq(nd_problem_get_owned_node_count(NULL, &own), ND_ERR_NULL);
  ck_assert_int_eq(nd_get_field_owned(NULL, ND_FIELD_DISPLACEMENT, own, values, nodes), ND_ERR_NULL);
  ck_assert_int_eq(nd_get_field_owned(p, ND_FIELD_DISPLACEMENT, own + 1, values, nodes), ND_ERR_SIZE);
  ck_assert_msg(strstr(nd_last_error(), "nd_get_field_owned: ") == nd_last_error(), "%s", nd_last_error());
  ck_assert_int_eq(nd_get_field_owned(p, 0, own, values, nodes), ND_ERR_KEY);
  ck_assert_int_eq(nd_get_field_owned(p, ND_FIELD_REACTION + 1, own, values, nodes), ND_ERR_KEY);
  for (int64_t i = 0; i < 2 * own + 2; ++i) ck_assert(values[i] == -7);
  for (int64_t i = 0; i < own + 1; ++i) ck_assert(nodes[i] == -7);
  /* the gathered field: a call refused on one rank is refused on every rank
   * with the same code (none is left waiting in the gather), and writes nothing */
  int64_t n_all = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n_all));
  double *whole = malloc(sizeof(double) * (size_t)(2 * n_all));
  for (int64_t i = 0; i < 2 * n_all; ++i) whole[i] = -7;
  const int last = g_size - 1;
  ck_assert_int_eq(nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, last, g_rank == last ? n_all + 1 : n_all, whole),
                   ND_ERR_SIZE);
  ck_assert_int_eq(nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, last, n_all, g_rank == last ? NULL : whole),
                   ND_ERR_NULL);
  ck_assert_int_eq(nd_get_field_gathered(p, g_rank == last ? 0 : ND_FIELD_VELOCITY, 0, n_all, whole), ND_ERR_KEY);
  ck_assert_int_eq(nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, g_size, n_all, whole), ND_ERR_VALUE);
  ck_assert_int_eq(nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, -1, n_all, whole), ND_ERR_VALUE);
  if (g_size > 1) {  /* valid calls that differ: another field, another root */
    ck_assert_int_eq(nd_get_field_gathered(p, g_rank == last ? ND_FIELD_VELOCITY : ND_FIELD_DISPLACEMENT, 0, n_all, whole),
                     ND_ERR_VALUE);
    ck_assert_msg(strstr(nd_last_error(), "same call") != NULL, "%s", nd_last_error());
    ck_assert_int_eq(nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, g_rank == last ? 0 : last, n_all, whole),
                     ND_ERR_VALUE);
  }
  for (int64_t i = 0; i < 2 * n_all; ++i) ck_assert(whole[i] == -7);
  /* on the other ranks n and out are not read */
  ND_OK_OR_FAIL(nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, 0, g_rank == 0 ? n_all : -3, g_rank == 0 ? whole : NULL));
  free(whole);
  /* the node numbers alone (no field computed), then the values alone */
  ND_OK_OR_FAIL(nd_get_field_owned(p, ND_FIELD_VELOCITY, own, NULL, nodes));
  ck_assert(nodes[own] == -7 && values[0] == -7);
  ND_OK_OR_FAIL(nd_get_field_owned(p, ND_FIELD_VELOCITY, own, values, NULL));
  ck_assert(values[2 * own] == -7);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));

  /* without a communicator the process owns every node, in order */
  p = scene(2, ND_SOLVER_PETSC_MUMPS, 0);
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
  ck_assert(own == n);
  int64_t *all = malloc(sizeof(int64_t) * (size_t)n);
  ND_OK_OR_FAIL(nd_get_field_owned(p, ND_FIELD_DISPLACEMENT, own, NULL, all));
  for (int64_t i = 0; i < n; ++i) ck_assert(all[i] == i);
  free(all), free(nodes), free(values);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* The operators by rows (slice 5): with a distributed solver on several
 * ranks, M, K and K_Theta hold each rank's rows only (src/problem/
 * discretization.hpp), and every product with them is the ranks' rows,
 * gathered. Checked through ND_STAT_MATRIX_ENTRIES_OWN:
 *  - every entry is held by one rank: the ranks' counts add up to one
 *    process's, and on several ranks each holds fewer (the histories above
 *    and the checkpoint test run on these operators);
 *  - operators made before the communicator are split when it comes, and
 *    whole again with a serial solver; with lumped mass (the explicit steps
 *    read the whole diagonal) every rank keeps the whole operators;
 *  - the energy of a state not set up (one process's checkpoint after 4
 *    steps, loaded) needs the ranks' rows: refused on one rank
 *    (ND_ERR_STATE, not a wrong value), then after nd_problem_setup the
 *    energy one process gave within the order of its sum (compare_split);
 *  - the coercivity check (Theta gamma0 above the element bound) factors
 *    K_Theta + delta M over the ranks, delta from every rank's diagonal,
 *    with MUMPS (also for GAMG, which certifies nothing): the verdict of
 *    CHOLMOD on the whole matrix in one process at gamma0 = 1.5, 2 and 4
 *    times the bound (coercive, refused by the check, and c M + K_Theta
 *    indefinite). */
static double sum_over_ranks(double x) {
  double sum = 0;
  MPI_Allreduce(&x, &sum, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return sum;
}

static int setup_status(int dim, int solver, int distributed, double gamma0) {
  char mesh[512];
  snprintf(mesh, sizeof mesh, "%s/%s_h4.msh", ND_MESH_DIR, dim == 2 ? "disk" : "ball");
  nd_problem p = NULL;
  ND_OK_OR_FAIL(drop_scene_create(dim, mesh, 1, ND_SCHEME_HYBRID, NULL, 1.0, gamma0, kTau, solver, &p));
  if (distributed) ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
  const int status = nd_problem_setup(p);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return status;
}

START_TEST(each_rank_holds_its_rows_of_the_operators) {
  for (int dim = 2; dim <= 3; ++dim) {
    /* one process's state after 4 steps of the fall, and its energy */
    nd_problem alone = scene(dim, ND_SOLVER_CHOLMOD, 0);
    for (int k = 0; k < 4; ++k) ND_OK_OR_FAIL(nd_step(alone));
    const double whole = scalar(alone, ND_STAT_MATRIX_ENTRIES_OWN), e0 = scalar(alone, ND_ENERGY_MECHANICAL);
    const double limit = scalar(alone, ND_GAMMA0_LIMIT);
    double tau_c0 = 0, tau_c = 0;
    ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(alone, &tau_c0));
    int64_t nodes = 0, nbytes = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(alone, &nodes));
    ND_OK_OR_FAIL(nd_problem_get_state_size(alone, &nbytes));
    void *state = malloc((size_t)nbytes);
    ND_OK_OR_FAIL(nd_problem_save_state(alone, nbytes, state));
    ND_OK_OR_FAIL(nd_problem_destroy(&alone));
    ck_assert(whole > 0 && e0 > 0);
    for (int solver = ND_SOLVER_PETSC_MUMPS; solver <= ND_SOLVER_PETSC_GAMG; ++solver) {
      nd_problem p = scene(dim, solver, 1);
      ND_OK_OR_FAIL(nd_problem_load_state(p, nbytes, state));  /* a restart: no products yet */
      double e = 0;
      ck_assert_int_eq(nd_get_scalar(p, ND_ENERGY_MECHANICAL, &e), g_size > 1 ? ND_ERR_STATE : ND_OK);
      if (g_size > 1)
        ck_assert_msg(strstr(nd_last_error(), "nd_problem_setup") != NULL, "%s", nd_last_error());
      ND_OK_OR_FAIL(nd_problem_setup(p));
      e = scalar(p, ND_ENERGY_MECHANICAL);
      const double bound = (double)(dim * nodes) * 1.1e-16 * 10;
      ck_assert_msg(fabs(e - e0) <= bound * e0, "%dD: energy %.17g after the set-up, %.17g in one process", dim, e,
                    e0);
      ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));  /* K_Theta x and M x: the ranks' rows */
      if (g_rank == 0)
        printf("%dD solver %d: critical step %.2e off one process's\n", dim, solver, fabs(tau_c - tau_c0) / tau_c0);
      ck_assert_msg(fabs(tau_c - tau_c0) <= 1e-8 * tau_c0, "%dD: critical step %.17g, %.17g in one process", dim, tau_c,
                    tau_c0);
      const double mine = scalar(p, ND_STAT_MATRIX_ENTRIES_OWN);
      ck_assert_double_eq(sum_over_ranks(mine), whole);
      if (g_size > 1) ck_assert_msg(mine < whole, "%dD: a rank holds %g of %g entries", dim, mine, whole);
      if (g_rank == 0 && solver == ND_SOLVER_PETSC_MUMPS)
        printf("%dD, %d rank(s): rank 0 holds %.0f of the operators' %.0f entries\n", dim, g_size, mine, whole);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
    free(state);
    /* operators made before the communicator (a query), then split when it
       comes; whole again with a serial solver (each rank factors them all) */
    nd_problem later = scene(dim, ND_SOLVER_PETSC_MUMPS, 0);
    ck_assert_double_eq(scalar(later, ND_GAMMA0_LIMIT), limit);
    ck_assert_double_eq(scalar(later, ND_STAT_MATRIX_ENTRIES_OWN), whole);
    ND_OK_OR_FAIL(nd_problem_set_comm(later, MPI_COMM_WORLD));
    ND_OK_OR_FAIL(nd_problem_setup(later));
    ck_assert_double_eq(sum_over_ranks(scalar(later, ND_STAT_MATRIX_ENTRIES_OWN)), whole);
    ND_OK_OR_FAIL(nd_problem_set_linear_solver(later, ND_SOLVER_CHOLMOD));
    ND_OK_OR_FAIL(nd_step(later));
    ck_assert_double_eq(scalar(later, ND_STAT_MATRIX_ENTRIES_OWN), whole);
    ND_OK_OR_FAIL(nd_problem_destroy(&later));
    nd_problem lumped = scene(dim, ND_SOLVER_PETSC_MUMPS, 1);
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(lumped, 1));
    ND_OK_OR_FAIL(nd_problem_setup(lumped));
    ck_assert_double_eq(scalar(lumped, ND_STAT_MATRIX_ENTRIES_OWN), whole);
    ND_OK_OR_FAIL(nd_problem_destroy(&lumped));

    int coercive = 0, refused = 0;
    const double factors[] = {1.5, 2, 4};
    for (size_t k = 0; k < sizeof factors / sizeof factors[0]; ++k) {
      const double gamma0 = factors[k] * limit;
      const int serial = setup_status(dim, ND_SOLVER_CHOLMOD, 0, gamma0);
      coercive += serial == ND_OK, refused += serial == ND_ERR_NOT_COERCIVE;
      ck_assert_int_eq(setup_status(dim, ND_SOLVER_PETSC_MUMPS, 1, gamma0), serial);
      /* GAMG cannot see that c M + K_Theta is indefinite (ND_ERR_INDEFINITE
         of a factorization): the check refuses such a K_Theta instead */
      ck_assert_int_eq(setup_status(dim, ND_SOLVER_PETSC_GAMG, 1, gamma0),
                       serial == ND_ERR_INDEFINITE ? ND_ERR_NOT_COERCIVE : serial);
    }
    if (g_rank == 0)
      printf("%dD: gamma0 = 1.5, 2, 4 x %.3g: %d coercive, %d refused by the check\n", dim, limit, coercive, refused);
    ck_assert_msg(coercive > 0 && refused > 0, "%dD: the check gave one verdict only", dim);
  }
}
END_TEST

/* Split operators (slice 6): every solve reads a rank's rows only, so the
 * right-hand side and the Newton residual stay on their rows, and a step
 * receives from the other ranks the solutions of its solves (their rows of
 * each), the contact points' values and a few sums, but no products. With
 * the operators whole (CHOLMOD on every rank) each rank gathers the other
 * rows of M U, M V and K U (the hybrid scheme: no M A) and no solution.
 * Counted by ND_STAT_VALUES_RECEIVED over a free-flight step. */
static void free_step_receives(int dim, int solver, double *other, double *rows_of_others, double *points) {
  /* other: the values received besides the solutions' rows */
  nd_problem p = scene(dim, solver, 1);
  ND_OK_OR_FAIL(nd_step(p)); /* the factorization and the set-up's passes */
  int64_t nodes = 0, own = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
  const double r0 = scalar(p, ND_STAT_VALUES_RECEIVED), s0 = scalar(p, ND_STAT_SOLVES);
  const double e0 = scalar(p, ND_STAT_POINT_EVALUATIONS) - scalar(p, ND_STAT_POINT_EVALUATIONS_OWN);
  const double v0 = scalar(p, ND_STAT_POINT_VALUES_RECEIVED);
  ND_OK_OR_FAIL(nd_step(p)); /* t = 0.5: free flight */
  ck_assert_double_eq(scalar(p, ND_ACTIVE_POINTS), 0);
  const double received = scalar(p, ND_STAT_VALUES_RECEIVED) - r0, solves = scalar(p, ND_STAT_SOLVES) - s0;
  *rows_of_others = (double)(dim * (nodes - own)); /* no clamped DOF in the drop scene */
  /* P_q (and u_n - g0) of the points the other ranks evaluated: none where
     the bound settled the step's checks (far from the obstacle: the new
     state's points left unevaluated, nd_get_field(3)) */
  *points = scalar(p, ND_STAT_POINT_EVALUATIONS) - scalar(p, ND_STAT_POINT_EVALUATIONS_OWN) - e0;
  /* the new state's pass, if made: their P_q and u_n - g0 */
  ck_assert(nd_test_on_all_ranks(scalar(p, ND_STAT_POINT_VALUES_RECEIVED) - v0 == 2 * *points));
  *other = received - (solver == ND_SOLVER_CHOLMOD ? 0 : solves * *rows_of_others);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}

START_TEST(a_step_on_split_rows_receives_no_products) {
  for (int dim = 2; dim <= 3; ++dim) {
    double other = 0, rows = 0, nc = 0;
    for (int solver = ND_SOLVER_PETSC_MUMPS; solver <= ND_SOLVER_PETSC_GAMG; ++solver) {
      free_step_receives(dim, solver, &other, &rows, &nc);
      if (g_rank == 0)
        printf("%dD solver %d, %d rank(s): a free-flight step received %.0f values besides its solutions "
               "(%.0f other rows, %.0f points evaluated by the others)\n", dim, solver, g_size, other, rows, nc);
      /* the P_q and u_n - g0 of the other ranks' points (the new state's
         pass over the points), each other rank's two energy sums and its
         two of the step (the loads' work on its rows, its non-finite values) */
      ck_assert_msg(nd_test_on_all_ranks(other == 2 * nc + 4 * (g_size - 1)), "%dD: %g values besides the solutions, %g points",
                    dim, other, nc);
    }
    /* through the impact: the Newton residuals stay on their rows too, so
       besides the solutions and the points' values a step receives only
       sums: per other rank, 4 per step (the energy's two, the step's work
       and non-finite count) and at most 6 per Newton iteration (the norms of
       r, G and M U, and of the update and the iterate). In 3D with GAMG, whose Newton refactors the tangent,
       every solve with it keeps the rows Newton reads (newton_held_rows: the
       rank's rows, their columns and the contact points' DOFs), and Newton
       gathers the other rows of U once per step. (The contact columns of the other Newton paths
       gather only the points' DOFs, then one whole U per step:
       tests/mpi_contact_columns.cpp counts them.) */
    if (dim == 3) {
      nd_problem p = scene(dim, ND_SOLVER_PETSC_GAMG, 1);
      /* the set-up: the products of the state at t = 0, one pass over the
         points, the others' nc of them */
      ND_OK_OR_FAIL(nd_problem_setup(p));
      const double nc_pass = scalar(p, ND_STAT_POINT_EVALUATIONS) - scalar(p, ND_STAT_POINT_EVALUATIONS_OWN);
      ND_OK_OR_FAIL(nd_step(p)); /* the factorization */
      const double r0 = scalar(p, ND_STAT_VALUES_RECEIVED), c0 = scalar(p, ND_STAT_CONTACT_EVALUATIONS);
      ND_OK_OR_FAIL(nd_step(p)); /* free flight */
      /* a step that evaluated no point left its new state's unevaluated (its
         checks settled by the bound: nd_get_field(3)); else the new state's
         pass gathers the others' P_q and u_n - g0 */
      const int evaluated = scalar(p, ND_STAT_CONTACT_EVALUATIONS) > c0;
      int64_t nodes = 0, own = 0;
      ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
      ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
      const double rows_of_others = (double)(dim * (nodes - own));
      /* its one solve, with A's factor, gathers the whole solution */
      ck_assert(nd_test_on_all_ranks(scalar(p, ND_STAT_VALUES_RECEIVED) - r0 ==
                                     rows_of_others + 2 * nc_pass * evaluated + 4 * (g_size - 1)));
      /* step by step: a solve with a refactored tangent (one per tangent
         assembly; GAMG keeps its hierarchy from tangent to tangent) keeps its
         held rows, `h` values from other ranks, and a step with one gathers
         the other rows of U once at its end; every other solve gathers a
         whole solution */
      double whole = 0, held_solves = 0, r = scalar(p, ND_STAT_VALUES_RECEIVED);
      const double v = scalar(p, ND_STAT_POINT_VALUES_RECEIVED), evaluations = scalar(p, ND_STAT_CONTACT_EVALUATIONS);
      double solves = scalar(p, ND_STAT_SOLVES), tangents = scalar(p, ND_STAT_TANGENT_UPDATES);
      const double factored = scalar(p, ND_STAT_FACTORIZATIONS);
      const int steps = kSteps - 2;
      int new_state_passes = 0; /* the steps whose new state's points were evaluated (above) */
      for (int k = 2; k < kSteps; ++k) {
        const double c = scalar(p, ND_STAT_CONTACT_EVALUATIONS);
        ND_OK_OR_FAIL(nd_step(p));
        new_state_passes += scalar(p, ND_STAT_CONTACT_EVALUATIONS) > c;
        const double t = scalar(p, ND_STAT_TANGENT_UPDATES) - tangents, sv = scalar(p, ND_STAT_SOLVES) - solves;
        whole += (sv - t + (t > 0)) * rows_of_others;
        held_solves += t;
        tangents += t, solves += sv;
      }
      /* the tangents' hierarchies: set up for the first, kept while they serve */
      const double setups = scalar(p, ND_STAT_FACTORIZATIONS) - factored;
      if (g_rank == 0) printf("3D GAMG, %d rank(s): %.0f tangents, %.0f set-ups\n", g_size, held_solves, setups);
      ck_assert(nd_test_on_all_ranks(setups >= 1 && setups < held_solves));
      ck_assert(scalar(p, ND_ACTIVE_POINTS) > 0 && held_solves > 0);
      /* the points' values: a step's new state, where evaluated, gathers P_q
         and u_n - g0 of the other ranks' points (2 nc_pass); a Newton pass
         receives only the points whose rows touch the rank's rows (slice
         10), at most the nc_pass a gather would */
      const double passes = scalar(p, ND_STAT_CONTACT_EVALUATIONS) - evaluations - new_state_passes;
      const double halo = scalar(p, ND_STAT_POINT_VALUES_RECEIVED) - v - 2.0 * new_state_passes * nc_pass;
      if (g_rank == 0)
        printf("%dD GAMG, %d rank(s): %.0f Newton passes over the points received %.0f of their values (a gather: "
               "%.0f each)\n", dim, g_size, passes, halo, nc_pass);
      ck_assert_msg(nd_test_on_all_ranks(passes > 0 && halo >= 0 && halo <= passes * nc_pass),
                    "%dD: %g values in %g passes, %g other points", dim, halo, passes, nc_pass);
      if (g_size > 1) ck_assert_msg(nd_test_on_all_ranks(halo < passes * nc_pass), "%dD: no pass was narrowed", dim);
      /* the rest is the held rows and the sums */
      const double rest = scalar(p, ND_STAT_VALUES_RECEIVED) - r - whole - (scalar(p, ND_STAT_POINT_VALUES_RECEIVED) - v);
      const double least = 4.0 * (g_size - 1) * steps; /* the energy's two and the step's two per step */
      const double most = 6.0 * (g_size - 1) * (steps + scalar(p, ND_NEWTON_ITERATIONS_TOTAL)) + least;
      const double h_lo = (rest - most) / held_solves, h_hi = (rest - least) / held_solves;
      if (g_rank == 0)
        printf("%dD GAMG, %d rank(s), %d steps through the impact, %.0f held solves: each received %.1f to %.1f "
               "values (a whole solution %.0f)\n", dim, g_size, steps, held_solves, h_lo, h_hi, rows_of_others);
      ck_assert_msg(nd_test_on_all_ranks(g_size == 1 ? rest == 0 : h_lo > 0 && h_hi < rows_of_others),
                    "%dD: a held solve received %g to %g values, a whole solution %g", dim, h_lo, h_hi, rows_of_others);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
    free_step_receives(dim, ND_SOLVER_CHOLMOD, &other, &rows, &nc);
    if (g_rank == 0)
      printf("%dD CHOLMOD on every rank: %.0f values received (%.0f other rows)\n", dim, other, rows);
    ck_assert_msg(nd_test_on_all_ranks(other == 3 * rows + 2 * nc + 2 * (g_size - 1)),
                  "%dD whole operators: %g values received, %g other rows", dim, other, rows);
  }
}
END_TEST

/* A distributed state (nd_problem_set_distributed_state): each rank keeps U,
 * V and A right on the rows its steps read, and no step gathers a whole
 * solution. The same scene stepped with the whole state on every rank (the
 * default) in the same process is the reference: the two make the same
 * solves and the same sums in the same order on those rows, so they agree
 * bitwise wherever PETSc repeats itself bitwise, which over several ranks it
 * does not always do (a second reference run, while this test was written:
 * MUMPS differed from itself now and then on 2 ranks, MUMPS and GAMG on 4,
 * at 1e-13; PT-Scotch's partition with several threads varies too). So
 * over several ranks the distributed run is held to the bound the other
 * tests hold the solvers to (1e-8 relative for MUMPS, the Krylov bound for
 * GAMG: a row read stale or missing is off by far more), and whether it was
 * bitwise is printed.
 * The scenes: the ball with GAMG (Newton refactors the tangent: every solve
 * keeps the rows), the disk and the ball with MUMPS (the condensed Newton on
 * the contact columns: its displacement is whole, its V and A are not).
 * Checked:
 *  - the monitors of every step (energies, forces, active points,
 *    penetration, Newton iterations, the loads' work, the time);
 *  - no contact point's value is received after the set-up (every rank
 *    holds U at every point's DOFs and evaluates the points it reads);
 *  - what a free-flight step receives for its solution: with the whole
 *    state exactly a whole solution's other rows; with a distributed one
 *    fewer, the held rows that are not the rank's (the refactoring Newton's
 *    solves, and the condensed Newton's, whose columns are held there);
 *  - the points a rank evaluates in a free-flight step (the new state's
 *    pass), on the refactoring path (GAMG in 3D): with the whole state its
 *    own, the ranks' adding up to every point once; with a distributed one
 *    the points it holds (slice 12), fewer than all on every rank, every
 *    point by one rank at least (with slice 11 each rank evaluated all);
 *  - the contact pressure and the applied one (collective here);
 *  - a rank's part of a field (nd_get_field_owned) and the whole field on
 *    one rank (nd_get_field_gathered) read as the state is, the owned part
 *    with no value received;
 *  - nd_get_field (collective here) for every field, the checkpoint, and a
 *    new problem resumed from it against the run that went on (GAMG's kept
 *    multigrid hierarchy depends on the history: the Krylov bound);
 *  - a field refused on the last rank alone is refused on every rank, and
 *    the layout is refused after the set-up. */
enum { kMonitors = 12, kRuns = 2, kRows = 3 }; /* rows: the two runs, the resumed one */

/* |x - y| relative to the largest |x| of the history: 0 (bitwise) or the gap */
static double history_gap(const double *x, const double *y, int n) {
  if (memcmp(x, y, sizeof(double) * (size_t)n) == 0) return 0;
  const double m = max_abs(x, n);
  return m > 0 ? relative_gap(x, y, n) : INFINITY;
}

/* the largest gap over the rows of a and b, relative to each row's largest |a| */
static double worst_gap(const double *a, const double *b, int rows, int n) {
  double worst = 0;
  for (int r = 0; r < rows; ++r) worst = worse(worst, history_gap(a + r * n, b + r * n, n));
  return worst;
}

static void compare_layouts(int dim, int solver) {
  nd_problem run[kRuns]; /* the whole state (the reference), the distributed state */
  for (int r = 0; r < kRuns; ++r) run[r] = scene(dim, solver, 1);
  nd_problem whole = run[0], kept = run[1];
  ND_OK_OR_FAIL(nd_problem_set_distributed_state(kept, 1));
  int64_t nodes = 0, own = 0, own_whole = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(kept, &nodes));
  ND_OK_OR_FAIL(nd_problem_get_owned_node_count(kept, &own));
  ND_OK_OR_FAIL(nd_problem_get_owned_node_count(whole, &own_whole));
  const int monitors[kMonitors] = {ND_ENERGY_MECHANICAL, ND_ENERGY_AUGMENTED, ND_ENERGY_NITSCHE, ND_CONTACT_FORCE,
                                   ND_CONTACT_FORCE_APPLIED, ND_ACTIVE_POINTS, ND_MAX_PENETRATION,
                                   ND_NEWTON_ITERATIONS, ND_WORK, ND_TIME, ND_STEP_INDEX, ND_WORK_OBSTACLE};
  const int steps = kSteps + 6;
  double *h = calloc((size_t)(kRows * kMonitors * steps), sizeof(double));
#define H(r, m, k) h[((r) * kMonitors + (m)) * steps + (k)]
  /* what a rank receives; in free-flight steps, besides the points' values
     and the 4 sums per other rank: a whole solution's other rows with the
     whole state, only the held rows that are not the rank's with a
     distributed one, on the refactoring path (the most, the least of them) */
  double received[kRuns] = {0}, solution[kRuns][2] = {{0, INFINITY}, {0, INFINITY}};
  double point_values[kRuns] = {0};
  int contact_steps = 0, free_steps = 0;
  /* the refactoring path on a distributed state holds the rank's points
     (slice 12): its step also adds the points' sums over the ranks, 6 values
     per other rank; the points evaluated in a free step (the most, the least) */
  const int holds_points = dim == 3 && solver == ND_SOLVER_PETSC_GAMG && g_size > 1;
  const double sums[kRuns] = {4, holds_points ? 10 : 4};
  double evaluated[kRuns][2] = {{0, INFINITY}, {0, INFINITY}}; /* (the fewest is [1]) */
  int64_t n_points = 0;
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(kept, &n_points));
  for (int k = 0; k < kSteps; ++k) {
    for (int r = 0; r < kRuns; ++r) {
      const double r0 = scalar(run[r], ND_STAT_VALUES_RECEIVED), p0 = scalar(run[r], ND_STAT_POINT_VALUES_RECEIVED);
      const double active_before = k > 0 ? scalar(run[r], ND_ACTIVE_POINTS) : 0;
      const double e0 = scalar(run[r], ND_STAT_POINT_EVALUATIONS_OWN);
      ND_OK_OR_FAIL(nd_step(run[r]));
      const double d = scalar(run[r], ND_STAT_VALUES_RECEIVED) - r0;
      received[r] += d;
      if (k > 0) point_values[r] += scalar(run[r], ND_STAT_POINT_VALUES_RECEIVED) - p0;
      for (int m = 0; m < kMonitors; ++m) H(r, m, k) = scalar(run[r], monitors[m]);
      if (k > 0 && active_before == 0 && scalar(run[r], ND_ACTIVE_POINTS) == 0 &&
          scalar(run[r], ND_NEWTON_ITERATIONS) == 1) {
        const double rest = d - (scalar(run[r], ND_STAT_POINT_VALUES_RECEIVED) - p0) - sums[r] * (g_size - 1);
        solution[r][0] = fmax(solution[r][0], rest), solution[r][1] = fmin(solution[r][1], rest);
        const double e = scalar(run[r], ND_STAT_POINT_EVALUATIONS_OWN) - e0;
        evaluated[r][0] = fmax(evaluated[r][0], e), evaluated[r][1] = fmin(evaluated[r][1], e);
        free_steps += r == 1;
      }
    }
    contact_steps += scalar(kept, ND_ACTIVE_POINTS) > 0;
  }
  ck_assert_msg(nd_test_on_all_ranks(contact_steps > 0 && free_steps > 0), "%dD: %d contact and %d free steps", dim, contact_steps, free_steps);
  /* after the set-up's pass (a whole state: gathered), each rank evaluates
     the points it reads itself: no point's value travels */
  ck_assert_msg(nd_test_on_all_ranks(point_values[1] == 0 && (g_size == 1 || point_values[0] > 0)),
                "%dD: the points' values received: %g, %g with the whole state", dim, point_values[1], point_values[0]);
  /* (each run's own partition: PT-Scotch's may differ from problem to
     problem; the rows of the others are those of the partition's nodes) */
  for (int r = 0; r < kRuns; ++r) {
    int64_t own_r = 0;
    ND_OK_OR_FAIL(nd_problem_get_owned_node_count(run[r], &own_r));
    const double others = (double)(dim * (nodes - own_r)); /* (no clamped DOF in the drop scene) */
    if (r == 0 || g_size == 1)
      ck_assert_msg(nd_test_on_all_ranks(solution[r][0] == others && solution[r][1] == others),
                    "%dD run %d: a free step's solution %g to %g values, the other rows %g", dim, r, solution[r][1],
                    solution[r][0], others);
    else
      ck_assert_msg(nd_test_on_all_ranks(solution[r][1] > 0 && solution[r][0] < others),
                    "%dD: a free step's held rows %g to %g values, the other rows %g", dim, solution[r][1],
                    solution[r][0], others);
  }
  if (dim == 3 && solver == ND_SOLVER_PETSC_GAMG) {
    /* the fewest of a free step, added over the ranks: with the state whole
       on every rank none (far from the obstacle the bound settles the
       step's checks and leaves the new state's points unevaluated:
       nd_get_field(3)); with the points each rank holds, the new state's
       pass over them (no point left unevaluated: that needs a whole state) */
    double total[kRuns];
    for (int r = 0; r < kRuns; ++r) MPI_Allreduce(&evaluated[r][1], &total[r], 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    if (g_rank == 0)
      printf("3D GAMG, %d rank(s): a free step evaluates %g of %" PRId64 " points on rank 0 (%g over the ranks), %g "
             "with the whole state (%g)\n",
             g_size, evaluated[1][1], n_points, total[1], evaluated[0][1], total[0]);
    ck_assert_msg(total[0] == 0, "the whole state's free step: %g points over the ranks, not 0 (of %" PRId64 ")",
                  total[0], n_points);
    /* the contact checks the bound settled: the job's count, the same on
       every rank; with the rank's points each rank's bound reads fewer DOFs
       (a smaller max |U - U^n|), so at least as many as the whole state's */
    double bounds[2] = {scalar(kept, ND_STAT_CONTACT_BOUNDS), -scalar(kept, ND_STAT_CONTACT_BOUNDS)};
    MPI_Allreduce(MPI_IN_PLACE, bounds, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    if (g_rank == 0)
      printf("  contact checks settled by the bound: %g, %g with the whole state\n", bounds[0],
             scalar(whole, ND_STAT_CONTACT_BOUNDS));
    ck_assert_msg(bounds[0] == -bounds[1] && bounds[0] >= scalar(whole, ND_STAT_CONTACT_BOUNDS) && bounds[0] > 0,
                  "contact checks settled by the bound: %g to %g over the ranks, %g with the whole state", -bounds[1],
                  bounds[0], scalar(whole, ND_STAT_CONTACT_BOUNDS));
    if (holds_points)
      ck_assert_msg(nd_test_on_all_ranks(evaluated[1][1] < (double)n_points) && total[1] >= (double)n_points,
                    "the distributed state's free step: %g of %" PRId64 " points on this rank, %g over the ranks",
                    evaluated[1][1], n_points, total[1]);
    else  /* (one rank: its distributed state is whole) */
      ck_assert(evaluated[1][1] == 0);
  }
  /* One rank: bitwise (nothing is split). More: the solver's bound (see
     above); whether the two runs had the same partition is reported */
  int64_t *na = malloc(sizeof(int64_t) * (size_t)(own_whole + 1)), *nb = malloc(sizeof(int64_t) * (size_t)(own + 1));
  ND_OK_OR_FAIL(nd_get_field_owned(whole, ND_FIELD_DISPLACEMENT, own_whole, NULL, na));
  ND_OK_OR_FAIL(nd_get_field_owned(kept, ND_FIELD_DISPLACEMENT, own, NULL, nb));
  const int same_partition =
      nd_test_on_all_ranks(own == own_whole && memcmp(na, nb, sizeof(int64_t) * (size_t)own) == 0);
  const double gap = worst_gap(&H(0, 0, 0), &H(1, 0, 0), kMonitors, kSteps);
  const double solves = scalar(whole, ND_STAT_SOLVES);
  const double bound = g_size == 1 ? 0 : solver == ND_SOLVER_PETSC_MUMPS ? 1e-8 : krylov_bound(whole, dim, solves);
  if (g_rank == 0)
    printf("%dD solver %d, %d rank(s), %d steps: the distributed state %.2e off the whole one (bound %.2e, %s "
           "partition); %.0f values received, %.0f with the distributed state (a free step's solution %.0f "
           "against %.0f)\n",
           dim, solver, g_size, kSteps, gap, bound, same_partition ? "the same" : "another", received[0], received[1],
           solution[1][0], solution[0][0]);
  ck_assert_msg(nd_test_on_all_ranks(gap <= bound), "%dD solver %d: the distributed state's monitors %.3g off (bound %.3g)",
                dim, solver, gap, bound);
  /* the pressures of every point (collective with a distributed state: its
     points are gathered), the reference's within the bound */
  double *pa = malloc(sizeof(double) * (size_t)(n_points + 1)), *pb = malloc(sizeof(double) * (size_t)(n_points + 1));
  for (int applied = 0; applied < 2; ++applied) {
    int (*get)(nd_problem, int64_t, double *) = applied ? nd_get_contact_pressure_applied : nd_get_contact_pressure;
    ND_OK_OR_FAIL(get(whole, n_points, pa));
    ND_OK_OR_FAIL(get(kept, n_points, pb));
    ck_assert_msg(max_abs(pa, (int)n_points) > 0, "%dD: no pressure to compare", dim);
    ck_assert_msg(history_gap(pa, pb, (int)n_points) <= bound, "%dD pressure (applied: %d) %.3g off the reference's",
                  dim, applied, history_gap(pa, pb, (int)n_points));
  }
  free(pa), free(pb);

  /* every field: this rank's part read as the state is (no message but
     for the acceleration, an equilibrium solve over the ranks that
     completes the state), the whole field on rank 0, then the whole field
     on every rank (collective): the part and the gathered field bitwise the
     whole one, which is the reference's within the bound */
  const int n = (int)(dim * nodes), fields = ND_FIELD_REACTION;
  const size_t bytes = sizeof(double) * (size_t)n;
  double *part = malloc(sizeof(double) * (size_t)(fields * dim * own + 1)), *root = malloc(bytes * (size_t)fields);
  double *a = malloc(bytes), *b = malloc(bytes);
  for (int field = 1; field <= fields; ++field) {
    const double r0 = scalar(kept, ND_STAT_VALUES_RECEIVED);
    ND_OK_OR_FAIL(nd_get_field_owned(kept, field, own, part + (field - 1) * dim * own, nb));
    if (field != ND_FIELD_ACCELERATION)
      ck_assert_msg(scalar(kept, ND_STAT_VALUES_RECEIVED) == r0, "%dD field %d: the owned part received values", dim,
                    field);
    ND_OK_OR_FAIL(nd_get_field_gathered(kept, field, 0, nodes, root + (size_t)(field - 1) * (size_t)n));
  }
  for (int field = 1; field <= fields; ++field) {
    ND_OK_OR_FAIL(nd_get_field(whole, field, nodes, a));
    ND_OK_OR_FAIL(nd_get_field(kept, field, nodes, b));
    int same = 1;
    for (int64_t k = 0; k < own; ++k)
      same &= memcmp(part + (field - 1) * dim * own + k * dim, b + nb[k] * dim, sizeof(double) * (size_t)dim) == 0;
    ck_assert_msg(same, "%dD field %d: this rank's part is not the whole field's", dim, field);
    if (g_rank == 0)
      ck_assert_msg(memcmp(root + (size_t)(field - 1) * (size_t)n, b, bytes) == 0,
                    "%dD field %d: gathered on rank 0, not the whole field", dim, field);
    ck_assert_msg(history_gap(a, b, n) <= bound, "%dD field %d: %.3g off the reference's", dim, field,
                  history_gap(a, b, n));
  }
  /* a step leaves the state partial again: refused on the last rank alone,
     refused on every rank, and no rank waits; then completed */
  for (int r = 0; r < kRuns; ++r) ND_OK_OR_FAIL(nd_step(run[r]));
  const int last = g_rank == g_size - 1;
  const int refused = nd_get_field(kept, ND_FIELD_DISPLACEMENT, last ? nodes + 1 : nodes, b);
  ck_assert_msg(nd_test_on_all_ranks(refused == ND_ERR_SIZE), "rank %d: %d for a size refused on the last rank", g_rank,
                refused);
  for (int field = 1; field <= fields; ++field) {
    ND_OK_OR_FAIL(nd_get_field(whole, field, nodes, a));
    ND_OK_OR_FAIL(nd_get_field(kept, field, nodes, b));
    ck_assert_msg(history_gap(a, b, n) <= bound, "%dD field %d: the completed state %.3g off", dim, field,
                  history_gap(a, b, n));
  }
  /* the checkpoint of a distributed state (collective), then the runs go on */
  for (int r = 0; r < kRuns; ++r) ND_OK_OR_FAIL(nd_step(run[r]));
  int64_t size_whole = 0, size_kept = 0;
  unsigned char *cw = nd_test_checkpoint(whole, &size_whole), *ck = nd_test_checkpoint(kept, &size_kept);
  ck_assert_int_eq(size_whole, size_kept);
  if (g_size == 1) ck_assert_msg(memcmp(cw, ck, (size_t)size_whole) == 0, "%dD: the checkpoints differ", dim);
  nd_problem resumed = scene(dim, solver, 1);
  ND_OK_OR_FAIL(nd_problem_set_distributed_state(resumed, 1));
  ND_OK_OR_FAIL(nd_problem_load_state(resumed, size_kept, ck));
  /* the resumed run (row 2) against the distributed one that went on */
  for (int k = kSteps; k < steps; ++k) {
    ND_OK_OR_FAIL(nd_step(kept));
    ND_OK_OR_FAIL(nd_step(resumed));
    for (int m = 0; m < kMonitors; ++m) H(1, m, k) = scalar(kept, monitors[m]), H(2, m, k) = scalar(resumed, monitors[m]);
  }
  double resumed_gap = 0;
  for (int m = 0; m < kMonitors; ++m)
    resumed_gap = worse(resumed_gap, history_gap(&H(1, m, kSteps), &H(2, m, kSteps), steps - kSteps));
  /* bitwise on one rank, as checkpoint_restores_bitwise; on more, MUMPS
     solves the contact columns of a step in blocks whose make-up depends on
     the history, and GAMG's Newton (3D) keeps a multigrid hierarchy from
     earlier tangents */
  const double resume_bound = g_size == 1 && !(solver == ND_SOLVER_PETSC_GAMG && dim == 3)
                                  ? 0
                                  : solver == ND_SOLVER_PETSC_MUMPS ? 1e-8 : krylov_bound(kept, dim, scalar(kept, ND_STAT_SOLVES));
  if (g_rank == 0) printf("  resumed from its checkpoint: %.2e off the run that went on (bound %.2e)\n", resumed_gap, resume_bound);
  ck_assert_msg(nd_test_on_all_ranks(resumed_gap <= resume_bound), "%dD: resumed %.3g off (bound %.3g)", dim,
                resumed_gap, resume_bound);
  ck_assert_int_eq(nd_problem_set_distributed_state(kept, 0), ND_ERR_STATE);
#undef H
  free(h), free(cw), free(ck), free(a), free(b), free(na), free(nb), free(part), free(root);
  ND_OK_OR_FAIL(nd_problem_destroy(&resumed));
  for (int r = 0; r < kRuns; ++r) ND_OK_OR_FAIL(nd_problem_destroy(&run[r]));
}

/* A distributed state made by one integrator and stepped by another: the
 * ball in contact with GAMG (the refactoring Newton: the rank's points),
 * then MUMPS (the condensed Newton: every point, other held rows). The
 * new integrator's first step completes the state; against the same run
 * with the whole state, within GAMG's Krylov bound. Without the
 * completion the MUMPS step reads rows and points the GAMG steps left NaN. */
START_TEST(a_change_of_solver_completes_a_distributed_state) {
  enum { kBefore = 42, kAfter = 3 }; /* in contact at t = 10.5 */
  nd_problem run[2];
  double mon[2][kAfter][4];
  for (int r = 0; r < 2; ++r) {
    run[r] = scene(3, ND_SOLVER_PETSC_GAMG, 1);
    if (r == 1) ND_OK_OR_FAIL(nd_problem_set_distributed_state(run[r], 1));
    for (int k = 0; k < kBefore; ++k) ND_OK_OR_FAIL(nd_step(run[r]));
    ck_assert(scalar(run[r], ND_ACTIVE_POINTS) > 0);
    ND_OK_OR_FAIL(nd_problem_set_linear_solver(run[r], ND_SOLVER_PETSC_MUMPS));
    for (int k = 0; k < kAfter; ++k) {
      ND_OK_OR_FAIL(nd_step(run[r]));
      const int keys[4] = {ND_ENERGY_AUGMENTED, ND_CONTACT_FORCE, ND_ACTIVE_POINTS, ND_WORK_OBSTACLE};
      for (int m = 0; m < 4; ++m) mon[r][k][m] = scalar(run[r], keys[m]);
    }
  }
  const double bound = krylov_bound(run[0], 3, scalar(run[0], ND_STAT_SOLVES));
  double gap = 0;
  for (int m = 0; m < 4; ++m) {
    double a[kAfter], b[kAfter];
    for (int k = 0; k < kAfter; ++k) a[k] = mon[0][k][m], b[k] = mon[1][k][m];
    gap = worse(gap, memcmp(a, b, sizeof a) == 0 ? 0 : relative_gap(a, b, kAfter));
  }
  if (g_rank == 0) printf("GAMG then MUMPS, %d rank(s): the distributed state %.2e off the whole one (bound %.2e)\n", g_size, gap, bound);
  ck_assert_msg(nd_test_on_all_ranks(gap <= bound), "%.3g off (bound %.3g)", gap, bound);
  for (int r = 0; r < 2; ++r) ND_OK_OR_FAIL(nd_problem_destroy(&run[r]));
}
END_TEST

START_TEST(a_distributed_state_gathers_no_solution) {
  compare_layouts(3, ND_SOLVER_PETSC_GAMG);
  compare_layouts(2, ND_SOLVER_PETSC_MUMPS);
  compare_layouts(3, ND_SOLVER_PETSC_MUMPS);
}
END_TEST

/* A step that fails on every rank once it is computed (the penetration
 * guard at 1e-9 h_K, in contact, where Nitsche's points sink by more)
 * leaves a distributed state as it was: every rank's own part
 * bitwise, the time and the monitors too; with the guard back at its
 * default the problem steps on, and its next state is the one of a twin
 * that was never refused (bitwise on one rank; over several within the solver's bound, the
 * twin being another problem: see compare_layouts). The disk with MUMPS
 * and the ball with GAMG, each in both layouts. */
static void failed_step_in_layout(int dim, int solver, int distributed) {
  nd_problem p = scene(dim, solver, 1), twin = scene(dim, solver, 1);
  ND_OK_OR_FAIL(nd_problem_set_distributed_state(p, distributed));
  ND_OK_OR_FAIL(nd_problem_set_distributed_state(twin, distributed));
  while (scalar(p, ND_ACTIVE_POINTS) == 0 && scalar(p, ND_TIME) < 12) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_step(twin));
  }
  ck_assert_msg(scalar(p, ND_ACTIVE_POINTS) > 0, "%dD: no contact", dim);
  int64_t own = 0, nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  const size_t part = (size_t)(dim * own) + 1;
  double *u0 = malloc(sizeof(double) * part), *v0 = malloc(sizeof(double) * part);
  double *u1 = malloc(sizeof(double) * part), *v1 = malloc(sizeof(double) * part);
  ND_OK_OR_FAIL(nd_get_field_owned(p, ND_FIELD_DISPLACEMENT, own, u0, NULL));
  ND_OK_OR_FAIL(nd_get_field_owned(p, ND_FIELD_VELOCITY, own, v0, NULL));
  const double t0 = scalar(p, ND_TIME), e0 = scalar(p, ND_ENERGY_AUGMENTED), f0 = scalar(p, ND_CONTACT_FORCE);
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_PENETRATION, 1e-9));
  const int status = nd_step(p);
  ck_assert_msg(nd_test_on_all_ranks(status == ND_ERR_PENETRATION), "%dD layout %d: nd_step returned %d: %s", dim,
                distributed, status, nd_last_error());
  ND_OK_OR_FAIL(nd_get_field_owned(p, ND_FIELD_DISPLACEMENT, own, u1, NULL));
  ND_OK_OR_FAIL(nd_get_field_owned(p, ND_FIELD_VELOCITY, own, v1, NULL));
  const double t1 = scalar(p, ND_TIME), e1 = scalar(p, ND_ENERGY_AUGMENTED), f1 = scalar(p, ND_CONTACT_FORCE);
  ck_assert_msg(memcmp(u0, u1, sizeof(double) * (part - 1)) == 0 && memcmp(v0, v1, sizeof(double) * (part - 1)) == 0,
                "%dD layout %d: a rank's part moved in a failed step", dim, distributed);
  ck_assert_msg(t0 == t1 && memcmp(&e0, &e1, sizeof e0) == 0 && memcmp(&f0, &f1, sizeof f0) == 0,
                "%dD layout %d: the monitors moved in a failed step", dim, distributed);
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_PENETRATION, 4)); /* the default (design.md §3b) */
  for (int k = 0; k < 3; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_step(twin));
  }
  const size_t bytes = sizeof(double) * (size_t)(dim * nodes);
  double *a = malloc(bytes), *b = malloc(bytes);
  ND_OK_OR_FAIL(nd_get_field(twin, ND_FIELD_VELOCITY, nodes, a));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, nodes, b));
  const double gap = history_gap(a, b, (int)(dim * nodes));
  const double bound =
      g_size == 1 ? 0 : solver == ND_SOLVER_PETSC_MUMPS ? 1e-8 : krylov_bound(twin, dim, scalar(twin, ND_STAT_SOLVES));
  if (g_rank == 0)
    printf("%dD solver %d layout %d, %d rank(s): after a step refused at t = %g, 3 steps on: %.2e off a twin "
           "that was never refused (bound %.2e)\n", dim, solver, distributed, g_size, t0, gap, bound);
  ck_assert_msg(nd_test_on_all_ranks(gap <= bound), "%dD layout %d: %.3g off the twin (bound %.3g)", dim, distributed,
                gap, bound);
  free(u0), free(v0), free(u1), free(v1), free(a), free(b);
  ND_OK_OR_FAIL(nd_problem_destroy(&twin));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}

START_TEST(a_failed_step_leaves_a_distributed_state_as_it_was) {
  for (int distributed = 0; distributed <= 1; ++distributed) {
    failed_step_in_layout(2, ND_SOLVER_PETSC_MUMPS, distributed);
    failed_step_in_layout(3, ND_SOLVER_PETSC_GAMG, distributed);
  }
}
END_TEST

/* An explicit step on split rows: the central difference with consistent
 * mass, MUMPS on every rank count, K_Theta U from the ranks' rows and a
 * distributed mass solve each step, through the impact, against one
 * process with CHOLMOD: the energy and contact-force histories to 1e-8
 * relative, as the implicit ones above, and the same active sets. */
static nd_problem explicit_consistent(int solver, int distributed, double tau) {
  const double central[2] = {0.0, 0.5};
  char mesh[512];
  snprintf(mesh, sizeof mesh, "%s/disk_h4.msh", ND_MESH_DIR);
  nd_problem p = NULL;
  ND_OK_OR_FAIL(drop_scene_create(2, mesh, 1, ND_SCHEME_NEWMARK, central, 1.0, 1e-3, tau, solver, &p));
  if (distributed) ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
  return p;
}

START_TEST(explicit_steps_on_split_rows) {
  nd_problem p = explicit_consistent(ND_SOLVER_CHOLMOD, 0, 1.0);
  double tau_c = 0;
  ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  const double tau = 0.9 * tau_c;
  const int steps = (int)(10.5 / tau);
  nd_problem alone = explicit_consistent(ND_SOLVER_CHOLMOD, 0, tau);
  nd_problem split = explicit_consistent(ND_SOLVER_PETSC_MUMPS, 1, tau);
  double *e = calloc(4 * (size_t)steps, sizeof(double)), *f = e + steps, *e_s = f + steps, *f_s = e_s + steps;
  for (int k = 0; k < steps; ++k) {
    ND_OK_OR_FAIL(nd_step(alone));
    ND_OK_OR_FAIL(nd_step(split));
    e[k] = scalar(alone, ND_ENERGY_MECHANICAL), e_s[k] = scalar(split, ND_ENERGY_MECHANICAL);
    f[k] = scalar(alone, ND_CONTACT_FORCE), f_s[k] = scalar(split, ND_CONTACT_FORCE);
    ck_assert_msg(scalar(alone, ND_ACTIVE_POINTS) == scalar(split, ND_ACTIVE_POINTS), "step %d: active sets differ", k);
  }
  const double e_gap = relative_gap(e, e_s, steps), f_gap = relative_gap(f, f_s, steps);
  if (g_rank == 0)
    printf("explicit, consistent mass, %d rank(s), %d steps: energy %.2e force %.2e off one process's\n", g_size, steps,
           e_gap, f_gap);
  ck_assert_msg(max_abs(f, steps) > 0, "no impact within the horizon");
  ck_assert_msg(e_gap <= 1e-8 && f_gap <= 1e-8, "energy %.3g, force %.3g off one process's", e_gap, f_gap);
  if (g_size > 1) {
    int64_t nodes = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(split, &nodes));
    const double mine = scalar(split, ND_STAT_MATRIX_ENTRIES_OWN), whole = scalar(alone, ND_STAT_MATRIX_ENTRIES_OWN);
    ck_assert_msg(mine < whole, "a rank holds %g of %g entries", mine, whole);
  }
  free(e);
  ND_OK_OR_FAIL(nd_problem_destroy(&alone));
  ND_OK_OR_FAIL(nd_problem_destroy(&split));
}
END_TEST

/* More ranks than cells: the bar of docs/design.md §7 (clamped at x = 1: the
 * reactions' rows) in 3 cells, so that on 4 ranks one owns no cell and no
 * row, stepped with MUMPS over the ranks against one process with CHOLMOD:
 * energy, contact force and reaction histories within 1e-8 of the largest
 * value. */
/* The bar of docs/design.md §7 (clamped at x = 1, the obstacle at x = 0), in three
 * runs: CHOLMOD in one process, MUMPS over the ranks, and MUMPS over the
 * ranks with a distributed state, whose rows include the clamped rows'
 * columns (the reactions read them). The energy, contact force and
 * reaction histories of both MPI runs within 1e-8 of one process's. With 3
 * cells some ranks own no node on 4 ranks; with 40 each has a share. */
static void bar_layouts(int cells) {
  enum { kBarSteps = 60 };
  double e[3][kBarSteps], f[3][kBarSteps], r[3][kBarSteps];
  for (int run = 0; run < 3; ++run) {
    nd_problem p = nd_test_bar(cells, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.0, 0.05);
    if (run > 0) {
      ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, ND_SOLVER_PETSC_MUMPS));
      ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
      ND_OK_OR_FAIL(nd_problem_set_distributed_state(p, run == 2));
    }
    for (int k = 0; k < kBarSteps; ++k) {
      ND_OK_OR_FAIL(nd_step(p));
      double reaction[41];
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_REACTION, cells + 1, reaction));
      e[run][k] = scalar(p, ND_ENERGY_AUGMENTED), f[run][k] = scalar(p, ND_CONTACT_FORCE);
      r[run][k] = reaction[cells]; /* the clamped end, x = 1 */
    }
    int64_t own = 0;
    ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
    double owners = own > 0, total = sum_over_ranks(owners);
    if (run > 0 && cells == 3 && g_size > 3) ck_assert_msg(total < g_size, "every rank owns a node of the 3-cell bar");
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  ck_assert_msg(max_abs(f[0], kBarSteps) > 0, "no contact within the horizon");
  for (int run = 1; run < 3; ++run) {
    const double de = relative_gap(e[0], e[run], kBarSteps), df = relative_gap(f[0], f[run], kBarSteps),
                 dr = relative_gap(r[0], r[run], kBarSteps);
    if (g_rank == 0)
      printf("bar of %d cells, %d rank(s)%s: energy %.2e force %.2e reaction %.2e\n", cells, g_size,
             run == 2 ? ", distributed state" : "", de, df, dr);
    ck_assert_msg(de <= 1e-8 && df <= 1e-8 && dr <= 1e-8, "%d cells, run %d: energy %.3g, force %.3g, reaction %.3g",
                  cells, run, de, df, dr);
  }
}

START_TEST(a_bar_on_more_ranks_than_cells) {
  bar_layouts(3);
  bar_layouts(40);
}
END_TEST

/* A communicator given again before the set-up (the same processes in the
 * other order: each owns another part of the mesh) makes the split
 * operators again, even when a query (ND_GAMMA0) built them over the first
 * one: the run is that of a problem given the second alone, to round-off
 * (bitwise with slabs; with PT-Scotch up to 1e-13 apart on 4 ranks, though
 * every rank owns the same nodes in both: two problems made alike, with no
 * first communicator, part as much, 1e-14 to 1e-13 and not the same from
 * run to run, so the bits part in MUMPS's solves on several ranks, not
 * here). Kept, the operators of the first partition made the step matrix
 * singular on the second. */
START_TEST(a_second_communicator_makes_the_operators_again) {
  MPI_Comm reversed;
  MPI_Comm_split(MPI_COMM_WORLD, 0, g_size - 1 - g_rank, &reversed);
  nd_problem again = scene(2, ND_SOLVER_PETSC_MUMPS, 1);
  ck_assert(scalar(again, ND_GAMMA0) > 0); /* the operators, split over MPI_COMM_WORLD's ranks */
  ND_OK_OR_FAIL(nd_problem_set_comm(again, reversed));
  nd_problem alone = scene(2, ND_SOLVER_PETSC_MUMPS, 0);
  ND_OK_OR_FAIL(nd_problem_set_comm(alone, reversed));
  history a, b;
  run(again, &a);
  run(alone, &b);
  const double de = relative_gap(b.energy, a.energy, kSteps), df = relative_gap(b.force, a.force, kSteps);
  ck_assert_msg(nd_test_on_all_ranks(de <= 1e-12 && df <= 1e-12),
                "rank %d: energy %.3g, force %.3g off the problem given the second alone", g_rank, de, df);
  ND_OK_OR_FAIL(nd_problem_destroy(&again));
  ND_OK_OR_FAIL(nd_problem_destroy(&alone));
  MPI_Comm_free(&reversed);
}
END_TEST

/* ND_PARTITION_KIND says which partition ran (issue 54): 0 on one rank, 1 for
   PT-Scotch (MPI_THREAD_MULTIPLE), 2 for the slabs it falls back to */
START_TEST(the_partition_kind_says_which_partition_ran) {
  nd_problem p = scene(2, ND_SOLVER_PETSC_MUMPS, 1);
  const double expected = g_size == 1 ? 0 : g_thread_multiple ? 1 : 2;
  ck_assert_msg(scalar(p, ND_PARTITION_KIND) == expected, "ND_PARTITION_KIND %g, expected %g",
                scalar(p, ND_PARTITION_KIND), expected);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(bad_communicators) {
  nd_problem p = scene(2, ND_SOLVER_PETSC_MUMPS, 0);
  ck_assert_int_eq(nd_problem_set_comm(p, MPI_COMM_NULL), ND_ERR_VALUE);
  ck_assert_msg(strstr(nd_last_error(), "nd_problem_set_comm: ") == nd_last_error(), "%s", nd_last_error());
  ck_assert_msg(strstr(nd_last_error(), "MPI_COMM_NULL") != NULL, "%s", nd_last_error());
  ck_assert_int_eq(nd_problem_set_comm_f(p, (int)MPI_Comm_c2f(MPI_COMM_NULL)), ND_ERR_VALUE);
  ck_assert_int_eq(nd_problem_set_comm(NULL, MPI_COMM_WORLD), ND_ERR_NULL);
  /* the Fortran handle of MPI_COMM_WORLD is accepted, before the set-up */
  ND_OK_OR_FAIL(nd_problem_set_comm_f(p, (int)MPI_Comm_c2f(MPI_COMM_WORLD)));
  ND_OK_OR_FAIL(nd_problem_setup(p));
  ck_assert_int_eq(nd_problem_set_comm(p, MPI_COMM_WORLD), ND_ERR_STATE);
  ck_assert_msg(strstr(nd_last_error(), "set up") != NULL, "%s", nd_last_error());
  ck_assert_int_eq(nd_problem_set_comm_f(p, (int)MPI_Comm_c2f(MPI_COMM_SELF)), ND_ERR_STATE);
  /* none of it changed the problem: it steps on the ranks it was given */
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert(scalar(p, ND_TIME) == kTau);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));

  /* another mesh on the last rank: every rank refuses the communicator (the
     mesh is partitioned over the ranks when it is given: the ranks compare
     first), and the problem stays each process's alone */
  if (g_size > 1) {
    char mesh[512];
    snprintf(mesh, sizeof mesh, "%s/disk_%s.msh", ND_MESH_DIR, g_rank == g_size - 1 ? "h2" : "h4");
    ND_OK_OR_FAIL(drop_scene_create(2, mesh, 1, ND_SCHEME_HYBRID, NULL, 1.0, 1e-3, kTau, ND_SOLVER_PETSC_MUMPS, &p));
    ck_assert_int_eq(nd_problem_set_comm(p, MPI_COMM_WORLD), ND_ERR_STATE);
    ck_assert_msg(strstr(nd_last_error(), "the ranks' meshes differ") != NULL, "%s", nd_last_error());
    int64_t n = 0, own = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
    ND_OK_OR_FAIL(nd_problem_get_owned_node_count(p, &own));
    ck_assert(own == n);
    ck_assert(scalar(p, ND_STEP_INDEX) == 0);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

int main(int argc, char **argv) {
  /* MPI_THREAD_MULTIPLE lets the library partition the mesh with PT-Scotch;
     with the argument "single" (MPI_THREAD_SINGLE) it cuts it in slabs
     (parallel/ownership.hpp): every check holds with both */
  int provided = 0;
  const int single = argc > 1 && strcmp(argv[1], "single") == 0;
  MPI_Init_thread(&argc, &argv, single ? MPI_THREAD_SINGLE : MPI_THREAD_MULTIPLE, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_thread_multiple = provided == MPI_THREAD_MULTIPLE;
  Suite *s = suite_create("mpi_distributed");
  TCase *tc = tcase_create("ranks");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, bad_communicators);
  tcase_add_test(tc, the_partition_kind_says_which_partition_ran);
  tcase_add_test(tc, a_second_communicator_makes_the_operators_again);
  tcase_add_test(tc, each_rank_reads_its_part_of_a_field);
  tcase_add_test(tc, histories_match_the_serial_solve);
  tcase_add_test(tc, implicit_schemes_on_split_rows);
  tcase_add_test(tc, contact_release_on_split_rows);
  tcase_add_test(tc, an_overflow_in_one_ranks_rows_fails_the_step_everywhere);
  tcase_add_test(tc, contact_points_and_rows_on_their_ranks);
  tcase_add_test(tc, a_load_refused_on_one_rank_fails_the_step_everywhere);
  tcase_add_test(tc, checkpoint_restores_bitwise);
  tcase_add_test(tc, each_rank_holds_its_rows_of_the_operators);
  tcase_add_test(tc, a_step_on_split_rows_receives_no_products);
  tcase_add_test(tc, a_distributed_state_gathers_no_solution);
  tcase_add_test(tc, a_change_of_solver_completes_a_distributed_state);
  tcase_add_test(tc, a_failed_step_leaves_a_distributed_state_as_it_was);
  tcase_add_test(tc, explicit_steps_on_split_rows);
  tcase_add_test(tc, a_bar_on_more_ranks_than_cells);
  suite_add_tcase(s, tc);
  return nd_test_run_on_ranks(s);
}
