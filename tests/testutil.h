/* Shared helpers of the Check tests. */
#ifndef ND_TESTUTIL_H
#define ND_TESTUTIL_H
#include <check.h>

#include "nitschedyn.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Runs a suite; returns the process exit status (0 when all passed). */
int nd_test_run(Suite *s);

/* The 1D bar of docs/design.md §7: Omega = (0,1), rho = E = 1, clamped at x = 1,
   contact at x = 0 with the obstacle below (g0 = 0), u0 = (1-x)/2, v0 = 0.
   scheme/params as nd_problem_set_scheme. Fails the test on any error. */
nd_problem nd_test_bar(int nx, int degree, int scheme, const double *params, double theta,
                       double gamma0, double tau);
/* The same bar with the obstacle plane at x = plane_x (0 in nd_test_bar) and,
   unless NULL, a body force. */
nd_problem nd_test_bar_at(int nx, int degree, int scheme, const double *params, double theta,
                          double gamma0, double tau, double plane_x, const double *body_force);

/* The same bar as a strip [0,1] x [0,1/nx]^(dim-1) of nx cells, one across
   (cell_type ND_CELL_SIMPLEX, or ND_CELL_QUADRILATERAL / ND_CELL_HEXAHEDRON
   for dim 2 / 3), nu = 0: region 1 at x = 0 against the plane x = 0,
   region 2 at x = 1 clamped, u0 = ((1-x)/2, 0, 0). gamma0 as given (a
   cell's diameter is sqrt(dim) h where the bar's is h: gamma0_bar /
   sqrt(dim) gives the bar's gamma on the contact). */
nd_problem nd_test_strip(int dim, int cell_type, int nx, int degree, int scheme, const double *params,
                         double theta, double gamma0, double tau);

/* The schemes the whole-run tests go through: theta = 1/2 and 1,
   Newmark(1/4, 1/2), explicit Newmark(0, 1/2), hybrid, generalized-alpha 0.8. */
typedef struct {
  int scheme;
  double params[2];
} nd_test_scheme;
enum { ND_TEST_N_SCHEMES = 6 };
extern const nd_test_scheme nd_test_schemes[ND_TEST_N_SCHEMES];
/* explicit Newmark (beta = 0): lumped mass and small steps */
int nd_test_is_explicit(const nd_test_scheme *s);

/* An operator of nd_problem_get_matrix (CSR on the free DOFs), fetched in
   its two calls; nd_test_csr_free frees its arrays. */
typedef struct {
  int64_t n, nnz;
  int64_t *ptr, *col;
  double *val;
} nd_test_csr;
nd_test_csr nd_test_get_matrix(nd_problem p, int which);
void nd_test_csr_free(nd_test_csr *a);
/* sum_ij |A_ij x_i y_j|: what the round-off of x'Ay is relative to (a
   quadratic energy of a state far from the origin, a body that has moved as
   a whole, cancels terms much larger than itself) */
double nd_test_csr_terms(const nd_test_csr *A, const double *x, const double *y);

/* writes text to the file at path (a check fails when it cannot) */
void nd_test_write_file(const char *path, const char *text);

/* p's checkpoint (nd_problem_save_state; collective), malloc'ed (the caller
   frees it), its size in *size; a check fails when it cannot be made */
unsigned char *nd_test_checkpoint(nd_problem p, int64_t *size);

/* What a step may change, to compare bitwise: the displacement, velocity and
   acceleration (dim values per node) and the first 15 scalars (ND_TIME on).
   nd_test_take fails the test on an error; nd_test_same is 1 when a and b
   hold the same bits; nd_test_snapshot_free frees the fields. */
typedef struct {
  int64_t n; /* values per field: nodes times dim */
  double *fields;
  double scalars[15];
} nd_test_snapshot;
nd_test_snapshot nd_test_take(nd_problem p, int dim);
int nd_test_same(const nd_test_snapshot *a, const nd_test_snapshot *b);
void nd_test_snapshot_free(nd_test_snapshot *s);

/* Step k (0-based) of p with Newton allowed one iteration: a failure
   (ND_ERR_NEWTON) must leave p bitwise as it was, and the step is taken
   again with 50; then ref (never limited) steps, and p and ref must be
   bitwise the same. Returns 0 when the first try was taken, 1 when it
   failed, 2 when it failed after a refresh of the contact rows (a curved
   obstacle's normals, a pair's pairings: ND_STAT_NORMAL_REFRESHES grew). */
int nd_test_step_failing_once(nd_problem p, nd_problem ref, int dim, int k);

#ifdef __cplusplus
}
#endif

/* ck_assert on a status, printing nd_last_error() when it is not ND_OK */
#define ND_OK_OR_FAIL(call)                                                          \
  do {                                                                               \
    int nd_status_ = (call);                                                         \
    ck_assert_msg(nd_status_ == ND_OK, "%s returned %d: %s", #call, nd_status_,      \
                  nd_last_error());                                                  \
  } while (0)
#endif
