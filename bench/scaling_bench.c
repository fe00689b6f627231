/* Benchmark (not a test; builds with PETSc): the 2D disk of docs/design.md §7 on the
 * ranks of MPI_COMM_WORLD, for report/SCALING.md (bench/scaling.sh runs it).
 * Every rank builds the same problem; with a PETSc solver the problem gets
 * MPI_COMM_WORLD (the solves are distributed), with cholmod it stays serial.
 * Each step is timed between two barriers (the slowest rank's time). Prints
 * one CSV row on rank 0 (the header: scaling_bench --header): the set-up and
 * the first step (assembly, factorization or multigrid set-up), the median of
 * the free-flight steps (no contact before or after) and of the contact steps
 * (contact before and after), Newton iterations per contact step, the largest
 * peak RSS of a rank, the 1-minute load average of the machine when the
 * run ended (/proc/loadavg: other work shares the cores), the time of
 * nd_problem_set_comm (it partitions the mesh), and the doubles a rank
 * received from the others in a free-flight and in a contact step (medians
 * of ND_STAT_VALUES_RECEIVED's increments, the largest rank's), and the
 * library's heap (operator new, bench/heap_track.cpp: its vectors,
 * operators and contact rows; not PETSc's nor MUMPS's), the largest rank's:
 * what a rank holds after the set-up (MB); the whole-length arrays (n
 * elements, n the unknowns, or an operator's n + 1 row pointers; counted in
 * units of 8 n bytes: n ints 0.5, n doubles or 8-byte indices 1, n pairs of
 * doubles 2, n triples 3) at the set-up's peak, held between steps (after
 * the last), and at the peak of a free-flight and of a contact step
 * (medians); and the peak of everything a free-flight and a contact step
 * add above what the rank held before them, in units of 8 n bytes (medians;
 * PETSc's copies of the matrix values on the refactoring path are among
 * them, nnz/P long).
 *   mpiexec -n N scaling_bench MESH DEGREE SOLVER TAU T [DIM]
 *   SOLVER: mumps | gamg | cholmod; DIM: 2 (the disk, default) or 3 (the ball)
 * ND_BENCH_DISTRIBUTED_STATE=1 in the environment: the state distributed
 * (nd_problem_set_distributed_state); ND_BENCH_COERCIVITY=0: without the
 * set-up's coercivity check (gamma0 = 1e-3 is above the element bound in
 * 3D: the check factors K_Theta + delta M with a direct solver). */
#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "drop_scene.h"
#include "nitschedyn_mpi.h"

static const char *kHeader =
    "ranks,mesh,degree,unknowns,solver,setup_s,first_step_s,free_steps,free_median_ms,contact_steps,"
    "contact_median_ms,newton_per_contact_step,peak_rss_mb_max,load1,set_comm_s,received_free,received_contact,"
    "heap_setup_mb,vectors_held,vectors_free_peak,vectors_contact_peak,heap_free_added,heap_contact_added,"
    "vectors_setup_peak";

/* bench/heap_track.cpp */
void nd_bench_heap_watch_vectors(long long doubles);
long long nd_bench_heap_now(void);
long long nd_bench_heap_vectors_now(void);
long long nd_bench_heap_peak(void);
long long nd_bench_heap_vectors_peak(void);
void nd_bench_heap_reset_peak(void);

static int by_value(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *x, int n) {
  if (n == 0) return 0;
  qsort(x, (size_t)n, sizeof *x, by_value);
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

static double timed(nd_problem p, int (*call)(nd_problem), int *status) {
  MPI_Barrier(MPI_COMM_WORLD);
  const double t0 = MPI_Wtime();
  *status = call(p);
  MPI_Barrier(MPI_COMM_WORLD);
  return MPI_Wtime() - t0;
}

static int set_world(nd_problem p) { return nd_problem_set_comm(p, MPI_COMM_WORLD); }

int main(int argc, char **argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1, status = ND_OK;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (argc == 2 && !strcmp(argv[1], "--header")) {
    if (rank == 0) puts(kHeader);
    MPI_Finalize();
    return 0;
  }
  if (argc != 6 && argc != 7) {
    if (rank == 0) fprintf(stderr, "usage: scaling_bench MESH DEGREE mumps|gamg|cholmod TAU T [DIM]\n");
    MPI_Finalize();
    return 2;
  }
  const char *mesh = argv[1], *solver_name = argv[3];
  const int degree = atoi(argv[2]);
  const double tau = atof(argv[4]), T = atof(argv[5]);
  const int dim = argc == 7 ? atoi(argv[6]) : 2;
  const int solver = !strcmp(solver_name, "mumps") ? ND_SOLVER_PETSC_MUMPS
                     : !strcmp(solver_name, "gamg") ? ND_SOLVER_PETSC_GAMG
                                                    : ND_SOLVER_CHOLMOD;
  const int steps = (int)(T / tau + 0.5);
  double *free_ms = malloc(sizeof(double) * (size_t)steps), *contact_ms = malloc(sizeof(double) * (size_t)steps);
  double *free_recv = malloc(sizeof(double) * (size_t)steps), *contact_recv = malloc(sizeof(double) * (size_t)steps);
  double *free_heap = malloc(sizeof(double) * (size_t)steps), *contact_heap = malloc(sizeof(double) * (size_t)steps);
  double *free_vec = malloc(sizeof(double) * (size_t)steps), *contact_vec = malloc(sizeof(double) * (size_t)steps);
  int n_free = 0, n_contact = 0;
  double newton = 0, setup_s = 0, first_s = 0, active_before = 0, active = 0, iterations = 0, comm_s = 0;
  double received_before = 0, received = 0;
  int64_t nodes = 0;
  nd_problem p = NULL;

  /* the unknowns first (no clamped DOFs in this scene), so that the heap
     accounting knows a whole vector from the problem's first one */
  status = drop_scene_create(dim, mesh, degree, ND_SCHEME_HYBRID, NULL, 1.0, 1e-3, tau, solver, &p);
  if (status == ND_OK) status = nd_problem_get_node_count(p, &nodes);
  nd_problem_destroy(&p);
  const double vector_bytes = 8.0 * (double)(dim * nodes);
  nd_bench_heap_watch_vectors(dim * nodes);
  if (status == ND_OK) status = drop_scene_create(dim, mesh, degree, ND_SCHEME_HYBRID, NULL, 1.0, 1e-3, tau, solver, &p);
  if (status == ND_OK && solver != ND_SOLVER_CHOLMOD) comm_s = timed(p, set_world, &status);  /* partitions the mesh */
  const char *layout = getenv("ND_BENCH_DISTRIBUTED_STATE");
  if (status == ND_OK && layout && !strcmp(layout, "1")) status = nd_problem_set_distributed_state(p, 1);
  const char *coercivity = getenv("ND_BENCH_COERCIVITY");
  if (status == ND_OK && coercivity && !strcmp(coercivity, "0")) status = nd_problem_set_guard(p, ND_GUARD_COERCIVITY, 0);
  nd_bench_heap_reset_peak();
  if (status == ND_OK) setup_s = timed(p, nd_problem_setup, &status);
  const double setup_vectors = (double)nd_bench_heap_vectors_peak() / vector_bytes;
  const double heap_setup_mb = (double)nd_bench_heap_now() / (1024.0 * 1024.0);
  if (status == ND_OK) status = nd_get_scalar(p, ND_STAT_VALUES_RECEIVED, &received_before);
  for (int k = 0; k < steps && status == ND_OK; ++k) {
    const long long before = nd_bench_heap_now();
    nd_bench_heap_reset_peak();
    const double dt = timed(p, nd_step, &status);
    const double added = (double)(nd_bench_heap_peak() - before) / vector_bytes;
    const double vectors = (double)nd_bench_heap_vectors_peak() / vector_bytes;
    if (status == ND_OK) status = nd_get_scalar(p, ND_ACTIVE_POINTS, &active);
    if (status == ND_OK) status = nd_get_scalar(p, ND_NEWTON_ITERATIONS, &iterations);
    if (status == ND_OK) status = nd_get_scalar(p, ND_STAT_VALUES_RECEIVED, &received);
    if (k == 0) {
      first_s = dt;
    } else if (active_before == 0 && active == 0) {
      free_recv[n_free] = received - received_before;
      free_heap[n_free] = added, free_vec[n_free] = vectors;
      free_ms[n_free++] = 1e3 * dt;
    } else if (active_before > 0 && active > 0) {
      contact_recv[n_contact] = received - received_before;
      contact_heap[n_contact] = added, contact_vec[n_contact] = vectors;
      contact_ms[n_contact++] = 1e3 * dt, newton += iterations;
    }
    active_before = active, received_before = received;
  }
  if (status != ND_OK) fprintf(stderr, "rank %d: %s\n", rank, nd_last_error());
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  double rss = ru.ru_maxrss / 1024.0, rss_max = 0;
  MPI_Reduce(&rss, &rss_max, 1, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  double load1 = -1;
  FILE *f = fopen("/proc/loadavg", "r");
  if (f) {
    if (fscanf(f, "%lf", &load1) != 1) load1 = -1;
    fclose(f);
  }
  double mine[9] = {median(free_recv, n_free),
                    median(contact_recv, n_contact),
                    heap_setup_mb,
                    (double)nd_bench_heap_vectors_now() / vector_bytes,
                    median(free_vec, n_free),
                    median(contact_vec, n_contact),
                    median(free_heap, n_free),
                    median(contact_heap, n_contact),
                    setup_vectors},
         most[9] = {0};
  MPI_Reduce(mine, most, 9, MPI_DOUBLE, MPI_MAX, 0, MPI_COMM_WORLD);
  const char *base = strrchr(mesh, '/');
  if (rank == 0 && status == ND_OK)
    printf("%d,%s,%d,%lld,%s,%.4f,%.4f,%d,%.3f,%d,%.3f,%.2f,%.1f,%.2f,%.4f,%.0f,%.0f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f\n", size,
           base ? base + 1 : mesh,
           degree, (long long)(dim * nodes), solver_name, setup_s, first_s, n_free, median(free_ms, n_free), n_contact,
           median(contact_ms, n_contact), n_contact ? newton / n_contact : 0.0, rss_max, load1, comm_s, most[0], most[1],
           most[2], most[3], most[4], most[5], most[6], most[7], most[8]);
  nd_problem_destroy(&p);
  free(free_ms);
  free(contact_ms);
  free(free_recv);
  free(contact_recv);
  free(free_heap);
  free(contact_heap);
  free(free_vec);
  free(contact_vec);
  MPI_Finalize();
  return status == ND_OK ? 0 : 1;
}
