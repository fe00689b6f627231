#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int nd_test_run(Suite *s) {
  SRunner *sr = srunner_create(s);
  srunner_run_all(sr, CK_NORMAL);
  int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

nd_problem nd_test_bar(int nx, int degree, int scheme, const double *params, double theta,
                       double gamma0, double tau) {
  return nd_test_bar_at(nx, degree, scheme, params, theta, gamma0, tau, 0.0, NULL);
}

nd_problem nd_test_bar_at(int nx, int degree, int scheme, const double *params, double theta,
                          double gamma0, double tau, double plane_x, const double *body_force) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double up = 1, lo0 = -0.5, hi0 = 0.5, lo1 = 0.5, hi1 = 1.5;
  ND_OK_OR_FAIL(nd_mesh_create_interval(nx, 0.0, 1.0, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo0, &hi0)); /* x = 0: contact */
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo1, &hi1)); /* x = 1: clamped */
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &plane_x, &up));
  if (body_force) ND_OK_OR_FAIL(nd_problem_set_body_force(p, body_force));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, gamma0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * (size_t)n), *u0 = malloc(sizeof(double) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n; ++i) u0[i] = 0.5 * (1 - x[i]);
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, NULL));
  free(x);
  free(u0);
  return p;
}

nd_problem nd_test_strip(int dim, int cell_type, int nx, int degree, int scheme, const double *params,
                         double theta, double gamma0, double tau) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double h = 1.0 / nx, lo[3] = {0, 0, 0}, hi[3] = {1, h, h};
  const double clo[3] = {-1, -1, -1}, chi[3] = {1e-9, 2, 2}, dlo[3] = {1 - 1e-9, -1, -1}, dhi[3] = {2, 2, 2};
  const double origin[3] = {0, 0, 0}, normal[3] = {1, 0, 0};
  if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(nx, 1, lo, hi, cell_type, &m));
  if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box_cells(nx, 1, 1, lo, hi, cell_type, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, clo, chi));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, dlo, dhi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0)); /* rho = E = 1 per unit cross-section */
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, normal));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, gamma0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * (size_t)(n * dim)), *u0 = calloc((size_t)(n * dim), sizeof(double));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n; ++i) u0[i * dim] = 0.5 * (1 - x[i * dim]);
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, NULL));
  free(x);
  free(u0);
  return p;
}

const nd_test_scheme nd_test_schemes[ND_TEST_N_SCHEMES] = {
    {ND_SCHEME_THETA, {0.5, 0}},   {ND_SCHEME_THETA, {1, 0}},  {ND_SCHEME_NEWMARK, {0.25, 0.5}},
    {ND_SCHEME_NEWMARK, {0, 0.5}}, {ND_SCHEME_HYBRID, {0, 0}}, {ND_SCHEME_GENERALIZED_ALPHA, {0.8, 0}}};

int nd_test_is_explicit(const nd_test_scheme *s) { return s->scheme == ND_SCHEME_NEWMARK && s->params[0] == 0; }

unsigned char *nd_test_checkpoint(nd_problem p, int64_t *size) {
  *size = 0;
  ND_OK_OR_FAIL(nd_problem_get_state_size(p, size));
  unsigned char *buf = malloc((size_t)*size);
  ck_assert_ptr_nonnull(buf);
  ND_OK_OR_FAIL(nd_problem_save_state(p, *size, buf));
  return buf;
}

nd_test_csr nd_test_get_matrix(nd_problem p, int which) {
  nd_test_csr a = {0, 0, NULL, NULL, NULL};
  ND_OK_OR_FAIL(nd_problem_get_matrix(p, which, &a.n, &a.nnz, NULL, NULL, NULL));
  a.ptr = malloc(sizeof(int64_t) * (size_t)(a.n + 1));
  a.col = malloc(sizeof(int64_t) * (size_t)(a.nnz ? a.nnz : 1));
  a.val = malloc(sizeof(double) * (size_t)(a.nnz ? a.nnz : 1));
  ND_OK_OR_FAIL(nd_problem_get_matrix(p, which, &a.n, &a.nnz, a.ptr, a.col, a.val));
  return a;
}

void nd_test_csr_free(nd_test_csr *a) { free(a->ptr), free(a->col), free(a->val); }

double nd_test_csr_terms(const nd_test_csr *A, const double *x, const double *y) {
  double s = 0;
  for (int64_t i = 0; i < A->n; ++i)
    for (int64_t e = A->ptr[i]; e < A->ptr[i + 1]; ++e) s += fabs(A->val[e] * x[i] * y[A->col[e]]);
  return s;
}

void nd_test_write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  ck_assert_ptr_nonnull(f);
  fputs(text, f);
  fclose(f);
}

nd_test_snapshot nd_test_take(nd_problem p, int dim) {
  nd_test_snapshot s;
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  s.n = nodes * dim;
  s.fields = malloc(sizeof(double) * (size_t)(3 * s.n));
  ck_assert_ptr_nonnull(s.fields);
  for (int f = 0; f < 3; ++f) ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT + f, nodes, s.fields + f * s.n));
  for (int k = 0; k < 15; ++k) ND_OK_OR_FAIL(nd_get_scalar(p, ND_TIME + k, &s.scalars[k]));
  return s;
}

int nd_test_same(const nd_test_snapshot *a, const nd_test_snapshot *b) {
  return a->n == b->n && memcmp(a->fields, b->fields, sizeof(double) * (size_t)(3 * a->n)) == 0 &&
         memcmp(a->scalars, b->scalars, sizeof a->scalars) == 0;
}

void nd_test_snapshot_free(nd_test_snapshot *s) {
  free(s->fields);
  s->fields = NULL;
}

int nd_test_step_failing_once(nd_problem p, nd_problem ref, int dim, int k) {
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0.0, 1));
  nd_test_snapshot before = nd_test_take(p, dim);
  double refreshes = 0, after_refreshes = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_STAT_NORMAL_REFRESHES, &refreshes));
  const int status = nd_step(p);
  int failed = 0;
  if (status != ND_OK) {
    ck_assert_int_eq(status, ND_ERR_NEWTON);
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_STAT_NORMAL_REFRESHES, &after_refreshes));
    failed = after_refreshes > refreshes ? 2 : 1;
    nd_test_snapshot after = nd_test_take(p, dim);
    /* (the refresh counter counts the work done, not the state) */
    ck_assert_msg(nd_test_same(&before, &after), "step %d: the failed step changed the problem", k + 1);
    nd_test_snapshot_free(&after);
    ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-10, 0.0, 50));
    ND_OK_OR_FAIL(nd_step(p));
  }
  nd_test_snapshot_free(&before);
  ND_OK_OR_FAIL(nd_step(ref));
  nd_test_snapshot a = nd_test_take(p, dim), b = nd_test_take(ref, dim);
  ck_assert_msg(nd_test_same(&a, &b), "step %d: the run differs from the run without failures", k + 1);
  nd_test_snapshot_free(&a), nd_test_snapshot_free(&b);
  return failed;
}
