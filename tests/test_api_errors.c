/* Error handling of the public C API (docs/design.md §6): every bad input gets its
 * specific status code, nd_last_error() names the function ("nd_<function>:")
 * and the argument, a rejected call leaves the object exactly as it was, and
 * the next successful call clears the message.
 *
 * Test cases: mesh, problem definition, stepping and getters, status codes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* ---- helpers ------------------------------------------------------------ */

static int contains(const char *s, const char *sub) {
  return sub == NULL || (s != NULL && strstr(s, sub) != NULL);
}

/* call must return `code`; nd_last_error() must start with "fn: " and, when
   `word` is not NULL, contain it. */
#define EXPECT_ERR(call, code, fn, word)                                                   \
  do {                                                                                     \
    const int st_ = (call);                                                                \
    const char *msg_ = nd_last_error();                                                    \
    ck_assert_msg(st_ == (code), "%s returned %d (%s), expected %d (%s); message: '%s'",   \
                  #call, st_, nd_strerror(st_), (int)(code), nd_strerror(code),            \
                  msg_ ? msg_ : "(NULL)");                                                 \
    ck_assert_msg(msg_ != NULL && msg_[0] != '\0', "%s: nd_last_error() is empty", #call); \
    ck_assert_msg(strncmp(msg_, fn ": ", strlen(fn ": ")) == 0,                            \
                  "%s: message '%s' does not start with '%s: '", #call, msg_, fn);         \
    const char *word_ = (word);                                                            \
    ck_assert_msg(contains(msg_, word_), "%s: message '%s' does not mention '%s'", #call,  \
                  msg_, word_ ? word_ : "");                                               \
  } while (0)

/* call must succeed and leave nd_last_error() empty */
#define EXPECT_OK(call)                                                                    \
  do {                                                                                     \
    ND_OK_OR_FAIL(call);                                                                   \
    ck_assert_msg(nd_last_error() != NULL && nd_last_error()[0] == '\0',                   \
                  "%s succeeded but nd_last_error() is '%s'", #call, nd_last_error());     \
  } while (0)

/* a non-NULL handle value that must be overwritten with NULL on failure */
static int sentinel_storage;
#define MESH_SENTINEL ((nd_mesh)(void *)&sentinel_storage)
#define PROBLEM_SENTINEL ((nd_problem)(void *)&sentinel_storage)

/* (0,1) in n cells; region 1 = {x = 0}, region 2 = {x = 1} */
static nd_mesh interval_with_regions(int64_t n) {
  nd_mesh m = NULL;
  const int64_t left = 0, right = n;
  EXPECT_OK(nd_mesh_create_interval(n, 0.0, 1.0, &m));
  EXPECT_OK(nd_mesh_set_region(m, 1, 1, &left));
  EXPECT_OK(nd_mesh_set_region(m, 2, 1, &right));
  return m;
}

/* the unit square in two counter-clockwise triangles;
   region 1 = bottom edge, region 2 = top edge */
static const double square_xy[] = {0, 0, 1, 0, 1, 1, 0, 1};
static const int64_t square_cells[] = {0, 1, 2, 0, 2, 3};

static nd_mesh square_with_regions(void) {
  nd_mesh m = NULL;
  const int64_t bottom[] = {0, 1}, top[] = {3, 2};  /* facet vertices in any order */
  EXPECT_OK(nd_mesh_create(2, 4, square_xy, 2, square_cells, &m));
  EXPECT_OK(nd_mesh_set_region(m, 1, 1, bottom));
  EXPECT_OK(nd_mesh_set_region(m, 2, 1, top));
  return m;
}

static nd_problem problem_from(nd_mesh m, int degree) {
  nd_problem p = NULL;
  EXPECT_OK(nd_problem_create(m, degree, &p));
  ck_assert_ptr_nonnull(p);
  return p;
}

static nd_problem problem_1d(void) {
  nd_mesh m = interval_with_regions(4);
  nd_problem p = problem_from(m, 1);
  EXPECT_OK(nd_mesh_destroy(&m));
  return p;
}

static nd_problem problem_2d(void) {
  nd_mesh m = square_with_regions();
  nd_problem p = problem_from(m, 1);
  EXPECT_OK(nd_mesh_destroy(&m));
  return p;
}

static int64_t node_count(nd_problem p) {
  int64_t n = -1;
  EXPECT_OK(nd_problem_get_node_count(p, &n));
  ck_assert_int_gt(n, 0);
  return n;
}

static int64_t contact_count(nd_problem p) {
  int64_t n = -1;
  EXPECT_OK(nd_problem_get_contact_point_count(p, &n));
  ck_assert_int_gt(n, 0);
  return n;
}

static double scalar(nd_problem p, int key) {
  double x = NAN;
  EXPECT_OK(nd_get_scalar(p, key, &x));
  return x;
}

/* ======================================================================== */
/* mesh                                                                      */
/* ======================================================================== */

/* one past the largest ND_SOLVER_* id, from the header's list (no test
   to edit when a solver is added) */
static int past_the_last_solver(void) {
  int last = 0;
#define ND_TEST_MAX_(name, value, doc) \
  if ((value) > last) last = (value);
  ND_SOLVER_LIST(ND_TEST_MAX_)
#undef ND_TEST_MAX_
  return last + 1;
}

START_TEST(mesh_null_arguments) {
  const double x[] = {0, 1};
  const int64_t c[] = {0, 1};
  nd_mesh m = NULL;
  int dim = 0;
  int64_t n = 0;
  const double lo = -1, hi = 2;
  const int64_t v0 = 0;

  EXPECT_ERR(nd_mesh_create(1, 2, x, 1, c, NULL), ND_ERR_NULL, "nd_mesh_create", "out");
  m = MESH_SENTINEL;
  EXPECT_ERR(nd_mesh_create(1, 2, NULL, 1, c, &m), ND_ERR_NULL, "nd_mesh_create", "coords");
  ck_assert_ptr_null(m);
  m = MESH_SENTINEL;
  EXPECT_ERR(nd_mesh_create(1, 2, x, 1, NULL, &m), ND_ERR_NULL, "nd_mesh_create", "cells");
  ck_assert_ptr_null(m);
  EXPECT_ERR(nd_mesh_create_interval(4, 0, 1, NULL), ND_ERR_NULL, "nd_mesh_create_interval",
             "out");

  /* NULL handle */
  EXPECT_ERR(nd_mesh_set_region(NULL, 1, 1, &v0), ND_ERR_NULL, "nd_mesh_set_region", "NULL");
  EXPECT_ERR(nd_mesh_mark_boundary_box(NULL, 1, &lo, &hi), ND_ERR_NULL,
             "nd_mesh_mark_boundary_box", "NULL");
  EXPECT_ERR(nd_mesh_get_dimension(NULL, &dim), ND_ERR_NULL, "nd_mesh_get_dimension", "NULL");
  EXPECT_ERR(nd_mesh_get_vertex_count(NULL, &n), ND_ERR_NULL, "nd_mesh_get_vertex_count",
             "NULL");
  EXPECT_ERR(nd_mesh_get_cell_count(NULL, &n), ND_ERR_NULL, "nd_mesh_get_cell_count", "NULL");
  EXPECT_ERR(nd_mesh_get_region_size(NULL, 1, &n), ND_ERR_NULL, "nd_mesh_get_region_size",
             "NULL");

  /* NULL arrays and out-pointers on a valid mesh */
  m = interval_with_regions(4);
  EXPECT_ERR(nd_mesh_set_region(m, 3, 1, NULL), ND_ERR_NULL, "nd_mesh_set_region",
             "facet_vertices");
  EXPECT_ERR(nd_mesh_mark_boundary_box(m, 3, NULL, &hi), ND_ERR_NULL,
             "nd_mesh_mark_boundary_box", "lo");
  EXPECT_ERR(nd_mesh_mark_boundary_box(m, 3, &lo, NULL), ND_ERR_NULL,
             "nd_mesh_mark_boundary_box", "hi");
  EXPECT_ERR(nd_mesh_get_dimension(m, NULL), ND_ERR_NULL, "nd_mesh_get_dimension", "dim");
  EXPECT_ERR(nd_mesh_get_vertex_count(m, NULL), ND_ERR_NULL, "nd_mesh_get_vertex_count",
             "n_vertices");
  EXPECT_ERR(nd_mesh_get_cell_count(m, NULL), ND_ERR_NULL, "nd_mesh_get_cell_count",
             "n_cells");
  EXPECT_ERR(nd_mesh_get_region_size(m, 1, NULL), ND_ERR_NULL, "nd_mesh_get_region_size",
             "n_facets");

  /* the getters still work */
  EXPECT_OK(nd_mesh_get_dimension(m, &dim));
  ck_assert_int_eq(dim, 1);
  EXPECT_OK(nd_mesh_get_vertex_count(m, &n));
  ck_assert_int_eq(n, 5);
  EXPECT_OK(nd_mesh_get_cell_count(m, &n));
  ck_assert_int_eq(n, 4);
  EXPECT_OK(nd_mesh_get_region_size(m, 3, &n));
  ck_assert_int_eq(n, 0);

  /* destroy: NULL, pointer to NULL, sets the handle to NULL, safe twice */
  EXPECT_OK(nd_mesh_destroy(NULL));
  EXPECT_OK(nd_mesh_destroy(&m));
  ck_assert_ptr_null(m);
  EXPECT_OK(nd_mesh_destroy(&m));
  ck_assert_ptr_null(m);
}
END_TEST

START_TEST(mesh_create_orphan_vertex) {
  /* node 3 belongs to no cell: it would carry unknowns with no mass and no
     stiffness (a lumped mass then wrote outside its matrix) */
  const double x[] = {0, 1, 2, 5};
  const int64_t c[] = {0, 1, 1, 2};
  nd_mesh m = MESH_SENTINEL;
  EXPECT_ERR(nd_mesh_create(1, 4, x, 2, c, &m), ND_ERR_INDEX, "nd_mesh_create", "vertex 3");
  ck_assert_ptr_null(m);
}
END_TEST

START_TEST(mesh_create_dimension_and_sizes) {
  const double x[] = {0, 1, 2};
  const int64_t c[] = {0, 1, 1, 2};
  nd_mesh m = MESH_SENTINEL;

  EXPECT_ERR(nd_mesh_create(0, 3, x, 2, c, &m), ND_ERR_DIMENSION, "nd_mesh_create", "dim");
  ck_assert_ptr_null(m);
  EXPECT_ERR(nd_mesh_create(4, 3, x, 2, c, &m), ND_ERR_DIMENSION, "nd_mesh_create", "dim");
  EXPECT_ERR(nd_mesh_create(-1, 3, x, 2, c, &m), ND_ERR_DIMENSION, "nd_mesh_create", "dim");

  EXPECT_ERR(nd_mesh_create(1, 0, x, 2, c, &m), ND_ERR_SIZE, "nd_mesh_create", "n_nodes");
  EXPECT_ERR(nd_mesh_create(1, -3, x, 2, c, &m), ND_ERR_SIZE, "nd_mesh_create", "n_nodes");
  EXPECT_ERR(nd_mesh_create(1, 3, x, 0, c, &m), ND_ERR_SIZE, "nd_mesh_create", "n_cells");
  EXPECT_ERR(nd_mesh_create(1, 3, x, -2, c, &m), ND_ERR_SIZE, "nd_mesh_create", "n_cells");
  ck_assert_ptr_null(m);

  EXPECT_OK(nd_mesh_create(1, 3, x, 2, c, &m));
  ck_assert_ptr_nonnull(m);
  EXPECT_OK(nd_mesh_destroy(&m));
}
END_TEST

START_TEST(mesh_create_cells_errors) {
  const double sq[8] = {0, 0, 1, 0, 1, 1, 0, 1}, lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  const int64_t q[4] = {0, 1, 2, 3}, cw[4] = {0, 3, 2, 1};
  nd_mesh m = MESH_SENTINEL;
  EXPECT_ERR(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 1, q, NULL), ND_ERR_NULL, "nd_mesh_create_cells",
             "out");
  EXPECT_ERR(nd_mesh_create_cells(2, 3, 4, sq, 1, q, &m), ND_ERR_VALUE, "nd_mesh_create_cells", "cell_type");
  ck_assert_ptr_null(m);
  EXPECT_ERR(nd_mesh_create_cells(2, -1, 4, sq, 1, q, &m), ND_ERR_VALUE, "nd_mesh_create_cells", "cell_type");
  EXPECT_ERR(nd_mesh_create_cells(3, ND_CELL_QUADRILATERAL, 4, sq, 1, q, &m), ND_ERR_DIMENSION,
             "nd_mesh_create_cells", "quadrilaterals need dim 2");
  EXPECT_ERR(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, NULL, 1, q, &m), ND_ERR_NULL, "nd_mesh_create_cells",
             "coords");
  EXPECT_ERR(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 0, q, &m), ND_ERR_SIZE, "nd_mesh_create_cells",
             "n_cells");
  EXPECT_ERR(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 1, cw, &m), ND_ERR_DEGENERATE,
             "nd_mesh_create_cells", "counter-clockwise");
  EXPECT_ERR(nd_mesh_create_rectangle_cells(2, 2, lo, hi, ND_CELL_HEXAHEDRON, &m), ND_ERR_VALUE,
             "nd_mesh_create_rectangle_cells", "cell_type");
  EXPECT_ERR(nd_mesh_create_rectangle_cells(0, 2, lo, hi, ND_CELL_QUADRILATERAL, &m), ND_ERR_SIZE,
             "nd_mesh_create_rectangle_cells", "direction 0");
  EXPECT_ERR(nd_mesh_create_rectangle_cells(2, 2, lo, hi, ND_CELL_QUADRILATERAL, NULL), ND_ERR_NULL,
             "nd_mesh_create_rectangle_cells", "out");
  EXPECT_ERR(nd_mesh_create_box_cells(2, 2, 2, lo, hi, 5, &m), ND_ERR_VALUE, "nd_mesh_create_box_cells",
             "cell_type");
  EXPECT_ERR(nd_mesh_create_box_cells(2, 2, 2, NULL, hi, ND_CELL_HEXAHEDRON, &m), ND_ERR_NULL,
             "nd_mesh_create_box_cells", "lo");
  ck_assert_ptr_null(m);
  EXPECT_OK(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 1, q, &m));
  EXPECT_OK(nd_mesh_destroy(&m));
}
END_TEST

/* nd_mesh_create_mixed: each refusal names the cell and what is wrong */
START_TEST(mesh_create_mixed_errors) {
  /* a square in two parts: quadrilateral 0 1 4 3 and triangles 1 2 5, 1 5 4 */
  const double x[12] = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1};
  const int types[3] = {ND_CELL_QUADRILATERAL, ND_CELL_SIMPLEX, ND_CELL_SIMPLEX};
  const int unknown[3] = {ND_CELL_QUADRILATERAL, 7, ND_CELL_SIMPLEX};
  const int hexahedron[3] = {ND_CELL_QUADRILATERAL, ND_CELL_HEXAHEDRON, ND_CELL_SIMPLEX};
  const int64_t cells[10] = {0, 1, 4, 3, 1, 2, 5, 1, 5, 4};
  const int64_t negative[10] = {0, 1, 4, 3, 1, 2, -5, 1, 5, 4}, outside[10] = {0, 1, 4, 3, 1, 2, 6, 1, 5, 4};
  const int64_t inverted[10] = {0, 1, 4, 3, 1, 5, 2, 1, 5, 4};
  nd_mesh m = MESH_SENTINEL;
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, types, cells, NULL), ND_ERR_NULL, "nd_mesh_create_mixed", "out");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, NULL, cells, &m), ND_ERR_NULL, "nd_mesh_create_mixed", "cell_types");
  ck_assert_ptr_null(m);
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, types, NULL, &m), ND_ERR_NULL, "nd_mesh_create_mixed", "cells");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, NULL, 3, types, cells, &m), ND_ERR_NULL, "nd_mesh_create_mixed", "coords");
  EXPECT_ERR(nd_mesh_create_mixed(4, 6, x, 3, types, cells, &m), ND_ERR_DIMENSION, "nd_mesh_create_mixed", "dim");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 0, types, cells, &m), ND_ERR_SIZE, "nd_mesh_create_mixed", "n_cells");
  EXPECT_ERR(nd_mesh_create_mixed(2, 2, x, 3, types, cells, &m), ND_ERR_SIZE, "nd_mesh_create_mixed", "n_nodes");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, unknown, cells, &m), ND_ERR_VALUE, "nd_mesh_create_mixed",
             "cell_types[1] is 7");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, hexahedron, cells, &m), ND_ERR_DIMENSION, "nd_mesh_create_mixed",
             "cell_types[1]: hexahedra need dim 3");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, types, negative, &m), ND_ERR_INDEX, "nd_mesh_create_mixed",
             "cell 1 names vertex -5");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, types, outside, &m), ND_ERR_INDEX, "nd_mesh_create_mixed",
             "cell 1 names vertex 6");
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, types, inverted, &m), ND_ERR_DEGENERATE, "nd_mesh_create_mixed",
             "cell 1 is inverted");
  /* counts that do not match the cells: the two triangles given as quadrilaterals */
  const int all_quads[3] = {ND_CELL_QUADRILATERAL, ND_CELL_QUADRILATERAL, ND_CELL_QUADRILATERAL};
  const int64_t wrong_count[12] = {0, 1, 4, 3, 1, 2, 5, 1, 5, 4, 0, 0};
  EXPECT_ERR(nd_mesh_create_mixed(2, 6, x, 3, all_quads, wrong_count, &m), ND_ERR_INDEX, "nd_mesh_create_mixed",
             "cell 1 repeats vertex 1");
  /* 3D: tetrahedra and hexahedra do not mix (no prisms or pyramids) */
  const double x3[27] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0, 0, 2};
  const int mix3[2] = {ND_CELL_HEXAHEDRON, ND_CELL_SIMPLEX};
  const int64_t cells3[12] = {0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 7, 8};
  EXPECT_ERR(nd_mesh_create_mixed(3, 9, x3, 2, mix3, cells3, &m), ND_ERR_DIMENSION, "nd_mesh_create_mixed",
             "pyramids or prisms");
  ck_assert_ptr_null(m);
  EXPECT_OK(nd_mesh_create_mixed(2, 6, x, 3, types, cells, &m));
  EXPECT_OK(nd_mesh_destroy(&m));
}
END_TEST

START_TEST(mesh_create_indices) {
  const double x[] = {0, 1, 2};
  nd_mesh m = MESH_SENTINEL;
  const int64_t too_big[] = {0, 1, 1, 3};   /* cell 1 names vertex 3 of 3 */
  const int64_t negative[] = {0, 1, -1, 2}; /* cell 1 names vertex -1 */
  const int64_t repeated[] = {0, 1, 2, 2};  /* cell 1 repeats vertex 2 */

  EXPECT_ERR(nd_mesh_create(1, 3, x, 2, too_big, &m), ND_ERR_INDEX, "nd_mesh_create", "cell 1");
  ck_assert_ptr_null(m);
  EXPECT_ERR(nd_mesh_create(1, 3, x, 2, negative, &m), ND_ERR_INDEX, "nd_mesh_create",
             "cell 1");
  EXPECT_ERR(nd_mesh_create(1, 3, x, 2, repeated, &m), ND_ERR_INDEX, "nd_mesh_create",
             "cell 1");

  /* 2D: out of range and repeated vertex in a triangle */
  const int64_t tri_big[] = {0, 1, 2, 0, 2, 4};
  const int64_t tri_rep[] = {0, 1, 2, 0, 2, 2};
  EXPECT_ERR(nd_mesh_create(2, 4, square_xy, 2, tri_big, &m), ND_ERR_INDEX, "nd_mesh_create",
             "cell 1");
  EXPECT_ERR(nd_mesh_create(2, 4, square_xy, 2, tri_rep, &m), ND_ERR_INDEX, "nd_mesh_create",
             "cell 1");
  ck_assert_ptr_null(m);

  /* 1-based connectivity of a 3x3-node grid: shifted by one, cell 2 becomes
     {2, 3, 6}, inverted, before cell 6 names vertex 9; the index is reported,
     with the hint, not the inversion */
  double grid[18];
  int64_t tris[24], tris1[24];
  for (int k = 0; k < 9; ++k) grid[2 * k] = k % 3, grid[2 * k + 1] = k / 3;
  for (int j = 0, c = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i, c += 2) {
      const int64_t a = 3 * j + i, t[6] = {a, a + 1, a + 4, a, a + 4, a + 3};
      for (int k = 0; k < 6; ++k) tris[3 * c + k] = t[k], tris1[3 * c + k] = t[k] + 1;
    }
  EXPECT_OK(nd_mesh_create(2, 9, grid, 8, tris, &m));
  EXPECT_OK(nd_mesh_destroy(&m));
  EXPECT_ERR(nd_mesh_create(2, 9, grid, 8, tris1, &m), ND_ERR_INDEX, "nd_mesh_create", "cell 6 names vertex 9");
  ck_assert(contains(nd_last_error(), "0-based") && contains(nd_last_error(), "1-based"));
  ck_assert_ptr_null(m);
  /* a single index out of range: 0-based is said, 1-based not suspected */
  EXPECT_ERR(nd_mesh_create(1, 3, x, 2, too_big, &m), ND_ERR_INDEX, "nd_mesh_create", "0-based");
  ck_assert(!contains(nd_last_error(), "1-based"));
}
END_TEST

START_TEST(mesh_create_nonfinite) {
  const int64_t c[] = {0, 1, 1, 2};
  const double x_nan[] = {0, NAN, 2};
  const double x_inf[] = {0, 1, INFINITY};
  const double x_minf[] = {-INFINITY, 1, 2};
  nd_mesh m = MESH_SENTINEL;

  EXPECT_ERR(nd_mesh_create(1, 3, x_nan, 2, c, &m), ND_ERR_NONFINITE, "nd_mesh_create",
             "node 1");
  ck_assert_ptr_null(m);
  EXPECT_ERR(nd_mesh_create(1, 3, x_inf, 2, c, &m), ND_ERR_NONFINITE, "nd_mesh_create",
             "node 2");
  EXPECT_ERR(nd_mesh_create(1, 3, x_minf, 2, c, &m), ND_ERR_NONFINITE, "nd_mesh_create",
             "node 0");

  double xy[8];
  memcpy(xy, square_xy, sizeof xy);
  xy[5] = NAN; /* y of node 2 */
  EXPECT_ERR(nd_mesh_create(2, 4, xy, 2, square_cells, &m), ND_ERR_NONFINITE,
             "nd_mesh_create", "node 2");
  ck_assert_ptr_null(m);
}
END_TEST

START_TEST(mesh_create_degenerate) {
  nd_mesh m = MESH_SENTINEL;

  /* 1D: cell 1 has zero length, its vertices at one position */
  const double x0[] = {0, 1, 1};
  const int64_t c0[] = {0, 1, 1, 2};
  EXPECT_ERR(nd_mesh_create(1, 3, x0, 2, c0, &m), ND_ERR_DEGENERATE, "nd_mesh_create",
             "vertices 1 and 2");
  ck_assert_ptr_null(m);

  /* 2D: cell 1 has zero area (three collinear vertices) */
  const double xy[] = {0, 0, 1, 0, 1, 1, 2, 0};
  const int64_t tri[] = {0, 1, 2, 0, 3, 1};
  EXPECT_ERR(nd_mesh_create(2, 4, xy, 2, tri, &m), ND_ERR_DEGENERATE, "nd_mesh_create",
             "cell 1");

  /* inverted: 1D cell {1, 0} with x0 < x1, clockwise triangle */
  const double x1[] = {0, 1, 2};
  const int64_t c_inv[] = {0, 1, 2, 1};
  EXPECT_ERR(nd_mesh_create(1, 3, x1, 2, c_inv, &m), ND_ERR_DEGENERATE, "nd_mesh_create",
             "cell 1");
  const int64_t c_inv0[] = {1, 0};
  EXPECT_ERR(nd_mesh_create(1, 2, x1, 1, c_inv0, &m), ND_ERR_DEGENERATE, "nd_mesh_create",
             "cell 0");
  const int64_t cw[] = {0, 1, 2, 0, 3, 2}; /* cell 1 clockwise */
  EXPECT_ERR(nd_mesh_create(2, 4, square_xy, 2, cw, &m), ND_ERR_DEGENERATE, "nd_mesh_create",
             "cell 1");
  ck_assert_ptr_null(m);

  /* 3D: a positive tetrahedron is accepted, the mirrored one is not */
  const double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const int64_t tet[] = {0, 1, 2, 3}, tet_inv[] = {0, 2, 1, 3};
  const int64_t tet_flat[] = {0, 1, 2, 3};
  const double xyz_flat[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  EXPECT_OK(nd_mesh_create(3, 4, xyz, 1, tet, &m));
  EXPECT_OK(nd_mesh_destroy(&m));
  EXPECT_ERR(nd_mesh_create(3, 4, xyz, 1, tet_inv, &m), ND_ERR_DEGENERATE, "nd_mesh_create",
             "cell 0");
  EXPECT_ERR(nd_mesh_create(3, 4, xyz_flat, 1, tet_flat, &m), ND_ERR_DEGENERATE,
             "nd_mesh_create", "cell 0");
  ck_assert_ptr_null(m);
}
END_TEST

START_TEST(mesh_create_interval_errors) {
  nd_mesh m = MESH_SENTINEL;
  EXPECT_ERR(nd_mesh_create_interval(0, 0, 1, &m), ND_ERR_SIZE, "nd_mesh_create_interval",
             "n_cells");
  ck_assert_ptr_null(m);
  EXPECT_ERR(nd_mesh_create_interval(-5, 0, 1, &m), ND_ERR_SIZE, "nd_mesh_create_interval",
             "n_cells");
  EXPECT_ERR(nd_mesh_create_interval(4, 1, 1, &m), ND_ERR_DEGENERATE, "nd_mesh_create_interval",
             "b");
  EXPECT_ERR(nd_mesh_create_interval(4, 1, 0, &m), ND_ERR_DEGENERATE, "nd_mesh_create_interval",
             "b");
  EXPECT_ERR(nd_mesh_create_interval(4, NAN, 1, &m), ND_ERR_NONFINITE, "nd_mesh_create_interval",
             NULL);
  EXPECT_ERR(nd_mesh_create_interval(4, 0, NAN, &m), ND_ERR_NONFINITE, "nd_mesh_create_interval",
             NULL);
  EXPECT_ERR(nd_mesh_create_interval(4, -INFINITY, 1, &m), ND_ERR_NONFINITE,
             "nd_mesh_create_interval", NULL);
  EXPECT_ERR(nd_mesh_create_interval(4, 0, INFINITY, &m), ND_ERR_NONFINITE,
             "nd_mesh_create_interval", NULL);
  ck_assert_ptr_null(m);
}
END_TEST

/* Failures found while building the cells of an interval are reported by
   nd_mesh_create_interval, not by the nd_mesh_create it uses internally.
   Loop test: _i = 0, 1. */
START_TEST(mesh_create_interval_error_names_function) {
  nd_mesh m = MESH_SENTINEL;
  if (_i == 0) /* 100 cells on an interval 4.5 ulps long: adjacent vertices coincide */
    EXPECT_ERR(nd_mesh_create_interval(100, 1.0, 1.0 + 1e-15, &m), ND_ERR_DEGENERATE,
               "nd_mesh_create_interval", NULL);
  else /* b - a overflows: the interior vertex is not finite */
    EXPECT_ERR(nd_mesh_create_interval(2, -1e308, 1e308, &m), ND_ERR_NONFINITE,
               "nd_mesh_create_interval", NULL);
  ck_assert_ptr_null(m);
}
END_TEST

START_TEST(mesh_set_region_errors) {
  nd_mesh m = NULL;
  int64_t n = -1;
  EXPECT_OK(nd_mesh_create_interval(4, 0.0, 1.0, &m)); /* vertices 0..4 */

  const int64_t interior = 2, outside = 5, negative = -1, left = 0;
  EXPECT_ERR(nd_mesh_set_region(m, 1, 1, &interior), ND_ERR_REGION, "nd_mesh_set_region",
             "facet 0");
  EXPECT_ERR(nd_mesh_set_region(m, 1, 1, &outside), ND_ERR_INDEX, "nd_mesh_set_region",
             "facet 0");
  EXPECT_ERR(nd_mesh_set_region(m, 1, 1, &negative), ND_ERR_INDEX, "nd_mesh_set_region",
             "facet 0");
  EXPECT_ERR(nd_mesh_set_region(m, -1, 1, &left), ND_ERR_REGION, "nd_mesh_set_region",
             "region");
  EXPECT_ERR(nd_mesh_set_region(m, 1, 0, &left), ND_ERR_SIZE, "nd_mesh_set_region",
             "n_facets");
  EXPECT_ERR(nd_mesh_set_region(m, 1, -1, &left), ND_ERR_SIZE, "nd_mesh_set_region",
             "n_facets");

  /* a rejected call adds nothing, not even its valid facets */
  const int64_t mixed[] = {0, 2}; /* facet 0 on the boundary, facet 1 interior */
  EXPECT_ERR(nd_mesh_set_region(m, 1, 2, mixed), ND_ERR_REGION, "nd_mesh_set_region",
             "facet 1");
  EXPECT_OK(nd_mesh_get_region_size(m, 1, &n));
  ck_assert_int_eq(n, 0);

  EXPECT_OK(nd_mesh_set_region(m, 1, 1, &left));
  EXPECT_OK(nd_mesh_get_region_size(m, 1, &n));
  ck_assert_int_eq(n, 1);

  /* the box marker */
  const double lo = NAN, hi = 1;
  EXPECT_ERR(nd_mesh_mark_boundary_box(m, 2, &lo, &hi), ND_ERR_NONFINITE,
             "nd_mesh_mark_boundary_box", NULL);
  EXPECT_ERR(nd_mesh_mark_boundary_box(m, -2, &hi, &hi), ND_ERR_REGION,
             "nd_mesh_mark_boundary_box", "region");
  EXPECT_OK(nd_mesh_get_region_size(m, 2, &n));
  ck_assert_int_eq(n, 0);
  EXPECT_OK(nd_mesh_destroy(&m));

  /* 2D: the diagonal of the square is interior; edges are found in any order */
  m = square_with_regions();
  const int64_t diagonal[] = {0, 2}, right[] = {2, 1}, bad[] = {0, 9};
  EXPECT_ERR(nd_mesh_set_region(m, 3, 1, diagonal), ND_ERR_REGION, "nd_mesh_set_region",
             "facet 0");
  EXPECT_ERR(nd_mesh_set_region(m, 3, 1, bad), ND_ERR_INDEX, "nd_mesh_set_region", "facet 0");
  EXPECT_OK(nd_mesh_set_region(m, 3, 1, right));
  EXPECT_OK(nd_mesh_get_region_size(m, 3, &n));
  ck_assert_int_eq(n, 1);
  EXPECT_OK(nd_mesh_destroy(&m));
}
END_TEST

/* ======================================================================== */
/* problem definition                                                        */
/* ======================================================================== */

START_TEST(problem_null_handles) {
  const double v[3] = {0, 1, 0};
  const double params[2] = {0.25, 0.5};
  int64_t n = 0;
  double x[8] = {0};
  const char *fn_null = "problem";

  EXPECT_ERR(nd_problem_set_material(NULL, 1, 0, 1), ND_ERR_NULL, "nd_problem_set_material",
             fn_null);
  EXPECT_ERR(nd_problem_set_dirichlet(NULL, 1), ND_ERR_NULL, "nd_problem_set_dirichlet",
             fn_null);
  EXPECT_ERR(nd_problem_set_body_force(NULL, v), ND_ERR_NULL, "nd_problem_set_body_force",
             fn_null);
  EXPECT_ERR(nd_problem_set_neumann(NULL, 1, v), ND_ERR_NULL, "nd_problem_set_neumann",
             fn_null);
  EXPECT_ERR(nd_problem_set_contact_plane(NULL, 1, v, v), ND_ERR_NULL,
             "nd_problem_set_contact_plane", fn_null);
  EXPECT_ERR(nd_problem_set_nitsche(NULL, 1, 0.2), ND_ERR_NULL, "nd_problem_set_nitsche",
             fn_null);
  EXPECT_ERR(nd_problem_set_scheme(NULL, ND_SCHEME_NEWMARK, params), ND_ERR_NULL,
             "nd_problem_set_scheme", fn_null);
  EXPECT_ERR(nd_problem_set_nodal_forces(NULL, 1, x), ND_ERR_NULL,
             "nd_problem_set_nodal_forces", fn_null);
  EXPECT_ERR(nd_problem_set_newton(NULL, 1e-10, 0, 50), ND_ERR_NULL, "nd_problem_set_newton",
             fn_null);
  EXPECT_ERR(nd_problem_set_mass_lumping(NULL, 1), ND_ERR_NULL, "nd_problem_set_mass_lumping",
             fn_null);
  EXPECT_ERR(nd_problem_set_linear_solver(NULL, ND_SOLVER_AUTO), ND_ERR_NULL,
             "nd_problem_set_linear_solver", fn_null);
  EXPECT_ERR(nd_problem_set_timestep(NULL, 0.1), ND_ERR_NULL, "nd_problem_set_timestep",
             fn_null);
  EXPECT_ERR(nd_problem_set_comm_f(NULL, 0), ND_ERR_NULL, "nd_problem_set_comm_f", fn_null);
  EXPECT_ERR(nd_problem_set_initial_state(NULL, 1, x, x), ND_ERR_NULL,
             "nd_problem_set_initial_state", fn_null);
  EXPECT_ERR(nd_problem_set_monitor(NULL, NULL, NULL), ND_ERR_NULL, "nd_problem_set_monitor",
             fn_null);
  EXPECT_ERR(nd_problem_get_node_count(NULL, &n), ND_ERR_NULL, "nd_problem_get_node_count",
             fn_null);
  EXPECT_ERR(nd_problem_get_node_coordinates(NULL, 1, x), ND_ERR_NULL,
             "nd_problem_get_node_coordinates", fn_null);
  EXPECT_ERR(nd_problem_get_contact_point_count(NULL, &n), ND_ERR_NULL,
             "nd_problem_get_contact_point_count", fn_null);
  EXPECT_ERR(nd_problem_get_contact_points(NULL, 1, x, x), ND_ERR_NULL,
             "nd_problem_get_contact_points", fn_null);
  EXPECT_ERR(nd_step(NULL), ND_ERR_NULL, "nd_step", fn_null);
  EXPECT_ERR(nd_problem_setup(NULL), ND_ERR_NULL, "nd_problem_setup", fn_null);
  EXPECT_ERR(nd_get_field(NULL, ND_FIELD_DISPLACEMENT, 1, x), ND_ERR_NULL, "nd_get_field",
             fn_null);
  EXPECT_ERR(nd_get_field_gathered(NULL, ND_FIELD_DISPLACEMENT, 0, 1, x), ND_ERR_NULL,
             "nd_get_field_gathered", fn_null);
  EXPECT_ERR(nd_get_scalar(NULL, ND_TIME, x), ND_ERR_NULL, "nd_get_scalar", fn_null);
  EXPECT_ERR(nd_get_contact_pressure(NULL, 1, x), ND_ERR_NULL, "nd_get_contact_pressure",
             fn_null);

  /* nd_problem_create: NULL mesh and NULL out */
  nd_problem p = PROBLEM_SENTINEL;
  EXPECT_ERR(nd_problem_create(NULL, 1, &p), ND_ERR_NULL, "nd_problem_create", "mesh");
  ck_assert_ptr_null(p);
  nd_mesh m = interval_with_regions(4);
  EXPECT_ERR(nd_problem_create(m, 1, NULL), ND_ERR_NULL, "nd_problem_create", "out");
  EXPECT_OK(nd_mesh_destroy(&m));

  /* destroy: NULL, pointer to NULL, sets the handle to NULL, safe twice */
  p = NULL;
  EXPECT_OK(nd_problem_destroy(NULL));
  EXPECT_OK(nd_problem_destroy(&p));
  p = problem_1d();
  EXPECT_OK(nd_problem_destroy(&p));
  ck_assert_ptr_null(p);
  EXPECT_OK(nd_problem_destroy(&p));
  ck_assert_ptr_null(p);
}
END_TEST

/* Prescribed motion: each argument refused with its code, the problem
   unchanged; a step that would move a clamped DOF a contact point's rows
   read (the one-cell bar: the contact point's s_q reads the clamped end) is
   refused and not taken. */
START_TEST(problem_prescribed_motion) {
  nd_problem p = nd_test_bar(1, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  const int64_t n = node_count(p);
  const double d = 0.01, nan = NAN;
  double u[4] = {0, 0, 0, 0};
  EXPECT_ERR(nd_problem_set_dirichlet_value(NULL, 2, &d), ND_ERR_NULL, "nd_problem_set_dirichlet_value", "problem");
  EXPECT_ERR(nd_problem_set_dirichlet_nodal(NULL, n, u), ND_ERR_NULL, "nd_problem_set_dirichlet_nodal", "problem");
  EXPECT_ERR(nd_problem_set_dirichlet_value(p, 2, NULL), ND_ERR_NULL, "nd_problem_set_dirichlet_value", "u");
  EXPECT_ERR(nd_problem_set_dirichlet_nodal(p, n, NULL), ND_ERR_NULL, "nd_problem_set_dirichlet_nodal", "u");
  EXPECT_ERR(nd_problem_set_dirichlet_value(p, 2, &nan), ND_ERR_NONFINITE, "nd_problem_set_dirichlet_value", "u");
  u[1] = INFINITY;
  EXPECT_ERR(nd_problem_set_dirichlet_nodal(p, n, u), ND_ERR_NONFINITE, "nd_problem_set_dirichlet_nodal", "u");
  u[1] = 0;
  EXPECT_ERR(nd_problem_set_dirichlet_nodal(p, n + 1, u), ND_ERR_SIZE, "nd_problem_set_dirichlet_nodal", NULL);
  EXPECT_ERR(nd_problem_set_dirichlet_nodal(p, -1, u), ND_ERR_SIZE, "nd_problem_set_dirichlet_nodal", NULL);
  /* region 1 is the contact end, not clamped; region 9 does not exist */
  EXPECT_ERR(nd_problem_set_dirichlet_value(p, 1, &d), ND_ERR_REGION, "nd_problem_set_dirichlet_value", "region 1");
  EXPECT_ERR(nd_problem_set_dirichlet_value(p, 9, &d), ND_ERR_REGION, "nd_problem_set_dirichlet_value", "region 9");
  /* the failed calls left no motion: the step is the bar's own */
  EXPECT_OK(nd_step(p));
  double w = 1;
  EXPECT_OK(nd_get_scalar(p, ND_WORK_PRESCRIBED, &w));
  ck_assert_double_eq(w, 0);
  EXPECT_OK(nd_problem_set_dirichlet_value(p, 2, &d));
  EXPECT_ERR(nd_step(p), ND_ERR_STATE, "nd_step", "contact point");
  double t = 0;
  EXPECT_OK(nd_get_scalar(p, ND_STEP_INDEX, &t));
  ck_assert_double_eq(t, 1);
  EXPECT_OK(nd_problem_set_dirichlet_nodal(p, n, u)); /* back to 0: the bar steps again */
  EXPECT_OK(nd_step(p));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_null_arrays) {
  nd_problem p = nd_test_bar(4, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  const double one = 1;
  const int64_t n = node_count(p), nq = contact_count(p);

  EXPECT_ERR(nd_problem_set_body_force(p, NULL), ND_ERR_NULL, "nd_problem_set_body_force",
             "f");
  EXPECT_ERR(nd_problem_set_neumann(p, 1, NULL), ND_ERR_NULL, "nd_problem_set_neumann", "g");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, NULL, &one), ND_ERR_NULL,
             "nd_problem_set_contact_plane", "point");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, &one, NULL), ND_ERR_NULL,
             "nd_problem_set_contact_plane", "normal");
  EXPECT_ERR(nd_problem_set_nodal_forces(p, n, NULL), ND_ERR_NULL,
             "nd_problem_set_nodal_forces", "f");
  EXPECT_ERR(nd_problem_get_node_count(p, NULL), ND_ERR_NULL, "nd_problem_get_node_count",
             "n_nodes");
  EXPECT_ERR(nd_problem_get_node_coordinates(p, n, NULL), ND_ERR_NULL,
             "nd_problem_get_node_coordinates", "coords");
  EXPECT_ERR(nd_problem_get_contact_point_count(p, NULL), ND_ERR_NULL,
             "nd_problem_get_contact_point_count", "n_points");
  EXPECT_ERR(nd_get_field(p, ND_FIELD_DISPLACEMENT, n, NULL), ND_ERR_NULL, "nd_get_field",
             "out");
  EXPECT_ERR(nd_get_field_gathered(p, ND_FIELD_DISPLACEMENT, 0, n, NULL), ND_ERR_NULL,
             "nd_get_field_gathered", "out");
  EXPECT_ERR(nd_get_scalar(p, ND_TIME, NULL), ND_ERR_NULL, "nd_get_scalar", "out");
  EXPECT_ERR(nd_get_contact_pressure(p, nq, NULL), ND_ERR_NULL, "nd_get_contact_pressure",
             "out");
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_create_degree) {
  nd_mesh m = interval_with_regions(4);
  nd_problem p = PROBLEM_SENTINEL;
  EXPECT_ERR(nd_problem_create(m, 0, &p), ND_ERR_DEGREE, "nd_problem_create", "degree");
  ck_assert_ptr_null(p);
  EXPECT_ERR(nd_problem_create(m, 3, &p), ND_ERR_DEGREE, "nd_problem_create", "degree");
  EXPECT_ERR(nd_problem_create(m, -1, &p), ND_ERR_DEGREE, "nd_problem_create", "degree");
  ck_assert_ptr_null(p);
  for (int degree = 1; degree <= 2; ++degree) {
    EXPECT_OK(nd_problem_create(m, degree, &p));
    EXPECT_OK(nd_problem_destroy(&p));
  }
  EXPECT_OK(nd_mesh_destroy(&m));
}
END_TEST

START_TEST(problem_material) {
  nd_problem p = problem_1d();
  EXPECT_ERR(nd_problem_set_material(p, 0, 0, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "young");
  EXPECT_ERR(nd_problem_set_material(p, -1, 0, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "young");
  EXPECT_ERR(nd_problem_set_material(p, NAN, 0, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "young");
  EXPECT_ERR(nd_problem_set_material(p, INFINITY, 0, 1), ND_ERR_MATERIAL,
             "nd_problem_set_material", "young");
  EXPECT_ERR(nd_problem_set_material(p, 1, 0, 0), ND_ERR_MATERIAL, "nd_problem_set_material",
             "density");
  EXPECT_ERR(nd_problem_set_material(p, 1, 0, -2), ND_ERR_MATERIAL, "nd_problem_set_material",
             "density");
  EXPECT_ERR(nd_problem_set_material(p, 1, 0, NAN), ND_ERR_MATERIAL, "nd_problem_set_material",
             "density");
  /* 1D: Poisson's ratio is not used, any value is accepted */
  EXPECT_OK(nd_problem_set_material(p, 1, 0.7, 1));
  EXPECT_OK(nd_problem_set_material(p, 1, -3, 1));
  EXPECT_OK(nd_problem_destroy(&p));

  p = problem_2d();
  EXPECT_ERR(nd_problem_set_material(p, 1, -1, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "poisson");
  EXPECT_ERR(nd_problem_set_material(p, 1, -1.5, 1), ND_ERR_MATERIAL,
             "nd_problem_set_material", "poisson");
  EXPECT_ERR(nd_problem_set_material(p, 1, 0.5, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "poisson");
  EXPECT_ERR(nd_problem_set_material(p, 1, 0.7, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "poisson");
  EXPECT_ERR(nd_problem_set_material(p, 1, NAN, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "poisson");
  EXPECT_ERR(nd_problem_set_material(p, 0, 0.3, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             "young");
  EXPECT_OK(nd_problem_set_material(p, 1, 0.3, 1));
  EXPECT_OK(nd_problem_set_material(p, 1, -0.99, 1));
  EXPECT_OK(nd_problem_set_material(p, 1, 0.49, 1));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* adaptive steps: finite values, tolerance >= 0, 0 < tau_min <= tau_max when
   on; an explicit scheme is refused at the step, the problem unchanged */
START_TEST(problem_adaptive_timestep) {
  nd_problem p = problem_1d();
  EXPECT_ERR(nd_problem_set_adaptive_timestep(NULL, 1e-3, 1e-6, 1e-2), ND_ERR_NULL, "nd_problem_set_adaptive_timestep", "problem");
  EXPECT_ERR(nd_problem_set_adaptive_timestep(p, NAN, 1e-6, 1e-2), ND_ERR_NONFINITE, "nd_problem_set_adaptive_timestep", "finite");
  EXPECT_ERR(nd_problem_set_adaptive_timestep(p, 1e-3, 1e-6, INFINITY), ND_ERR_NONFINITE, "nd_problem_set_adaptive_timestep", "finite");
  EXPECT_ERR(nd_problem_set_adaptive_timestep(p, -1e-3, 1e-6, 1e-2), ND_ERR_VALUE, "nd_problem_set_adaptive_timestep", "tolerance");
  EXPECT_ERR(nd_problem_set_adaptive_timestep(p, 1e-3, 0, 1e-2), ND_ERR_TIMESTEP, "nd_problem_set_adaptive_timestep", "tau_min");
  EXPECT_ERR(nd_problem_set_adaptive_timestep(p, 1e-3, -1, 1e-2), ND_ERR_TIMESTEP, "nd_problem_set_adaptive_timestep", "tau_min");
  EXPECT_ERR(nd_problem_set_adaptive_timestep(p, 1e-3, 1e-2, 1e-3), ND_ERR_TIMESTEP, "nd_problem_set_adaptive_timestep", "tau_max");
  EXPECT_OK(nd_problem_set_adaptive_timestep(p, 1e-3, 1e-6, 1e-2));
  EXPECT_OK(nd_problem_set_adaptive_timestep(p, 0, 0, 0)); /* off: tau_min, tau_max not read */
  EXPECT_OK(nd_problem_destroy(&p));
  const double explicit_newmark[2] = {0, 0.5};
  p = nd_test_bar(8, 1, ND_SCHEME_NEWMARK, explicit_newmark, 1.0, 0.2, 1e-3);
  EXPECT_OK(nd_problem_set_adaptive_timestep(p, 1e-3, 1e-6, 1e-3));
  EXPECT_ERR(nd_step(p), ND_ERR_STATE, "nd_step", "implicit");
  double n = -1;
  EXPECT_OK(nd_get_scalar(p, ND_STEP_INDEX, &n));
  ck_assert_double_eq(n, 0);
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* Rayleigh damping: alpha, beta >= 0 and finite; plane stress only in 2D;
   stiffness damping with mass redistribution refused at set-up */
START_TEST(problem_damping_plane_stress) {
  nd_problem p = problem_1d();
  EXPECT_ERR(nd_problem_set_damping(NULL, 0.1, 0), ND_ERR_NULL, "nd_problem_set_damping", "problem");
  EXPECT_ERR(nd_problem_set_damping(p, -0.1, 0), ND_ERR_VALUE, "nd_problem_set_damping", "alpha");
  EXPECT_ERR(nd_problem_set_damping(p, NAN, 0), ND_ERR_VALUE, "nd_problem_set_damping", "alpha");
  EXPECT_ERR(nd_problem_set_damping(p, 0, -1e-3), ND_ERR_VALUE, "nd_problem_set_damping", "beta");
  EXPECT_ERR(nd_problem_set_damping(p, 0, INFINITY), ND_ERR_VALUE, "nd_problem_set_damping", "beta");
  EXPECT_OK(nd_problem_set_damping(p, 0.1, 1e-3));
  EXPECT_OK(nd_problem_set_damping(p, 0, 0));
  EXPECT_ERR(nd_problem_set_plane_stress(NULL, 1), ND_ERR_NULL, "nd_problem_set_plane_stress", "problem");
  EXPECT_ERR(nd_problem_set_plane_stress(p, 1), ND_ERR_DIMENSION, "nd_problem_set_plane_stress", "2D");
  EXPECT_OK(nd_problem_set_plane_stress(p, 0));
  EXPECT_OK(nd_problem_destroy(&p));
  p = problem_2d();
  EXPECT_OK(nd_problem_set_plane_stress(p, 1));
  EXPECT_OK(nd_problem_set_plane_stress(p, 0));
  EXPECT_OK(nd_problem_destroy(&p));
  /* beta > 0 with mass redistribution: the massless DOFs would carry beta K V */
  const double nm[2] = {0.25, 0.5};
  p = nd_test_bar(8, 1, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, 0.01);
  EXPECT_OK(nd_problem_set_mass_redistribution(p, 1));
  EXPECT_OK(nd_problem_set_damping(p, 0, 1e-3));
  EXPECT_ERR(nd_problem_setup(p), ND_ERR_STATE, "nd_problem_setup", "redistribution");
  EXPECT_OK(nd_problem_set_damping(p, 0.1, 0));
  EXPECT_OK(nd_problem_setup(p));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* cell regions (nd_mesh_set_cell_region, nd_mesh_get_cell_regions) and a
   material per region: each refusal changes nothing */
START_TEST(cell_regions_and_materials) {
  nd_mesh m = NULL;
  int region[4] = {-1, -1, -1, -1};
  const int64_t two[] = {1, 2}, mixed[] = {0, 4}, negative = -1;
  EXPECT_OK(nd_mesh_create_interval(4, 0.0, 1.0, &m));
  EXPECT_ERR(nd_mesh_set_cell_region(NULL, 1, 2, two), ND_ERR_NULL, "nd_mesh_set_cell_region", "mesh");
  EXPECT_ERR(nd_mesh_set_cell_region(m, 1, 2, NULL), ND_ERR_NULL, "nd_mesh_set_cell_region", "cells");
  EXPECT_ERR(nd_mesh_set_cell_region(m, -1, 2, two), ND_ERR_REGION, "nd_mesh_set_cell_region", "cell_region");
  EXPECT_ERR(nd_mesh_set_cell_region(m, 1, 0, two), ND_ERR_SIZE, "nd_mesh_set_cell_region", "n_cells");
  EXPECT_ERR(nd_mesh_set_cell_region(m, 1, 2, mixed), ND_ERR_INDEX, "nd_mesh_set_cell_region", "cells[1] = 4");
  EXPECT_ERR(nd_mesh_set_cell_region(m, 1, 1, &negative), ND_ERR_INDEX, "nd_mesh_set_cell_region", "cells[0]");
  EXPECT_ERR(nd_mesh_get_cell_regions(NULL, 4, region), ND_ERR_NULL, "nd_mesh_get_cell_regions", "mesh");
  EXPECT_ERR(nd_mesh_get_cell_regions(m, 4, NULL), ND_ERR_NULL, "nd_mesh_get_cell_regions", "region");
  EXPECT_ERR(nd_mesh_get_cell_regions(m, 3, region), ND_ERR_SIZE, "nd_mesh_get_cell_regions", "n_cells");
  ck_assert_int_eq(region[0], -1); /* a refused call writes nothing */
  EXPECT_OK(nd_mesh_get_cell_regions(m, 4, region)); /* the refused calls moved no cell */
  for (int c = 0; c < 4; ++c) ck_assert_int_eq(region[c], 0);
  EXPECT_OK(nd_mesh_set_cell_region(m, 5, 2, two));
  EXPECT_OK(nd_mesh_get_cell_regions(m, 4, region));
  ck_assert_int_eq(region[0], 0);
  ck_assert_int_eq(region[1], 5);
  ck_assert_int_eq(region[2], 5);

  nd_problem p = NULL;
  EXPECT_OK(nd_problem_create(m, 1, &p));
  EXPECT_OK(nd_mesh_destroy(&m));
  EXPECT_ERR(nd_problem_set_material_region(NULL, 5, 1, 0, 1), ND_ERR_NULL, "nd_problem_set_material_region",
             "problem");
  EXPECT_ERR(nd_problem_set_material_region(p, 0, 1, 0, 1), ND_ERR_REGION, "nd_problem_set_material_region",
             "cell_region is 0");
  EXPECT_ERR(nd_problem_set_material_region(p, 6, 1, 0, 1), ND_ERR_REGION, "nd_problem_set_material_region",
             "cell region 6 has no cells");
  EXPECT_ERR(nd_problem_set_material_region(p, 5, 0, 0, 1), ND_ERR_MATERIAL, "nd_problem_set_material_region",
             "young");
  EXPECT_ERR(nd_problem_set_material_region(p, 5, 1, 0, NAN), ND_ERR_MATERIAL, "nd_problem_set_material_region",
             "density");
  /* a region's material does not give the default one */
  EXPECT_OK(nd_problem_set_material_region(p, 5, 2, 0, 3));
  EXPECT_ERR(nd_problem_setup(p), ND_ERR_INCOMPLETE, "nd_problem_setup", "nd_problem_set_material");
  EXPECT_OK(nd_problem_destroy(&p));

  p = problem_2d(); /* 2D: Poisson's ratio is checked as nd_problem_set_material does */
  EXPECT_ERR(nd_problem_set_material_region(p, 1, 1, 0.5, 1), ND_ERR_MATERIAL, "nd_problem_set_material_region",
             "poisson");
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_nitsche_timestep) {
  nd_problem p = problem_1d();
  EXPECT_OK(nd_problem_set_nitsche(p, 1, 0)); /* automatic */
  EXPECT_ERR(nd_problem_set_nitsche(p, 1, -0.2), ND_ERR_NITSCHE, "nd_problem_set_nitsche",
             "gamma0");
  EXPECT_ERR(nd_problem_set_nitsche(p, 1, NAN), ND_ERR_NITSCHE, "nd_problem_set_nitsche",
             "gamma0");
  EXPECT_ERR(nd_problem_set_nitsche(p, 1, INFINITY), ND_ERR_NITSCHE, "nd_problem_set_nitsche",
             "gamma0");
  EXPECT_ERR(nd_problem_set_nitsche(p, NAN, 0.2), ND_ERR_NITSCHE, "nd_problem_set_nitsche",
             "theta");
  EXPECT_ERR(nd_problem_set_nitsche(p, -INFINITY, 0.2), ND_ERR_NITSCHE,
             "nd_problem_set_nitsche", "theta");
  const double thetas[] = {-3, -1, 0, 0.5, 1, 7};
  for (size_t i = 0; i < sizeof thetas / sizeof *thetas; ++i)
    EXPECT_OK(nd_problem_set_nitsche(p, thetas[i], 0.2));

  EXPECT_ERR(nd_problem_set_timestep(p, 0), ND_ERR_TIMESTEP, "nd_problem_set_timestep", "tau");
  EXPECT_ERR(nd_problem_set_timestep(p, -0.1), ND_ERR_TIMESTEP, "nd_problem_set_timestep",
             "tau");
  EXPECT_ERR(nd_problem_set_timestep(p, NAN), ND_ERR_TIMESTEP, "nd_problem_set_timestep",
             "tau");
  EXPECT_ERR(nd_problem_set_timestep(p, INFINITY), ND_ERR_TIMESTEP, "nd_problem_set_timestep",
             "tau");
  EXPECT_OK(nd_problem_set_timestep(p, 1e-3));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_scheme) {
  nd_problem p = problem_1d();
  const double half = 0.5;
  EXPECT_ERR(nd_problem_set_scheme(p, 0, &half), ND_ERR_SCHEME, "nd_problem_set_scheme",
             "scheme");
  EXPECT_ERR(nd_problem_set_scheme(p, 5, &half), ND_ERR_SCHEME, "nd_problem_set_scheme",
             "scheme");
  EXPECT_ERR(nd_problem_set_scheme(p, 99, &half), ND_ERR_SCHEME, "nd_problem_set_scheme",
             "scheme");
  EXPECT_ERR(nd_problem_set_scheme(p, -1, NULL), ND_ERR_SCHEME, "nd_problem_set_scheme",
             "scheme");

  /* theta scheme: theta in [0, 1] */
  const double th_bad[] = {-0.1, 1.1, NAN, INFINITY};
  for (size_t i = 0; i < sizeof th_bad / sizeof *th_bad; ++i)
    EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_THETA, &th_bad[i]), ND_ERR_SCHEME,
               "nd_problem_set_scheme", "theta");
  const double th_ok[] = {0, 0.5, 1};
  for (size_t i = 0; i < sizeof th_ok / sizeof *th_ok; ++i)
    EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_THETA, &th_ok[i]));
  EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_THETA, NULL), ND_ERR_NULL,
             "nd_problem_set_scheme", "params");

  /* Newmark: beta in [0, 1/2], gamma in [0, 1] */
  const double nm_bad_beta[][2] = {{-0.1, 0.5}, {0.6, 0.5}, {NAN, 0.5}};
  for (size_t i = 0; i < 3; ++i)
    EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm_bad_beta[i]), ND_ERR_SCHEME,
               "nd_problem_set_scheme", "beta");
  const double nm_bad_gamma[][2] = {{0.25, -0.1}, {0.25, 1.1}, {0.25, NAN}};
  for (size_t i = 0; i < 3; ++i)
    EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm_bad_gamma[i]), ND_ERR_SCHEME,
               "nd_problem_set_scheme", "gamma");
  const double nm_ok[][2] = {{0, 0}, {0, 1}, {0.5, 0}, {0.5, 1}, {0.25, 0.5}};
  for (size_t i = 0; i < 5; ++i)
    EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm_ok[i]));
  EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, NULL), ND_ERR_NULL,
             "nd_problem_set_scheme", "params");

  /* hybrid: no parameter, NULL accepted */
  EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));

  /* generalized-alpha: rho_inf in [0, 1] */
  const double ga_bad[] = {-0.1, 1.1, NAN, INFINITY};
  for (size_t i = 0; i < sizeof ga_bad / sizeof *ga_bad; ++i)
    EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_GENERALIZED_ALPHA, &ga_bad[i]), ND_ERR_SCHEME,
               "nd_problem_set_scheme", "rho_inf");
  const double ga_ok[] = {0, 0.5, 1};
  for (size_t i = 0; i < sizeof ga_ok / sizeof *ga_ok; ++i)
    EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_GENERALIZED_ALPHA, &ga_ok[i]));
  EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_GENERALIZED_ALPHA, NULL), ND_ERR_NULL,
             "nd_problem_set_scheme", "params");
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_regions_and_loads) {
  nd_problem p = problem_1d(); /* regions 1 and 2 */
  const double zero = 0, one = 1, nan = NAN, inf = INFINITY;

  EXPECT_ERR(nd_problem_set_dirichlet(p, 7), ND_ERR_REGION, "nd_problem_set_dirichlet",
             "region 7");
  EXPECT_ERR(nd_problem_set_dirichlet(p, -1), ND_ERR_REGION, "nd_problem_set_dirichlet",
             "region -1");
  EXPECT_ERR(nd_problem_set_neumann(p, 7, &one), ND_ERR_REGION, "nd_problem_set_neumann",
             "region 7");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 7, &zero, &one), ND_ERR_REGION,
             "nd_problem_set_contact_plane", "region 7");

  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, &zero, &zero), ND_ERR_VALUE,
             "nd_problem_set_contact_plane", "normal");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, &nan, &one), ND_ERR_NONFINITE,
             "nd_problem_set_contact_plane", "point");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, &zero, &inf), ND_ERR_NONFINITE,
             "nd_problem_set_contact_plane", "normal");
  EXPECT_ERR(nd_problem_set_body_force(p, &nan), ND_ERR_NONFINITE, "nd_problem_set_body_force",
             "f");
  EXPECT_ERR(nd_problem_set_neumann(p, 1, &inf), ND_ERR_NONFINITE, "nd_problem_set_neumann",
             "g");

  EXPECT_OK(nd_problem_set_dirichlet(p, 2));
  EXPECT_OK(nd_problem_set_neumann(p, 1, &one));
  EXPECT_OK(nd_problem_set_body_force(p, &one));
  EXPECT_OK(nd_problem_set_contact_plane(p, 1, &zero, &one));
  EXPECT_OK(nd_problem_destroy(&p));

  /* the problem keeps its own copy of the mesh: a region added to the mesh
     afterwards is not part of the problem */
  nd_mesh m = interval_with_regions(4);
  p = problem_from(m, 1);
  const int64_t right = 4;
  EXPECT_OK(nd_mesh_set_region(m, 5, 1, &right));
  EXPECT_ERR(nd_problem_set_dirichlet(p, 5), ND_ERR_REGION, "nd_problem_set_dirichlet",
             "region 5");
  EXPECT_OK(nd_mesh_destroy(&m));
  EXPECT_OK(nd_problem_destroy(&p));

  /* 2D */
  p = problem_2d();
  const double pt[2] = {0, 0}, up[2] = {0, 1}, n0[2] = {0, 0}, n_nan[2] = {NAN, 1},
               pt_inf[2] = {0, INFINITY}, f_nan[2] = {0, NAN}, g_inf[2] = {-INFINITY, 0};
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, pt, n0), ND_ERR_VALUE,
             "nd_problem_set_contact_plane", "normal");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, pt, n_nan), ND_ERR_NONFINITE,
             "nd_problem_set_contact_plane", "normal");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, pt_inf, up), ND_ERR_NONFINITE,
             "nd_problem_set_contact_plane", "point");
  EXPECT_ERR(nd_problem_set_contact_plane(p, 3, pt, up), ND_ERR_REGION,
             "nd_problem_set_contact_plane", "region 3");
  EXPECT_ERR(nd_problem_set_body_force(p, f_nan), ND_ERR_NONFINITE, "nd_problem_set_body_force",
             "f");
  EXPECT_ERR(nd_problem_set_neumann(p, 2, g_inf), ND_ERR_NONFINITE, "nd_problem_set_neumann",
             "g");
  EXPECT_ERR(nd_problem_set_neumann(p, 3, up), ND_ERR_REGION, "nd_problem_set_neumann",
             "region 3");
  EXPECT_OK(nd_problem_set_contact_plane(p, 1, pt, up));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* The normal is normalised: its length does not matter as long as it is
   finite and non-zero, also at the ends of the double range.
   Loop test: _i = 0 (normal 1e200), 1 (normal 1e-200), each against normal 1. */
static void contact_bar_displacement(double normal, double *u) {
  const double zero = 0;
  nd_mesh m = interval_with_regions(20);
  nd_problem p = problem_from(m, 1);
  EXPECT_OK(nd_mesh_destroy(&m));
  EXPECT_OK(nd_problem_set_material(p, 1, 0, 1));
  EXPECT_OK(nd_problem_set_dirichlet(p, 2));
  const int st = nd_problem_set_contact_plane(p, 1, &zero, &normal);
  char msg[256];
  snprintf(msg, sizeof msg, "%s", nd_last_error());
  if (st != ND_OK) nd_problem_destroy(&p); /* no leak when the assertion fails */
  ck_assert_msg(st == ND_OK, "normal %g rejected: %d, '%s'", normal, st, msg);
  EXPECT_OK(nd_problem_set_nitsche(p, 1, 0.2));
  EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  EXPECT_OK(nd_problem_set_timestep(p, 0.025));
  double x[21], u0[21];
  EXPECT_OK(nd_problem_get_node_coordinates(p, 21, x));
  for (int i = 0; i < 21; ++i) u0[i] = 0.5 * (1 - x[i]);
  EXPECT_OK(nd_problem_set_initial_state(p, 21, u0, NULL));
  for (int k = 0; k < 60; ++k) EXPECT_OK(nd_step(p)); /* t = 1.5: in contact */
  EXPECT_OK(nd_get_field(p, ND_FIELD_DISPLACEMENT, 21, u));
  EXPECT_OK(nd_problem_destroy(&p));
}

/* the obstacles: sphere, cylinder, distance callback, motion */
static int unit_up(double t, const double *x, double *d, double *nu, void *user) {
  (void)t, (void)user;
  *d = x[1];
  nu[0] = 0, nu[1] = 1;
  return 0;
}

START_TEST(problem_obstacles) {
  const double zero[3] = {0, 0, 0}, c[2] = {0.5, -1}, nan = NAN, inf = INFINITY, ax[3] = {1, 0, 0};
  const double bad[2] = {nan, 0};
  nd_problem p = problem_1d();
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 1, zero, 1, 0), ND_ERR_DIMENSION, "nd_problem_add_contact_sphere",
             "plane");
  EXPECT_ERR(nd_problem_add_contact_distance(p, 1, unit_up, NULL), ND_ERR_DIMENSION,
             "nd_problem_add_contact_distance", "plane");
  EXPECT_OK(nd_problem_destroy(&p));

  p = problem_2d();
  EXPECT_ERR(nd_problem_add_contact_sphere(NULL, 1, c, 1, 0), ND_ERR_NULL, "nd_problem_add_contact_sphere", "p");
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 1, NULL, 1, 0), ND_ERR_NULL, "nd_problem_add_contact_sphere",
             "center");
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 1, bad, 1, 0), ND_ERR_NONFINITE, "nd_problem_add_contact_sphere",
             "center");
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 1, c, inf, 0), ND_ERR_NONFINITE, "nd_problem_add_contact_sphere",
             "radius");
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 1, c, 0, 0), ND_ERR_VALUE, "nd_problem_add_contact_sphere", "radius");
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 1, c, -1, 0), ND_ERR_VALUE, "nd_problem_add_contact_sphere", "radius");
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 1, c, 1, 2), ND_ERR_VALUE, "nd_problem_add_contact_sphere", "inside");
  EXPECT_ERR(nd_problem_add_contact_sphere(p, 7, c, 1, 0), ND_ERR_REGION, "nd_problem_add_contact_sphere",
             "region 7");
  EXPECT_ERR(nd_problem_add_contact_cylinder(p, 1, zero, ax, 1, 0), ND_ERR_DIMENSION,
             "nd_problem_add_contact_cylinder", "3D");
  EXPECT_ERR(nd_problem_add_contact_cylinder(p, 1, NULL, ax, 1, 0), ND_ERR_NULL, "nd_problem_add_contact_cylinder",
             "point");
  EXPECT_ERR(nd_problem_add_contact_cylinder(p, 1, zero, NULL, 1, 0), ND_ERR_NULL,
             "nd_problem_add_contact_cylinder", "axis");
  EXPECT_ERR(nd_problem_add_contact_cylinder(p, 1, zero, ax, nan, 0), ND_ERR_NONFINITE,
             "nd_problem_add_contact_cylinder", "radius");
  EXPECT_ERR(nd_problem_add_contact_cylinder(p, 1, zero, ax, 1, -1), ND_ERR_VALUE,
             "nd_problem_add_contact_cylinder", "inside");
  EXPECT_ERR(nd_problem_add_contact_distance(p, 1, NULL, NULL), ND_ERR_NULL, "nd_problem_add_contact_distance", "f");
  EXPECT_ERR(nd_problem_add_contact_distance(p, 7, unit_up, NULL), ND_ERR_REGION, "nd_problem_add_contact_distance",
             "region 7");
  /* contact pairs: the problem, the regions */
  EXPECT_ERR(nd_problem_set_contact_pair(NULL, 1, 1), ND_ERR_NULL, "nd_problem_set_contact_pair", "p");
  EXPECT_ERR(nd_problem_set_contact_pair(p, 7, 1), ND_ERR_REGION, "nd_problem_set_contact_pair", "region 7");
  EXPECT_ERR(nd_problem_set_contact_pair(p, 1, -1), ND_ERR_REGION, "nd_problem_set_contact_pair", "region -1");
  /* a contact region's scalars */
  double x = 0;
  EXPECT_ERR(nd_get_region_scalar(NULL, 1, ND_CONTACT_FORCE, &x), ND_ERR_NULL, "nd_get_region_scalar", "p");
  EXPECT_ERR(nd_get_region_scalar(p, 1, ND_CONTACT_FORCE, NULL), ND_ERR_NULL, "nd_get_region_scalar", "out");
  EXPECT_ERR(nd_get_region_scalar(p, 1, 999, &x), ND_ERR_KEY, "nd_get_region_scalar", "999");
  /* nothing to move yet */
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, 0, zero, NULL), ND_ERR_INDEX, "nd_problem_move_obstacle", "index 0");
  EXPECT_OK(nd_problem_add_contact_sphere(p, 1, c, 1, 0));
  EXPECT_ERR(nd_problem_move_obstacle(NULL, 1, 0, zero, NULL), ND_ERR_NULL, "nd_problem_move_obstacle", "p");
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, 0, NULL, NULL), ND_ERR_NULL, "nd_problem_move_obstacle", "translation");
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, 0, bad, NULL), ND_ERR_NONFINITE, "nd_problem_move_obstacle",
             "translation");
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, 1, zero, NULL), ND_ERR_INDEX, "nd_problem_move_obstacle", "index 1");
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, -1, zero, NULL), ND_ERR_INDEX, "nd_problem_move_obstacle", "index -1");
  EXPECT_ERR(nd_problem_move_obstacle(p, 2, 0, zero, NULL), ND_ERR_INDEX, "nd_problem_move_obstacle", "region 2");
  const double shear[4] = {1, 0.5, 0, 1}, mirror[4] = {1, 0, 0, -1}, rnan[4] = {1, 0, nan, 1};
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, 0, zero, shear), ND_ERR_VALUE, "nd_problem_move_obstacle", "rotation");
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, 0, zero, mirror), ND_ERR_VALUE, "nd_problem_move_obstacle", "rotation");
  EXPECT_ERR(nd_problem_move_obstacle(p, 1, 0, zero, rnan), ND_ERR_NONFINITE, "nd_problem_move_obstacle",
             "rotation");
  const double quarter[4] = {0, -1, 1, 0};
  EXPECT_OK(nd_problem_move_obstacle(p, 1, 0, zero, quarter));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_friction) {
  const double F = 0.3, neg = -0.1, nan = NAN, inf = INFINITY;
  nd_problem p = problem_1d();
  EXPECT_ERR(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F), ND_ERR_DIMENSION, "nd_problem_set_friction",
             "1D");
  EXPECT_OK(nd_problem_set_friction(p, 1, ND_FRICTION_NONE, NULL));  /* (frictionless: any dimension) */
  EXPECT_OK(nd_problem_destroy(&p));
  p = problem_2d();
  EXPECT_ERR(nd_problem_set_friction(NULL, 1, ND_FRICTION_COULOMB, &F), ND_ERR_NULL, "nd_problem_set_friction", "p");
  EXPECT_ERR(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, NULL), ND_ERR_NULL, "nd_problem_set_friction",
             "params");
  EXPECT_ERR(nd_problem_set_friction(p, 1, ND_FRICTION_TRESCA, NULL), ND_ERR_NULL, "nd_problem_set_friction",
             "params");
  EXPECT_ERR(nd_problem_set_friction(p, 1, 3, &F), ND_ERR_KEY, "nd_problem_set_friction", "law 3");
  EXPECT_ERR(nd_problem_set_friction(p, 1, -1, &F), ND_ERR_KEY, "nd_problem_set_friction", "law -1");
  EXPECT_ERR(nd_problem_set_friction(p, 7, ND_FRICTION_COULOMB, &F), ND_ERR_REGION, "nd_problem_set_friction",
             "region 7");
  EXPECT_ERR(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &neg), ND_ERR_VALUE, "nd_problem_set_friction",
             "coefficient F");
  EXPECT_ERR(nd_problem_set_friction(p, 1, ND_FRICTION_TRESCA, &nan), ND_ERR_NONFINITE, "nd_problem_set_friction",
             "threshold s");
  EXPECT_ERR(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &inf), ND_ERR_NONFINITE, "nd_problem_set_friction",
             "coefficient F");
  EXPECT_OK(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
  EXPECT_OK(nd_problem_set_friction(p, 1, ND_FRICTION_NONE, NULL));
  EXPECT_OK(nd_problem_destroy(&p));
  /* friction needs its region's plane alone, which may move (docs/design.md
     §10.2): a circle on the region refuses the step, and a moving plane steps */
  p = problem_2d();
  const double theta = 1, point[2] = {0, -0.01}, up[2] = {0, 1}, centre[2] = {0.5, -100};
  EXPECT_OK(nd_problem_set_material(p, 100, 0.3, 1));
  EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_THETA, &theta));
  EXPECT_OK(nd_problem_set_timestep(p, 1e-2));
  EXPECT_OK(nd_problem_set_contact_plane(p, 1, point, up));
  EXPECT_OK(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
  EXPECT_OK(nd_problem_add_contact_sphere(p, 1, centre, 99.99, 0));
  EXPECT_ERR(nd_step(p), ND_ERR_STATE, "nd_step", "sphere, cylinder or distance");
  EXPECT_OK(nd_problem_set_friction(p, 1, ND_FRICTION_NONE, NULL));
  EXPECT_OK(nd_step(p));
  EXPECT_OK(nd_problem_destroy(&p));
  p = problem_2d();
  EXPECT_OK(nd_problem_set_material(p, 100, 0.3, 1));
  EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_THETA, &theta));
  EXPECT_OK(nd_problem_set_timestep(p, 1e-2));
  EXPECT_OK(nd_problem_set_contact_plane(p, 1, point, up));
  EXPECT_OK(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
  EXPECT_OK(nd_step(p));
  const double moved[2] = {0.01, -0.005};
  EXPECT_OK(nd_problem_set_contact_plane(p, 1, moved, up));
  EXPECT_OK(nd_step(p));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_contact_normal_scale) {
  const double normal = _i == 0 ? 1e200 : 1e-200;
  double u_ref[21], u[21];
  contact_bar_displacement(1.0, u_ref);
  contact_bar_displacement(normal, u);
  for (int i = 0; i < 21; ++i)
    ck_assert_msg(fabs(u[i] - u_ref[i]) <= 1e-12, "normal %g: u[%d] = %g, expected %g", normal,
                  i, u[i], u_ref[i]);
}
END_TEST

START_TEST(problem_newton_solver) {
  nd_problem p = problem_1d();
  EXPECT_ERR(nd_problem_set_newton(p, -1e-8, 0, 50), ND_ERR_VALUE, "nd_problem_set_newton",
             "rtol");
  EXPECT_ERR(nd_problem_set_newton(p, NAN, 0, 50), ND_ERR_VALUE, "nd_problem_set_newton",
             "rtol");
  EXPECT_ERR(nd_problem_set_newton(p, INFINITY, 0, 50), ND_ERR_VALUE, "nd_problem_set_newton",
             "rtol");
  EXPECT_ERR(nd_problem_set_newton(p, 1e-8, -1, 50), ND_ERR_VALUE, "nd_problem_set_newton",
             "atol");
  EXPECT_ERR(nd_problem_set_newton(p, 1e-8, NAN, 50), ND_ERR_VALUE, "nd_problem_set_newton",
             "atol");
  EXPECT_ERR(nd_problem_set_newton(p, 1e-8, 0, 0), ND_ERR_VALUE, "nd_problem_set_newton",
             "max_iter");
  EXPECT_ERR(nd_problem_set_newton(p, 1e-8, 0, -5), ND_ERR_VALUE, "nd_problem_set_newton",
             "max_iter");
  EXPECT_OK(nd_problem_set_newton(p, 0, 0, 1));

  EXPECT_ERR(nd_problem_set_linear_solver(p, past_the_last_solver()), ND_ERR_KEY,
             "nd_problem_set_linear_solver", "solver");
  EXPECT_ERR(nd_problem_set_linear_solver(p, -1), ND_ERR_KEY, "nd_problem_set_linear_solver",
             "solver");
  EXPECT_OK(nd_problem_set_linear_solver(p, ND_SOLVER_AUTO));
  EXPECT_OK(nd_problem_set_linear_solver(p, ND_SOLVER_DENSE));
  EXPECT_OK(nd_problem_set_linear_solver(p, ND_SOLVER_BANDED));
  EXPECT_OK(nd_problem_set_linear_solver(p, ND_SOLVER_CHOLMOD));
  EXPECT_OK(nd_problem_set_linear_solver(p, ND_SOLVER_UMFPACK));
  EXPECT_OK(nd_problem_set_linear_solver(p, ND_SOLVER_KLU));
  EXPECT_OK(nd_problem_set_mass_lumping(p, 1));
  EXPECT_OK(nd_problem_set_mass_lumping(p, 0));
  /* a build without PETSc has no MPI: the communicator is refused as the
     PETSc solvers are, with the same code, and the problem stays serial
     (builds with PETSc: tests/test_mpi.c) */
  if (nd_problem_set_linear_solver(p, ND_SOLVER_PETSC_MUMPS) == ND_ERR_KEY)
    EXPECT_ERR(nd_problem_set_comm_f(p, 0), ND_ERR_KEY, "nd_problem_set_comm_f", "ND_WITH_PETSC");
  EXPECT_OK(nd_problem_set_linear_solver(p, ND_SOLVER_AUTO));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* ======================================================================== */
/* stepping and getters                                                      */
/* ======================================================================== */

START_TEST(step_array_lengths) {
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  const int64_t n = node_count(p), nq = contact_count(p);
  ck_assert_int_eq(n, 21);
  double *a = calloc((size_t)(n + 1), sizeof(double));
  double *b = calloc((size_t)(n + 1), sizeof(double));
  double *q = calloc((size_t)(nq + 1), sizeof(double));
  double *w = calloc((size_t)(nq + 1), sizeof(double));
  ck_assert_ptr_nonnull(a);
  ck_assert_ptr_nonnull(b);
  ck_assert_ptr_nonnull(q);
  ck_assert_ptr_nonnull(w);

  EXPECT_ERR(nd_problem_set_initial_state(p, n - 1, a, b), ND_ERR_SIZE,
             "nd_problem_set_initial_state", NULL);
  EXPECT_ERR(nd_problem_set_initial_state(p, n + 1, a, b), ND_ERR_SIZE,
             "nd_problem_set_initial_state", NULL);
  EXPECT_ERR(nd_problem_set_initial_state(p, 0, NULL, NULL), ND_ERR_SIZE,
             "nd_problem_set_initial_state", NULL);
  EXPECT_ERR(nd_problem_set_nodal_forces(p, n - 1, a), ND_ERR_SIZE,
             "nd_problem_set_nodal_forces", NULL);
  EXPECT_ERR(nd_problem_set_nodal_forces(p, -1, a), ND_ERR_SIZE, "nd_problem_set_nodal_forces",
             NULL);
  EXPECT_ERR(nd_problem_get_node_coordinates(p, n + 1, a), ND_ERR_SIZE,
             "nd_problem_get_node_coordinates", NULL);
  EXPECT_ERR(nd_problem_get_node_coordinates(p, n - 1, a), ND_ERR_SIZE,
             "nd_problem_get_node_coordinates", NULL);
  for (int field = ND_FIELD_DISPLACEMENT; field <= ND_FIELD_REACTION; ++field) {
    EXPECT_ERR(nd_get_field(p, field, n - 1, a), ND_ERR_SIZE, "nd_get_field", NULL);
    EXPECT_ERR(nd_get_field(p, field, n + 1, a), ND_ERR_SIZE, "nd_get_field", NULL);
    EXPECT_OK(nd_get_field(p, field, n, a));
    EXPECT_ERR(nd_get_field_gathered(p, field, 0, n + 1, a), ND_ERR_SIZE, "nd_get_field_gathered", NULL);
    EXPECT_ERR(nd_get_field_gathered(p, field, 1, n, a), ND_ERR_VALUE, "nd_get_field_gathered", NULL);
    EXPECT_OK(nd_get_field_gathered(p, field, 0, n, b));
    ck_assert_msg(memcmp(a, b, sizeof(double) * (size_t)n) == 0, "field %d: gathered on rank 0 of 1 is not nd_get_field's",
                  field);
  }
  EXPECT_ERR(nd_get_contact_pressure(p, nq + 1, q), ND_ERR_SIZE, "nd_get_contact_pressure",
             NULL);
  EXPECT_ERR(nd_get_contact_pressure(p, nq - 1, q), ND_ERR_SIZE, "nd_get_contact_pressure",
             NULL);
  EXPECT_ERR(nd_problem_get_contact_points(p, nq + 1, q, w), ND_ERR_SIZE,
             "nd_problem_get_contact_points", NULL);
  EXPECT_ERR(nd_problem_get_contact_points(p, nq - 1, q, w), ND_ERR_SIZE,
             "nd_problem_get_contact_points", NULL);
  EXPECT_OK(nd_get_contact_pressure(p, nq, q));
  EXPECT_OK(nd_problem_get_contact_points(p, nq, q, w));

  /* non-finite values in the arrays */
  for (int64_t i = 0; i < n; ++i) a[i] = b[i] = 0;
  a[n - 1] = NAN;
  EXPECT_ERR(nd_problem_set_initial_state(p, n, a, b), ND_ERR_NONFINITE,
             "nd_problem_set_initial_state", "u0");
  EXPECT_ERR(nd_problem_set_nodal_forces(p, n, a), ND_ERR_NONFINITE,
             "nd_problem_set_nodal_forces", "f");
  a[n - 1] = 0;
  b[3] = INFINITY;
  EXPECT_ERR(nd_problem_set_initial_state(p, n, a, b), ND_ERR_NONFINITE,
             "nd_problem_set_initial_state", "v0");
  EXPECT_ERR(nd_problem_set_nodal_forces(p, n, b), ND_ERR_NONFINITE,
             "nd_problem_set_nodal_forces", "f");
  b[3] = 0;
  EXPECT_OK(nd_problem_set_nodal_forces(p, n, b));

  free(a);
  free(b);
  free(q);
  free(w);
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(problem_guards) {
  nd_problem p = problem_1d();
  EXPECT_ERR(nd_problem_set_guard(NULL, ND_GUARD_ENERGY, 2), ND_ERR_NULL, "nd_problem_set_guard", "problem");
  EXPECT_ERR(nd_problem_set_guard(p, 0, 1), ND_ERR_KEY, "nd_problem_set_guard", "guard 0");
  /* (7 is ND_GUARD_ENERGY_BALANCE since issue 57: 8 is the first unknown) */
  EXPECT_ERR(nd_problem_set_guard(p, 8, 1), ND_ERR_KEY, "nd_problem_set_guard", "guard 8");
  EXPECT_ERR(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, -0.1), ND_ERR_VALUE, "nd_problem_set_guard", "0 (off)");
  EXPECT_ERR(nd_problem_set_guard(p, ND_GUARD_ENERGY, 0.5), ND_ERR_VALUE, "nd_problem_set_guard", ">= 1");
  EXPECT_ERR(nd_problem_set_guard(p, ND_GUARD_ENERGY, NAN), ND_ERR_VALUE, "nd_problem_set_guard", "0 (off)");
  EXPECT_ERR(nd_problem_set_guard(p, ND_GUARD_PENETRATION, -1), ND_ERR_VALUE, "nd_problem_set_guard", "0 (off)");
  EXPECT_ERR(nd_problem_set_guard(p, ND_GUARD_PENETRATION, INFINITY), ND_ERR_VALUE, "nd_problem_set_guard",
             "finite");
#define ND_CHECK_GUARD_(name, value, text) \
  EXPECT_OK(nd_problem_set_guard(p, name, 0)); \
  EXPECT_OK(nd_problem_set_guard(p, name, 3));
  ND_GUARD_LIST(ND_CHECK_GUARD_)
#undef ND_CHECK_GUARD_
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* a density and a stiffness whose operators the assembly accepts, but K/M
   out of the doubles' range (fuzz_api: density 1e-308 on a thin rectangle):
   the critical step is refused as the assembly refuses operators that
   overflow, not reported as the library's failure */
START_TEST(critical_step_out_of_range) {
  const double cases[2][2] = {{1e300, 1e-150}, {1e-300, 1e150}}; /* young, density */
  const char *words[2] = {"overflows", "too small"};
  for (int k = 0; k < 2; ++k) {
    nd_problem p = problem_2d();
    EXPECT_OK(nd_problem_set_material(p, cases[k][0], 0.25, cases[k][1]));
    double tau_c = -1;
    EXPECT_ERR(nd_problem_estimate_critical_timestep(p, &tau_c), ND_ERR_MATERIAL,
               "nd_problem_estimate_critical_timestep", words[k]);
    ck_assert_double_eq(tau_c, -1); /* (not written) */
    EXPECT_OK(nd_problem_set_material(p, 1.0, 0.25, 1.0));
    EXPECT_OK(nd_problem_estimate_critical_timestep(p, &tau_c));
    ck_assert(tau_c > 0 && isfinite(tau_c));
    EXPECT_OK(nd_problem_destroy(&p));
  }
}
END_TEST

START_TEST(step_unknown_keys) {
  nd_problem p = nd_test_bar(4, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  double u[5], x = 0;
  EXPECT_ERR(nd_get_field(p, 0, 5, u), ND_ERR_KEY, "nd_get_field", "field");
  EXPECT_ERR(nd_get_field(p, 1000, 5, u), ND_ERR_KEY, "nd_get_field", "field");
  EXPECT_ERR(nd_get_field(p, -1, 5, u), ND_ERR_KEY, "nd_get_field", "field");
  EXPECT_ERR(nd_get_scalar(p, 0, &x), ND_ERR_KEY, "nd_get_scalar", "key");
  EXPECT_ERR(nd_get_scalar(p, 1000, &x), ND_ERR_KEY, "nd_get_scalar", "key");
  EXPECT_ERR(nd_get_scalar(p, -3, &x), ND_ERR_KEY, "nd_get_scalar", "key");
#define ND_CHECK_KEY_(name, value, text) EXPECT_OK(nd_get_scalar(p, name, &x));
  ND_SCALAR_LIST(ND_CHECK_KEY_)
#undef ND_CHECK_KEY_
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* A problem with everything but what `omit` names:
   'm' material, 't' time step, 's' scheme, 'n' Nitsche parameters. */
static nd_problem partial_bar(char omit) {
  nd_mesh m = interval_with_regions(4);
  nd_problem p = problem_from(m, 1);
  const double zero = 0, up = 1;
  EXPECT_OK(nd_mesh_destroy(&m));
  if (omit != 'm') EXPECT_OK(nd_problem_set_material(p, 1, 0, 1));
  EXPECT_OK(nd_problem_set_dirichlet(p, 2));
  EXPECT_OK(nd_problem_set_contact_plane(p, 1, &zero, &up));
  if (omit != 'n') EXPECT_OK(nd_problem_set_nitsche(p, 1, 0.2));
  if (omit != 's') EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  if (omit != 't') EXPECT_OK(nd_problem_set_timestep(p, 0.025));
  return p;
}

/* Operators out and contact on the host's operators: every argument checked,
   nothing changed by a refused call (the checkpoint is the same). */
START_TEST(host_calls_bad_arguments) {
  nd_problem p = nd_test_bar(4, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  int64_t n = 0, nnz = 0, ptr[8], col[64], node[4], nc = 0, cells[16], before_size = 0, after_size = 0;
  int comp[4], npc = 0;
  double val[64], u[4] = {0, 0, 0, 0}, r[4], f[4], values[4];
  EXPECT_OK(nd_step(p));
  unsigned char *before = nd_test_checkpoint(p, &before_size);
  EXPECT_ERR(nd_problem_get_matrix(NULL, ND_MATRIX_MASS, &n, &nnz, NULL, NULL, NULL), ND_ERR_NULL,
             "nd_problem_get_matrix", "problem");
  EXPECT_ERR(nd_problem_get_matrix(p, 0, &n, &nnz, NULL, NULL, NULL), ND_ERR_KEY, "nd_problem_get_matrix", "which 0");
  EXPECT_ERR(nd_problem_get_matrix(p, 7, &n, &nnz, NULL, NULL, NULL), ND_ERR_KEY, "nd_problem_get_matrix", "which 7");
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_MASS, NULL, &nnz, NULL, NULL, NULL), ND_ERR_NULL,
             "nd_problem_get_matrix", "n is NULL");
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, NULL, NULL, NULL, NULL), ND_ERR_NULL,
             "nd_problem_get_matrix", "nnz is NULL");
  EXPECT_OK(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, &nnz, NULL, NULL, NULL));
  ck_assert_int_eq(n, 4); /* the bar's 5 nodes, x = 1 clamped */
  ck_assert(nnz <= 64);
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, &nnz, ptr, NULL, val), ND_ERR_NULL,
             "nd_problem_get_matrix", "col_idx");
  int64_t wrong = nnz - 1;
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, &wrong, ptr, col, val), ND_ERR_SIZE,
             "nd_problem_get_matrix", "nnz");
  wrong = n + 1;
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_MASS, &wrong, &nnz, ptr, col, val), ND_ERR_SIZE,
             "nd_problem_get_matrix", "rows");
  EXPECT_OK(nd_problem_get_matrix(p, ND_MATRIX_STEP, &n, &nnz, ptr, col, val));
  EXPECT_ERR(nd_problem_get_dof_map(p, 5, node, comp), ND_ERR_SIZE, "nd_problem_get_dof_map", "expected 4");
  EXPECT_OK(nd_problem_get_dof_map(p, 4, node, NULL));
  EXPECT_ERR(nd_problem_get_load(p, 3, f), ND_ERR_SIZE, "nd_problem_get_load", "expected 4");
  EXPECT_ERR(nd_problem_get_load(p, 4, NULL), ND_ERR_NULL, "nd_problem_get_load", "f");
  EXPECT_ERR(nd_problem_get_cells(p, NULL, &npc, NULL), ND_ERR_NULL, "nd_problem_get_cells", "n_cells");
  EXPECT_ERR(nd_problem_get_cells(p, &nc, NULL, NULL), ND_ERR_NULL, "nd_problem_get_cells", "nodes_per_cell");
  EXPECT_OK(nd_problem_get_cells(p, &nc, &npc, NULL));
  ck_assert_int_eq(nc, 4);
  ck_assert_int_eq(npc, 2);
  nc = 3;
  EXPECT_ERR(nd_problem_get_cells(p, &nc, &npc, cells), ND_ERR_SIZE, "nd_problem_get_cells", "n_cells");
  EXPECT_ERR(nd_problem_contact_residual(p, 5, u, r), ND_ERR_SIZE, "nd_problem_contact_residual", "expected 4");
  EXPECT_ERR(nd_problem_contact_residual(p, 4, NULL, r), ND_ERR_NULL, "nd_problem_contact_residual", "u");
  EXPECT_ERR(nd_problem_contact_residual(p, 4, u, NULL), ND_ERR_NULL, "nd_problem_contact_residual", "r");
  u[2] = NAN;
  EXPECT_ERR(nd_problem_contact_residual(p, 4, u, r), ND_ERR_NONFINITE, "nd_problem_contact_residual", "u[2]");
  EXPECT_ERR(nd_problem_contact_tangent(p, 4, u, &nnz, ptr, col, val), ND_ERR_NONFINITE,
             "nd_problem_contact_tangent", "u[2]");
  EXPECT_ERR(nd_problem_contact_values(p, 4, u, 4, values), ND_ERR_NONFINITE, "nd_problem_contact_values", "u[2]");
  u[2] = INFINITY;
  EXPECT_ERR(nd_problem_contact_values(p, 4, u, 4, values), ND_ERR_NONFINITE, "nd_problem_contact_values", "u[2]");
  u[2] = 0;
  EXPECT_ERR(nd_problem_contact_tangent(p, 3, NULL, &nnz, NULL, NULL, NULL), ND_ERR_SIZE,
             "nd_problem_contact_tangent", "expected 4");
  EXPECT_ERR(nd_problem_contact_tangent(p, 4, u, NULL, NULL, NULL, NULL), ND_ERR_NULL, "nd_problem_contact_tangent",
             "nnz");
  EXPECT_OK(nd_problem_contact_tangent(p, 4, NULL, &nnz, NULL, NULL, NULL));
  EXPECT_ERR(nd_problem_contact_tangent(p, 4, NULL, &nnz, ptr, col, val), ND_ERR_NULL, "nd_problem_contact_tangent",
             "u is NULL");
  EXPECT_ERR(nd_problem_contact_tangent(p, 4, u, &nnz, ptr, col, NULL), ND_ERR_NULL, "nd_problem_contact_tangent",
             "values");
  EXPECT_OK(nd_problem_contact_tangent(p, 4, u, &nnz, ptr, col, val));
  EXPECT_ERR(nd_problem_contact_values(p, 4, u, 0, values), ND_ERR_SIZE, "nd_problem_contact_values", "nvalues");
  EXPECT_ERR(nd_problem_contact_values(p, 4, u, 5, values), ND_ERR_SIZE, "nd_problem_contact_values", "nvalues");
  EXPECT_ERR(nd_problem_contact_values(p, 4, u, 2, NULL), ND_ERR_NULL, "nd_problem_contact_values", "values");
  EXPECT_OK(nd_problem_contact_values(p, 4, u, 1, values));
  /* the step form: u_old checked as u, the size query reading neither */
  double un[4] = {0, 0, 0, 0};
  EXPECT_ERR(nd_problem_contact_step_residual(p, 5, u, un, r), ND_ERR_SIZE, "nd_problem_contact_step_residual",
             "expected 4");
  EXPECT_ERR(nd_problem_contact_step_residual(p, 4, NULL, un, r), ND_ERR_NULL, "nd_problem_contact_step_residual",
             "u is NULL");
  EXPECT_ERR(nd_problem_contact_step_residual(p, 4, u, NULL, r), ND_ERR_NULL, "nd_problem_contact_step_residual",
             "u_old");
  EXPECT_ERR(nd_problem_contact_step_residual(p, 4, u, un, NULL), ND_ERR_NULL, "nd_problem_contact_step_residual",
             "r");
  un[1] = NAN;
  EXPECT_ERR(nd_problem_contact_step_residual(p, 4, u, un, r), ND_ERR_NONFINITE, "nd_problem_contact_step_residual",
             "u_old[1]");
  EXPECT_ERR(nd_problem_contact_step_tangent(p, 4, u, un, &nnz, ptr, col, val), ND_ERR_NONFINITE,
             "nd_problem_contact_step_tangent", "u_old[1]");
  un[1] = 0;
  EXPECT_ERR(nd_problem_contact_step_tangent(p, 3, NULL, NULL, &nnz, NULL, NULL, NULL), ND_ERR_SIZE,
             "nd_problem_contact_step_tangent", "expected 4");
  EXPECT_ERR(nd_problem_contact_step_tangent(p, 4, u, un, NULL, NULL, NULL, NULL), ND_ERR_NULL,
             "nd_problem_contact_step_tangent", "nnz");
  EXPECT_OK(nd_problem_contact_step_tangent(p, 4, NULL, NULL, &nnz, NULL, NULL, NULL));
  EXPECT_ERR(nd_problem_contact_step_tangent(p, 4, u, NULL, &nnz, ptr, col, val), ND_ERR_NULL,
             "nd_problem_contact_step_tangent", "u_old");
  EXPECT_ERR(nd_problem_contact_step_tangent(p, 4, u, un, &nnz, ptr, NULL, val), ND_ERR_NULL,
             "nd_problem_contact_step_tangent", "col_idx");
  EXPECT_OK(nd_problem_contact_step_tangent(p, 4, u, un, &nnz, ptr, col, val));
  EXPECT_OK(nd_problem_contact_step_residual(p, 4, u, un, r));
  unsigned char *after = nd_test_checkpoint(p, &after_size);
  ck_assert_int_eq(before_size, after_size);
  ck_assert(memcmp(before, after, (size_t)before_size) == 0);
  free(before), free(after);
  /* the step matrix: not for an explicit scheme */
  const double zero = 0;
  EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_THETA, &zero));
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_STEP, &n, &nnz, NULL, NULL, NULL), ND_ERR_STATE,
             "nd_problem_get_matrix", "explicit");
  EXPECT_OK(nd_problem_get_matrix(p, ND_MATRIX_LUMPED_MASS, &n, &nnz, NULL, NULL, NULL));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* ... nor for an incomplete problem, whose operators need the material */
START_TEST(host_calls_incomplete) {
  nd_problem p = partial_bar('s');
  int64_t n = 0, nnz = 0;
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_STEP, &n, &nnz, NULL, NULL, NULL), ND_ERR_INCOMPLETE,
             "nd_problem_get_matrix", "scheme");
  EXPECT_OK(nd_problem_get_matrix(p, ND_MATRIX_STIFFNESS, &n, &nnz, NULL, NULL, NULL));
  { /* the step form needs the scheme's rule; the at-end form does not */
    double u[4] = {0, 0, 0, 0}, r[4];
    EXPECT_ERR(nd_problem_contact_step_residual(p, 4, u, u, r), ND_ERR_INCOMPLETE,
               "nd_problem_contact_step_residual", "scheme");
    EXPECT_OK(nd_problem_contact_residual(p, 4, u, r));
  }
  EXPECT_OK(nd_problem_destroy(&p));
  p = partial_bar('m');
  EXPECT_ERR(nd_problem_get_matrix(p, ND_MATRIX_MASS, &n, &nnz, NULL, NULL, NULL), ND_ERR_INCOMPLETE,
             "nd_problem_get_matrix", "material");
  double u[4] = {0, 0, 0, 0}, r[4];
  EXPECT_ERR(nd_problem_contact_residual(p, 4, u, r), ND_ERR_INCOMPLETE, "nd_problem_contact_residual", "material");
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(step_incomplete) {
  nd_problem p = partial_bar('m');
  EXPECT_ERR(nd_problem_setup(p), ND_ERR_INCOMPLETE, "nd_problem_setup", "material");
  EXPECT_ERR(nd_step(p), ND_ERR_INCOMPLETE, "nd_step", "material");
  ck_assert(!contains(nd_last_error(), "time step"));
  ck_assert(!contains(nd_last_error(), "Nitsche"));
  /* completing the problem makes it step */
  EXPECT_OK(nd_problem_set_material(p, 1, 0, 1));
  EXPECT_OK(nd_step(p));
  ck_assert_double_eq(scalar(p, ND_STEP_INDEX), 1);
  EXPECT_OK(nd_problem_destroy(&p));

  p = partial_bar('t');
  EXPECT_ERR(nd_step(p), ND_ERR_INCOMPLETE, "nd_step", "time step");
  ck_assert(!contains(nd_last_error(), "material"));
  ck_assert(!contains(nd_last_error(), "scheme"));
  EXPECT_OK(nd_problem_set_timestep(p, 0.025));
  EXPECT_OK(nd_step(p));
  EXPECT_OK(nd_problem_destroy(&p));

  p = partial_bar('s');
  EXPECT_ERR(nd_step(p), ND_ERR_INCOMPLETE, "nd_step", "scheme");
  ck_assert(!contains(nd_last_error(), "material"));
  ck_assert(!contains(nd_last_error(), "time step"));
  EXPECT_OK(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  EXPECT_OK(nd_step(p));
  EXPECT_OK(nd_problem_destroy(&p));

  p = partial_bar('n');
  EXPECT_ERR(nd_step(p), ND_ERR_INCOMPLETE, "nd_step", "Nitsche");
  ck_assert(!contains(nd_last_error(), "material"));
  EXPECT_OK(nd_problem_set_nitsche(p, 1, 0.2));
  EXPECT_OK(nd_step(p));
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

START_TEST(step_dirichlet_after_step) {
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  EXPECT_OK(nd_step(p));
  EXPECT_ERR(nd_problem_set_dirichlet(p, 2), ND_ERR_STATE, "nd_problem_set_dirichlet", NULL);
  EXPECT_ERR(nd_problem_set_dirichlet(p, 1), ND_ERR_STATE, "nd_problem_set_dirichlet", NULL);
  ck_assert_double_eq(scalar(p, ND_STEP_INDEX), 1);
  EXPECT_OK(nd_step(p));
  ck_assert_double_eq(scalar(p, ND_STEP_INDEX), 2);
  EXPECT_OK(nd_problem_destroy(&p));
}
END_TEST

/* Every setter called with a bad argument; all must be rejected. */
static void reject_everything(nd_problem p, int started) {
  const int64_t n = node_count(p);
  double *bad = calloc((size_t)n, sizeof(double));
  ck_assert_ptr_nonnull(bad);
  bad[n - 1] = NAN;
  const double zero = 0, nan = NAN, th = 2, nm[2] = {0.25, 1.5};
  double x = 0;

  EXPECT_ERR(nd_problem_set_material(p, -1, 0, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             NULL);
  EXPECT_ERR(nd_problem_set_material(p, 2, 0, NAN), ND_ERR_MATERIAL, "nd_problem_set_material",
             NULL);
  EXPECT_ERR(nd_problem_set_nitsche(p, NAN, 0.1), ND_ERR_NITSCHE, "nd_problem_set_nitsche",
             NULL);
  EXPECT_ERR(nd_problem_set_nitsche(p, 0, -0.1), ND_ERR_NITSCHE, "nd_problem_set_nitsche",
             NULL);
  EXPECT_ERR(nd_problem_set_timestep(p, 0), ND_ERR_TIMESTEP, "nd_problem_set_timestep", NULL);
  EXPECT_ERR(nd_problem_set_scheme(p, 99, NULL), ND_ERR_SCHEME, "nd_problem_set_scheme", NULL);
  EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_THETA, &th), ND_ERR_SCHEME,
             "nd_problem_set_scheme", NULL);
  EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm), ND_ERR_SCHEME,
             "nd_problem_set_scheme", NULL);
  EXPECT_ERR(nd_problem_set_scheme(p, ND_SCHEME_THETA, NULL), ND_ERR_NULL,
             "nd_problem_set_scheme", NULL);
  if (started)
    EXPECT_ERR(nd_problem_set_dirichlet(p, 1), ND_ERR_STATE, "nd_problem_set_dirichlet", NULL);
  EXPECT_ERR(nd_problem_set_dirichlet(p, 7), ND_ERR_REGION, "nd_problem_set_dirichlet", NULL);
  EXPECT_ERR(nd_problem_set_neumann(p, 7, &zero), ND_ERR_REGION, "nd_problem_set_neumann",
             NULL);
  EXPECT_ERR(nd_problem_set_neumann(p, 1, &nan), ND_ERR_NONFINITE, "nd_problem_set_neumann",
             NULL);
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, &zero, &zero), ND_ERR_VALUE,
             "nd_problem_set_contact_plane", NULL);
  EXPECT_ERR(nd_problem_set_contact_plane(p, 1, &nan, &th), ND_ERR_NONFINITE,
             "nd_problem_set_contact_plane", NULL);
  EXPECT_ERR(nd_problem_set_contact_plane(p, 9, &zero, &th), ND_ERR_REGION,
             "nd_problem_set_contact_plane", NULL);
  EXPECT_ERR(nd_problem_set_body_force(p, &nan), ND_ERR_NONFINITE, "nd_problem_set_body_force",
             NULL);
  EXPECT_ERR(nd_problem_set_body_force(p, NULL), ND_ERR_NULL, "nd_problem_set_body_force",
             NULL);
  EXPECT_ERR(nd_problem_set_nodal_forces(p, n - 1, bad), ND_ERR_SIZE,
             "nd_problem_set_nodal_forces", NULL);
  EXPECT_ERR(nd_problem_set_nodal_forces(p, n, bad), ND_ERR_NONFINITE,
             "nd_problem_set_nodal_forces", NULL);
  EXPECT_ERR(nd_problem_set_initial_state(p, n, bad, NULL), ND_ERR_NONFINITE,
             "nd_problem_set_initial_state", NULL);
  EXPECT_ERR(nd_problem_set_initial_state(p, n, NULL, bad), ND_ERR_NONFINITE,
             "nd_problem_set_initial_state", NULL);
  EXPECT_ERR(nd_problem_set_initial_state(p, n + 1, NULL, NULL), ND_ERR_SIZE,
             "nd_problem_set_initial_state", NULL);
  EXPECT_ERR(nd_problem_set_newton(p, -1, 0, 50), ND_ERR_VALUE, "nd_problem_set_newton", NULL);
  EXPECT_ERR(nd_problem_set_newton(p, 1e-10, 0, 0), ND_ERR_VALUE, "nd_problem_set_newton",
             NULL);
  EXPECT_ERR(nd_problem_set_linear_solver(p, 9), ND_ERR_KEY, "nd_problem_set_linear_solver",
             NULL);
  EXPECT_ERR(nd_get_field(p, 9, n, bad), ND_ERR_KEY, "nd_get_field", NULL);
  EXPECT_ERR(nd_get_scalar(p, 99, &x), ND_ERR_KEY, "nd_get_scalar", NULL);
  free(bad);
}

static void run_bar(int with_rejects, double *u, double *v, double *s) {
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  if (with_rejects) reject_everything(p, 0);
  for (int k = 0; k < 40; ++k) {
    EXPECT_OK(nd_step(p));
    if (with_rejects && k == 19) reject_everything(p, 1);
  }
  EXPECT_OK(nd_get_field(p, ND_FIELD_DISPLACEMENT, 21, u));
  EXPECT_OK(nd_get_field(p, ND_FIELD_VELOCITY, 21, v));
  s[0] = scalar(p, ND_TIME);
  s[1] = scalar(p, ND_STEP_INDEX);
  s[2] = scalar(p, ND_ENERGY_AUGMENTED);
  s[3] = scalar(p, ND_WORK);
  s[4] = scalar(p, ND_NEWTON_ITERATIONS_TOTAL);
  s[5] = scalar(p, ND_TIMESTEP);
  EXPECT_OK(nd_problem_destroy(&p));
}

START_TEST(step_rejected_calls_change_nothing) {
  double u_ref[21], v_ref[21], s_ref[6], u[21], v[21], s[6];
  run_bar(0, u_ref, v_ref, s_ref);
  run_bar(1, u, v, s);
  ck_assert_double_eq(s_ref[1], 40);
  ck_assert_msg(memcmp(u, u_ref, sizeof u) == 0, "displacement changed by rejected calls");
  ck_assert_msg(memcmp(v, v_ref, sizeof v) == 0, "velocity changed by rejected calls");
  for (int i = 0; i < 6; ++i)
    ck_assert_msg(memcmp(&s[i], &s_ref[i], sizeof(double)) == 0,
                  "scalar %d changed by rejected calls: %.17g vs %.17g", i, s[i], s_ref[i]);
}
END_TEST

/* Reading the initial state is not a definition call: a body force set after
   a getter must act from t = 0 exactly as when no getter was called. */
static void run_loaded_bar(int peek, double *u, double *work) {
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 0.025);
  const double f = -0.3;
  if (peek) (void)scalar(p, ND_ENERGY_MECHANICAL);
  EXPECT_OK(nd_problem_set_body_force(p, &f));
  for (int k = 0; k < 40; ++k) EXPECT_OK(nd_step(p));
  EXPECT_OK(nd_get_field(p, ND_FIELD_DISPLACEMENT, 21, u));
  *work = scalar(p, ND_WORK);
  EXPECT_OK(nd_problem_destroy(&p));
}

START_TEST(step_getter_has_no_side_effect) {
  double u_ref[21], u[21], w_ref = 0, w = 0;
  run_loaded_bar(0, u_ref, &w_ref);
  run_loaded_bar(1, u, &w);
  for (int i = 0; i < 21; ++i)
    ck_assert_msg(fabs(u[i] - u_ref[i]) <= 1e-13, "u[%d] = %.17g after a getter, %.17g without",
                  i, u[i], u_ref[i]);
  ck_assert_msg(fabs(w - w_ref) <= 1e-13, "work %.17g after a getter, %.17g without", w, w_ref);
}
END_TEST

/* ======================================================================== */
/* status codes and the error message                                        */
/* ======================================================================== */

START_TEST(last_error_cleared_by_success) {
  nd_mesh m = interval_with_regions(4);
  int dim = 0;
  EXPECT_ERR(nd_mesh_get_dimension(m, NULL), ND_ERR_NULL, "nd_mesh_get_dimension", NULL);
  /* reading the message does not clear it */
  ck_assert_str_ne(nd_last_error(), "");
  ck_assert_str_ne(nd_last_error(), "");
  EXPECT_OK(nd_mesh_get_dimension(m, &dim));
  ck_assert_str_eq(nd_last_error(), "");

  nd_problem p = problem_from(m, 1);
  EXPECT_ERR(nd_problem_set_timestep(p, -1), ND_ERR_TIMESTEP, "nd_problem_set_timestep", NULL);
  EXPECT_OK(nd_problem_set_timestep(p, 0.1));
  ck_assert_str_eq(nd_last_error(), "");

  /* a failure of another function replaces the message */
  EXPECT_ERR(nd_problem_set_material(p, -1, 0, 1), ND_ERR_MATERIAL, "nd_problem_set_material",
             NULL);
  EXPECT_ERR(nd_problem_set_nitsche(p, 1, -1), ND_ERR_NITSCHE, "nd_problem_set_nitsche", NULL);
  ck_assert(!contains(nd_last_error(), "nd_problem_set_material"));

  /* destroy and the library functions also clear it */
  int major, minor, patch;
  EXPECT_OK(nd_version(&major, &minor, &patch));
  ck_assert_str_eq(nd_last_error(), "");
  EXPECT_ERR(nd_problem_set_nitsche(p, 1, -1), ND_ERR_NITSCHE, "nd_problem_set_nitsche", NULL);
  EXPECT_OK(nd_problem_destroy(&p));
  ck_assert_str_eq(nd_last_error(), "");
  EXPECT_OK(nd_mesh_destroy(&m));
}
END_TEST

#define ND_STATUS_ENTRY_(name, value, text) {name, value, #name, text},
static const struct {
  int code, value;
  const char *name, *text;
} statuses[] = {ND_STATUS_LIST(ND_STATUS_ENTRY_)};
#undef ND_STATUS_ENTRY_
static const size_t n_statuses = sizeof statuses / sizeof *statuses;

START_TEST(strerror_all_codes) {
  ck_assert_int_ge(n_statuses, 23);
  for (size_t i = 0; i < n_statuses; ++i) {
    ck_assert_int_eq(statuses[i].code, statuses[i].value);
    const char *s = nd_strerror(statuses[i].code);
    ck_assert_msg(s != NULL && s[0] != '\0', "nd_strerror(%s) is empty", statuses[i].name);
    ck_assert_msg(strcmp(s, statuses[i].text) == 0, "nd_strerror(%s) = '%s', header says '%s'",
                  statuses[i].name, s, statuses[i].text);
    /* errors are negative, ND_OK is 0, ND_MONITOR_STOP positive */
    if (strncmp(statuses[i].name, "ND_ERR_", 7) == 0)
      ck_assert_msg(statuses[i].code < 0, "%s is not negative", statuses[i].name);
    for (size_t j = 0; j < i; ++j) {
      ck_assert_msg(statuses[i].code != statuses[j].code, "%s and %s share the value %d",
                    statuses[i].name, statuses[j].name, statuses[i].code);
      ck_assert_msg(strcmp(s, nd_strerror(statuses[j].code)) != 0,
                    "%s and %s share the message '%s'", statuses[i].name, statuses[j].name, s);
    }
  }
  ck_assert_int_eq(ND_OK, 0);
  ck_assert_int_gt(ND_MONITOR_STOP, 0);
  const int unknown[] = {2, 12345, -23 - 1000, -99999, 2147483647, -2147483647 - 1};
  for (size_t i = 0; i < sizeof unknown / sizeof *unknown; ++i) {
    const char *s = nd_strerror(unknown[i]);
    ck_assert_msg(s != NULL && s[0] != '\0', "nd_strerror(%d) is NULL or empty", unknown[i]);
    ck_assert_str_ne(s, nd_strerror(ND_OK));
  }
}
END_TEST

static Suite *api_errors_suite(void) {
  Suite *s = suite_create("api_errors");

  TCase *mesh = tcase_create("mesh");
  tcase_add_test(mesh, mesh_null_arguments);
  tcase_add_test(mesh, mesh_create_dimension_and_sizes);
  tcase_add_test(mesh, mesh_create_cells_errors);
  tcase_add_test(mesh, mesh_create_mixed_errors);
  tcase_add_test(mesh, mesh_create_orphan_vertex);
  tcase_add_test(mesh, mesh_create_indices);
  tcase_add_test(mesh, mesh_create_nonfinite);
  tcase_add_test(mesh, mesh_create_degenerate);
  tcase_add_test(mesh, mesh_create_interval_errors);
  tcase_add_loop_test(mesh, mesh_create_interval_error_names_function, 0, 2);
  tcase_add_test(mesh, mesh_set_region_errors);
  suite_add_tcase(s, mesh);

  TCase *def = tcase_create("problem_definition");
  tcase_add_test(def, problem_null_handles);
  tcase_add_test(def, problem_null_arrays);
  tcase_add_test(def, problem_create_degree);
  tcase_add_test(def, problem_material);
  tcase_add_test(def, cell_regions_and_materials);
  tcase_add_test(def, problem_nitsche_timestep);
  tcase_add_test(def, problem_damping_plane_stress);
  tcase_add_test(def, problem_adaptive_timestep);
  tcase_add_test(def, problem_scheme);
  tcase_add_test(def, problem_regions_and_loads);
  tcase_add_loop_test(def, problem_contact_normal_scale, 0, 2);
  tcase_add_test(def, problem_obstacles);
  tcase_add_test(def, problem_friction);
  tcase_add_test(def, problem_newton_solver);
  tcase_add_test(def, problem_guards);
  tcase_add_test(def, critical_step_out_of_range);
  tcase_add_test(def, problem_prescribed_motion);
  suite_add_tcase(s, def);

  TCase *step = tcase_create("stepping_getters");
  tcase_set_timeout(step, 60);
  tcase_add_test(step, step_array_lengths);
  tcase_add_test(step, step_unknown_keys);
  tcase_add_test(step, step_incomplete);
  tcase_add_test(step, host_calls_bad_arguments);
  tcase_add_test(step, host_calls_incomplete);
  tcase_add_test(step, step_dirichlet_after_step);
  tcase_add_test(step, step_rejected_calls_change_nothing);
  tcase_add_test(step, step_getter_has_no_side_effect);
  suite_add_tcase(s, step);

  TCase *codes = tcase_create("status_codes");
  tcase_add_test(codes, last_error_cleared_by_success);
  tcase_add_test(codes, strerror_all_codes);
  suite_add_tcase(s, codes);
  return s;
}

int main(void) { return nd_test_run(api_errors_suite()); }
