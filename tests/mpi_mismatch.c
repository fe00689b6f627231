/* Collective calls the ranks do not match (issue 54, finding 11), under
 * mpiexec -n 2 and 4 (tests/CMakeLists.txt, builds with PETSc), with
 * NITSCHEDYN_MPI_TIMEOUT = 2 s. Before the fix each of these hung or ended the job:
 *  - one rank calls nd_step once more: it fails after the timeout, a late
 *    rank's step fails after the timeout too, every later collective call at
 *    once, and a new problem on the same ranks steps again;
 *  - the ranks make different collective calls (nd_step on one,
 *    nd_get_field_gathered or nd_problem_save_state_file of a distributed
 *    state on the others): every rank fails at once, no state moves, and
 *    the next matched calls succeed; with a whole state, where saving is
 *    not collective, the stepping rank fails after the timeout;
 *  - a time step refused because one rank's differs, then reset on that
 *    rank alone (MUMPS and GAMG): the next step succeeds on every rank
 *    (that rank's rebuilt factorization used to wait for the others for
 *    ever), with the work of a reset on every rank;
 *  - nd_problem_set_state refused on one rank (a NaN): refused on every rank;
 *  - ND_PARTITION_KIND without a communicator: 0.
 * CK_FORK=no (MPI is initialized once per process). */
#include <math.h>
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "drop_scene.h"
#include "nitschedyn_mpi.h"
#include "testutil_mpi.h"

static const double kTau = 0.25;
static const double kTimeout = 2; /* NITSCHEDYN_MPI_TIMEOUT, set in main */
static int g_rank, g_size;

static nd_problem scene(int solver, int distributed_state) {
  char mesh[512];
  snprintf(mesh, sizeof mesh, "%s/disk_h4.msh", ND_MESH_DIR);
  nd_problem p = NULL;
  ND_OK_OR_FAIL(drop_scene_create(2, mesh, 1, ND_SCHEME_HYBRID, NULL, 1.0, 1e-3, kTau, solver, &p));
  ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
  if (distributed_state) ND_OK_OR_FAIL(nd_problem_set_distributed_state(p, 1));
  return p;
}

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* a call's status and the seconds it took, with its message */
typedef struct {
  int status;
  double seconds;
  char message[1024];
} outcome;

static outcome timed(int status, double start) {
  outcome o;
  o.status = status;
  o.seconds = MPI_Wtime() - start;
  snprintf(o.message, sizeof o.message, "%s", status == ND_OK ? "" : nd_last_error());
  return o;
}

static outcome step(nd_problem p) {
  const double start = MPI_Wtime();
  return timed(nd_step(p), start);
}

/* refused with ND_ERR_STATE at once (well within the timeout: no rank waited) */
static void refused_at_once(const outcome *o, const char *what) {
  ck_assert_msg(o->status == ND_ERR_STATE, "%s returned %d: %s", what, o->status, o->message);
  ck_assert_msg(o->seconds < kTimeout / 2, "%s took %g s", what, o->seconds);
}

/* refused with ND_ERR_STATE after waiting for the timeout, not much longer */
static void refused_after_the_wait(const outcome *o, const char *what) {
  ck_assert_msg(o->status == ND_ERR_STATE, "%s returned %d: %s", what, o->status, o->message);
  ck_assert_msg(o->seconds >= kTimeout && o->seconds < kTimeout + 5, "%s took %g s", what, o->seconds);
  ck_assert_msg(strstr(o->message, "waited") != NULL, "%s", o->message);
}

START_TEST(one_rank_steps_once_more) {
  nd_problem p = scene(ND_SOLVER_PETSC_MUMPS, 0);
  for (int k = 0; k < 2; ++k) ND_OK_OR_FAIL(nd_step(p));
  if (g_rank == 0) {
    const outcome extra = step(p); /* the others make no collective call */
    refused_after_the_wait(&extra, "rank 0's extra nd_step");
    printf("rank 0's extra step (%.2f s): %s\n", extra.seconds, extra.message);
    ck_assert_msg(scalar(p, ND_STEP_INDEX) == 2, "the refused step moved the state");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (g_rank != 0) { /* a late step meets rank 0's abandoned header, and waits for its confirmation */
    const outcome late = step(p);
    refused_after_the_wait(&late, "a late nd_step");
  }
  MPI_Barrier(MPI_COMM_WORLD);
  /* the problem makes no collective call any more, on any rank, and says why */
  const outcome again = step(p);
  refused_at_once(&again, "nd_step after the ranks lost step");
  ck_assert_msg(strstr(again.message, "lost step") != NULL, "%s", again.message);
  if (g_rank == 0) printf("the next step: %s\n", again.message);
  ck_assert_msg(scalar(p, ND_STEP_INDEX) == 2, "a refused step moved the state");
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  /* the job goes on: a new problem on the same ranks steps */
  nd_problem q = scene(ND_SOLVER_PETSC_MUMPS, 0);
  for (int k = 0; k < 2; ++k) ND_OK_OR_FAIL(nd_step(q));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

/* rank 0 steps while the others call `other` (collective): every rank fails at once */
static void step_against(nd_problem p, int (*other)(nd_problem), const char *what) {
  const double n = scalar(p, ND_STEP_INDEX);
  MPI_Barrier(MPI_COMM_WORLD);
  const double start = MPI_Wtime();
  const outcome o = timed(g_rank == 0 ? nd_step(p) : other(p), start);
  refused_at_once(&o, g_rank == 0 ? "nd_step" : what);
  ck_assert_msg(strstr(o.message, "not in the same collective call") != NULL, "%s", o.message);
  if (g_rank == 0) printf("nd_step against %s (%.3f s): %s\n", what, o.seconds, o.message);
  ck_assert_msg(strstr(o.message, "nd_step") != NULL && strstr(o.message, what) != NULL, "%s", o.message);
  ck_assert_msg(scalar(p, ND_STEP_INDEX) == n, "a refused call moved the state");
  /* the ranks are still in step: the next matched call succeeds */
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert(scalar(p, ND_STEP_INDEX) == n + 1);
}

static double *g_field; /* n_nodes * 2 values */
static int gather_displacement(nd_problem p) {
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  return nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, 0, n, g_field);
}

static char g_path[256];
static int save_file(nd_problem p) { return nd_problem_save_state_file(p, g_path); }

START_TEST(ranks_in_different_calls_fail_at_once) {
  snprintf(g_path, sizeof g_path, "mpi_mismatch_%d.ndstate", g_rank);
  for (int distributed = 0; distributed < 2; ++distributed) {
    nd_problem p = scene(ND_SOLVER_PETSC_MUMPS, distributed);
    ND_OK_OR_FAIL(nd_step(p));
    int64_t n = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
    g_field = malloc(sizeof(double) * 2 * (size_t)n);
    step_against(p, gather_displacement, "nd_get_field_gathered");
    /* saving a distributed state gathers it: collective */
    if (distributed) step_against(p, save_file, "nd_problem_save_state_file");
    free(g_field);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  /* saving a whole state is the rank's own (no collective call): the
     stepping rank alone waits, then fails; a late step fails after it */
  nd_problem p = scene(ND_SOLVER_PETSC_MUMPS, 0);
  ND_OK_OR_FAIL(nd_step(p));
  if (g_rank == 0) {
    const outcome o = step(p);
    refused_after_the_wait(&o, "nd_step against a save");
  } else {
    ND_OK_OR_FAIL(save_file(p));
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (g_rank != 0) {
    const outcome late = step(p);
    refused_after_the_wait(&late, "the late nd_step");
  }
  unlink(g_path);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* A run of 5 steps where after the second the last rank's time step is
   2 tau (the step is refused everywhere), then reset (`alone`: on that rank;
   else on every rank); its displacement and its work counters
   (factorizations, symbolic analyses: ND_STAT_*) */
typedef struct {
  double factorizations, analyses;
} work;

static work run_with_a_reset(int solver, int alone, double *u, int64_t n) {
  nd_problem p = scene(solver, 0);
  const int last = g_rank == g_size - 1;
  for (int k = 0; k < 2; ++k) ND_OK_OR_FAIL(nd_step(p));
  if (last) ND_OK_OR_FAIL(nd_problem_set_timestep(p, 2 * kTau));
  const outcome refused = step(p);
  refused_at_once(&refused, "nd_step with another time step on the last rank");
  ck_assert_msg(strstr(refused.message, "problems differ") != NULL, "%s", refused.message);
  if (last || !alone) ND_OK_OR_FAIL(nd_problem_set_timestep(p, kTau));
  for (int k = 0; k < 3; ++k) {
    const outcome o = step(p);
    ck_assert_msg(o.status == ND_OK, "step %d after the reset: %d: %s", k, o.status, o.message);
  }
  ck_assert(scalar(p, ND_STEP_INDEX) == 5);
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u));
  const work w = {scalar(p, ND_STAT_FACTORIZATIONS), scalar(p, ND_STAT_SYMBOLIC_ANALYSES)};
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return w;
}

START_TEST(a_time_step_reset_on_one_rank_steps_on_every_rank) {
  const int solvers[] = {ND_SOLVER_PETSC_MUMPS, ND_SOLVER_PETSC_GAMG};
  for (int s = 0; s < 2; ++s) {
    nd_problem probe = scene(solvers[s], 0);
    int64_t n = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(probe, &n));
    ND_OK_OR_FAIL(nd_problem_destroy(&probe));
    const int bytes = (int)(sizeof(double) * 2 * (size_t)n);
    double *u = malloc((size_t)bytes);
    const work alone = run_with_a_reset(solvers[s], 1, u, n);
    ck_assert(nd_test_same_on_all_ranks(u, bytes)); /* (the solution gathered to every rank) */
    const work all = run_with_a_reset(solvers[s], 0, u, n);
    /* every rank rebuilt its factorization, as when every rank resets tau:
       the same work, on every rank (the displacements are compared in
       mpi_distributed: MUMPS and GAMG over several ranks need not repeat
       their bits from run to run) */
    ck_assert_msg(alone.factorizations == all.factorizations && alone.analyses == all.analyses,
                  "solver %d: %g factorizations and %g analyses after a reset on one rank, %g and %g after a "
                  "reset on every rank",
                  solvers[s], alone.factorizations, alone.analyses, all.factorizations, all.analyses);
    ck_assert(nd_test_same_on_all_ranks(&alone, (int)sizeof alone));
    free(u);
  }
}
END_TEST

/* nd_problem_set_state with a NaN on the last rank alone: refused on every
   rank at once with the same code (the others waited for ever before) */
START_TEST(a_state_refused_on_one_rank_is_refused_on_every_rank) {
  nd_problem p = scene(ND_SOLVER_PETSC_MUMPS, 0);
  ND_OK_OR_FAIL(nd_step(p));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *u = malloc(sizeof(double) * 2 * (size_t)n), *before = malloc(sizeof(double) * 2 * (size_t)n);
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u));
  memcpy(before, u, sizeof(double) * 2 * (size_t)n);
  if (g_rank == g_size - 1) u[1] = NAN;
  const double start = MPI_Wtime();
  const outcome o = timed(nd_problem_set_state(p, n, u, NULL), start);
  ck_assert_msg(o.status == ND_ERR_NONFINITE, "nd_problem_set_state returned %d: %s", o.status, o.message);
  ck_assert_msg(o.seconds < kTimeout / 2, "nd_problem_set_state took %g s", o.seconds);
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, u));
  ck_assert_msg(memcmp(u, before, sizeof(double) * 2 * (size_t)n) == 0, "a refused nd_problem_set_state moved U");
  ND_OK_OR_FAIL(nd_problem_set_state(p, n, u, NULL)); /* the same values everywhere: taken */
  ND_OK_OR_FAIL(nd_step(p));
  free(u), free(before);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(partition_kind_without_a_communicator) {
  char mesh[512];
  snprintf(mesh, sizeof mesh, "%s/disk_h4.msh", ND_MESH_DIR);
  nd_problem p = NULL;
  ND_OK_OR_FAIL(drop_scene_create(2, mesh, 1, ND_SCHEME_HYBRID, NULL, 1.0, 1e-3, kTau, ND_SOLVER_CHOLMOD, &p));
  ck_assert(scalar(p, ND_PARTITION_KIND) == 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(int argc, char **argv) {
  char timeout[32];
  snprintf(timeout, sizeof timeout, "%g", kTimeout);
  setenv("NITSCHEDYN_MPI_TIMEOUT", timeout, 1);
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SINGLE, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  Suite *s = suite_create("mpi_mismatch");
  TCase *tc = tcase_create("ranks");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, partition_kind_without_a_communicator);
  if (g_size > 1) {
    tcase_add_test(tc, ranks_in_different_calls_fail_at_once);
    tcase_add_test(tc, a_state_refused_on_one_rank_is_refused_on_every_rank);
    tcase_add_test(tc, a_time_step_reset_on_one_rank_steps_on_every_rank);
    tcase_add_test(tc, one_rank_steps_once_more);
  }
  suite_add_tcase(s, tc);
  return nd_test_run_on_ranks(s);
}
