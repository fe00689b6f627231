/* Meshes mixing triangles and quadrilaterals (issue 60, docs/design.md
 * §10.7), P1 with Q1 and P2 with Q2, by identities that hold to round-off:
 *  - the operators are the sums of their cells': K, M and the lumped M of a
 *    mixed mesh equal those of its triangles alone plus its quadrilaterals
 *    alone (two meshes on the same points), DOF by DOF matched by position;
 *  - the rigid motions are in K's kernel; sum M = rho |Omega| dim, the
 *    lumped diagonal too, and positive;
 *  - the patch test on distorted mixed cells: a linear field is in the space
 *    (a P2 triangle and a Q2 quadrilateral share an edge's three nodes), K u
 *    vanishes at the interior nodes and u'Ku = |Omega| sigma:eps;
 *  - the Gmsh reader: examples/meshes/mixed.msh (MSH 4.1), mixed_v2.msh
 *    (2.2) and mixed_o2.msh (6-node triangles, 9-node quadrilaterals) give
 *    the operators of nd_mesh_create_mixed with the file's cells;
 *  - contact: a block of triangles and quadrilaterals dropped on a plane
 *    (also with redistributed mass), and one onto another (a contact pair),
 *    hybrid scheme, Theta = 1: the ledger never rises, step by step;
 *  - the refusals: a 3D mix (arrays and files), prisms and pyramids. */
#include <math.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testutil.h"

typedef nd_test_csr csr;

/* ---- a distorted mixed patch ---------------------------------------------- */

enum { G = 4, NV = G * G, MAX_CELLS = 2 * (G - 1) * (G - 1) };

/* [0,1]^2 in 3 x 3 squares, the interior vertices moved off the grid (the
   boundary stays the square's: |Omega| = 1); the squares with i + j even
   kept whole, the others in two triangles (the diagonal alternating) */
typedef struct {
  double x[2 * NV];
  int64_t n_cells, n_indices;
  int types[MAX_CELLS];
  int64_t cells[4 * MAX_CELLS];
} patch;

static patch mixed_patch(void) {
  patch p;
  p.n_cells = p.n_indices = 0;
  for (int v = 0; v < NV; ++v) {
    const int i = v % G, j = v / G, inside = i > 0 && i < G - 1 && j > 0 && j < G - 1;
    p.x[2 * v] = (double)i / (G - 1) + (inside ? 0.04 * (j - 1.5) + 0.01 * v / NV : 0.0);
    p.x[2 * v + 1] = (double)j / (G - 1) + (inside ? -0.05 * (i - 1.5) + 0.02 : 0.0);
  }
  for (int j = 0; j + 1 < G; ++j)
    for (int i = 0; i + 1 < G; ++i) {
      const int64_t a = i + G * j, b = a + 1, c = a + 1 + G, d = a + G;
      if ((i + j) % 2 == 0) {
        const int64_t q[4] = {a, b, c, d};
        p.types[p.n_cells++] = ND_CELL_QUADRILATERAL;
        memcpy(p.cells + p.n_indices, q, sizeof q), p.n_indices += 4;
      } else {
        const int64_t t[6] = {a, b, c, a, c, d}, s[6] = {a, b, d, b, c, d};
        p.types[p.n_cells++] = ND_CELL_SIMPLEX, p.types[p.n_cells++] = ND_CELL_SIMPLEX;
        memcpy(p.cells + p.n_indices, j % 2 ? t : s, sizeof t), p.n_indices += 6;
      }
    }
  return p;
}

static nd_problem problem_of(nd_mesh m, int degree, double rho) {
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 5.0, 0.3, rho));
  return p;
}

static nd_problem mixed_problem(int degree, double rho) {
  const patch q = mixed_patch();
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_mixed(2, NV, q.x, q.n_cells, q.types, q.cells, &m));
  return problem_of(m, degree, rho);
}

/* the patch's cells of one type alone, on the vertices they use */
static nd_problem part_problem(int type, int degree, double rho) {
  const patch q = mixed_patch();
  int64_t renumber[NV], cells[4 * MAX_CELLS], n = 0, nc = 0, k = 0;
  double x[2 * NV];
  for (int v = 0; v < NV; ++v) renumber[v] = -1;
  for (int64_t c = 0, at = 0; c < q.n_cells; ++c) {
    const int nv = q.types[c] == ND_CELL_SIMPLEX ? 3 : 4;
    if (q.types[c] == type) {
      for (int i = 0; i < nv; ++i) {
        const int64_t v = q.cells[at + i];
        if (renumber[v] < 0) renumber[v] = n, x[2 * n] = q.x[2 * v], x[2 * n + 1] = q.x[2 * v + 1], ++n;
        cells[k++] = renumber[v];
      }
      ++nc;
    }
    at += nv;
  }
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_cells(2, type, n, x, nc, cells, &m));
  return problem_of(m, degree, rho);
}

/* ---- DOFs by position -------------------------------------------------------- */

typedef struct {
  int64_t n;   /* free DOFs */
  double *x;   /* each DOF's node's position (2 values) */
  int *comp;
} dof_places;

static dof_places places_of(nd_problem p) {
  dof_places d;
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *nx = malloc(sizeof(double) * (size_t)(2 * nn));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, nx));
  int64_t nnz = 0;
  ND_OK_OR_FAIL(nd_problem_get_matrix(p, ND_MATRIX_STIFFNESS, &d.n, &nnz, NULL, NULL, NULL));
  int64_t *node = malloc(sizeof(int64_t) * (size_t)d.n);
  d.comp = malloc(sizeof(int) * (size_t)d.n);
  d.x = malloc(sizeof(double) * (size_t)(2 * d.n));
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, d.n, node, d.comp));
  for (int64_t r = 0; r < d.n; ++r) d.x[2 * r] = nx[2 * node[r]], d.x[2 * r + 1] = nx[2 * node[r] + 1];
  free(nx), free(node);
  return d;
}

static void places_free(dof_places *d) { free(d->x), free(d->comp); }

/* the DOF of `in` at the position and component of DOF r of `of` (a check
   fails when there is none) */
static int64_t same_dof(const dof_places *in, const dof_places *of, int64_t r) {
  for (int64_t s = 0; s < in->n; ++s)
    if (in->comp[s] == of->comp[r] && fabs(in->x[2 * s] - of->x[2 * r]) <= 1e-12 &&
        fabs(in->x[2 * s + 1] - of->x[2 * r + 1]) <= 1e-12)
      return s;
  ck_abort_msg("no DOF at (%g, %g)", of->x[2 * r], of->x[2 * r + 1]);
  return -1;
}

/* p's operator added to D (ref->n squared, ref's DOF order); returns its
   largest |entry| */
static double add_dense(nd_problem p, int which, const dof_places *ref, double *D) {
  dof_places mine = places_of(p);
  int64_t *to = malloc(sizeof(int64_t) * (size_t)mine.n);
  for (int64_t r = 0; r < mine.n; ++r) to[r] = same_dof(ref, &mine, r);
  csr A = nd_test_get_matrix(p, which);
  double largest = 0;
  for (int64_t r = 0; r < A.n; ++r)
    for (int64_t k = A.ptr[r]; k < A.ptr[r + 1]; ++k) {
      D[to[r] * ref->n + to[A.col[k]]] += A.val[k];
      largest = fmax(largest, fabs(A.val[k]));
    }
  nd_test_csr_free(&A);
  free(to);
  places_free(&mine);
  return largest;
}

/* max |A - B| over the entries, of the operator `which` of two problems on
   the same DOF positions, relative to their largest entry */
static double difference(nd_problem a, nd_problem b, int which) {
  dof_places ref = places_of(a);
  const size_t n = (size_t)ref.n;
  double *A = calloc(n * n, sizeof(double)), *B = calloc(n * n, sizeof(double));
  const double scale = add_dense(a, which, &ref, A);
  add_dense(b, which, &ref, B);
  double worst = 0;
  for (size_t k = 0; k < n * n; ++k) worst = fmax(worst, fabs(A[k] - B[k]));
  free(A), free(B);
  places_free(&ref);
  return worst / scale;
}

/* ---- the operators are the sums of their cells' ----------------------------- */

START_TEST(operators_are_the_sums_of_the_parts) {
  const int degree = 1 + _i;
  const int which[3] = {ND_MATRIX_STIFFNESS, ND_MATRIX_MASS, ND_MATRIX_LUMPED_MASS};
  for (int w = 0; w < 3; ++w) {
    nd_problem mixed = mixed_problem(degree, 1.5), tri = part_problem(ND_CELL_SIMPLEX, degree, 1.5),
               quad = part_problem(ND_CELL_QUADRILATERAL, degree, 1.5);
    dof_places ref = places_of(mixed);
    const size_t n = (size_t)ref.n;
    double *A = calloc(n * n, sizeof(double)), *S = calloc(n * n, sizeof(double));
    const double scale = add_dense(mixed, which[w], &ref, A);
    add_dense(tri, which[w], &ref, S);
    add_dense(quad, which[w], &ref, S);
    double worst = 0;
    for (size_t k = 0; k < n * n; ++k) worst = fmax(worst, fabs(A[k] - S[k]));
    printf("sum of parts P%d/Q%d, matrix %d: max |mixed - (triangles + quadrilaterals)| = %.3g of %.3g\n", degree,
           degree, which[w], worst, scale);
    /* each entry is the sum of at most 6 cells' contributions, the same bits
       on both sides, added in another order: a few ulps of the largest */
    ck_assert_double_le(worst, 8 * DBL_EPSILON * scale);
    free(A), free(S);
    places_free(&ref);
    ND_OK_OR_FAIL(nd_problem_destroy(&mixed));
    ND_OK_OR_FAIL(nd_problem_destroy(&tri));
    ND_OK_OR_FAIL(nd_problem_destroy(&quad));
  }
}
END_TEST

/* a field u(x) at every free DOF of p (component c of f(x)) */
typedef void field_fn(const double *x, double *u);
static double *field(const dof_places *d, field_fn *f) {
  double *u = malloc(sizeof(double) * (size_t)d->n);
  for (int64_t r = 0; r < d->n; ++r) {
    double v[2];
    f(&d->x[2 * r], v);
    u[r] = v[d->comp[r]];
  }
  return u;
}

static const double kGrad[2][2] = {{0.3, -0.2}, {0.1, -0.25}}, kShift[2] = {0.4, -0.3};
static void linear(const double *x, double *u) {
  for (int a = 0; a < 2; ++a) u[a] = kShift[a] + kGrad[a][0] * x[0] + kGrad[a][1] * x[1];
}
static void shift_x(const double *x, double *u) { (void)x, u[0] = 1, u[1] = 0; }
static void shift_y(const double *x, double *u) { (void)x, u[0] = 0, u[1] = 1; }
static void rotation(const double *x, double *u) { u[0] = -x[1], u[1] = x[0]; }

START_TEST(rigid_motions_mass_and_patch_test) {
  const int degree = 1 + _i;
  const double rho = 2.5, young = 5.0, nu = 0.3;
  nd_problem p = mixed_problem(degree, rho);
  dof_places d = places_of(p);
  csr K = nd_test_get_matrix(p, ND_MATRIX_STIFFNESS);
  ck_assert_int_eq(K.n, d.n);
  /* rigid motions: K r = 0 on every row, to the round-off of its terms */
  field_fn *rigid[3] = {shift_x, shift_y, rotation};
  double worst_rigid = 0;
  for (int m = 0; m < 3; ++m) {
    double *r = field(&d, rigid[m]);
    for (int64_t i = 0; i < K.n; ++i) {
      double Kr = 0, terms = 0;
      for (int64_t k = K.ptr[i]; k < K.ptr[i + 1]; ++k) Kr += K.val[k] * r[K.col[k]], terms += fabs(K.val[k] * r[K.col[k]]);
      worst_rigid = fmax(worst_rigid, fabs(Kr) / terms);
    }
    free(r);
  }
  /* the patch test: u = G x + b */
  double *u = field(&d, linear);
  double energy = 0, worst = 0, scale = 0;
  for (int64_t i = 0; i < K.n; ++i) {
    double Ku = 0, terms = 0;
    for (int64_t k = K.ptr[i]; k < K.ptr[i + 1]; ++k) Ku += K.val[k] * u[K.col[k]], terms += fabs(K.val[k] * u[K.col[k]]);
    energy += u[i] * Ku;
    scale = fmax(scale, terms);
    const double *x = &d.x[2 * i];
    if (x[0] > 1e-12 && x[0] < 1 - 1e-12 && x[1] > 1e-12 && x[1] < 1 - 1e-12) worst = fmax(worst, fabs(Ku));
  }
  const double lambda = young * nu / ((1 + nu) * (1 - 2 * nu)), mu = young / (2 * (1 + nu));
  const double tr = kGrad[0][0] + kGrad[1][1];
  double ee = 0;
  for (int a = 0; a < 2; ++a)
    for (int c = 0; c < 2; ++c) ee += 0.25 * (kGrad[a][c] + kGrad[c][a]) * (kGrad[a][c] + kGrad[c][a]);
  const double exact = lambda * tr * tr + 2 * mu * ee;
  /* the mass */
  csr M = nd_test_get_matrix(p, ND_MATRIX_MASS), L = nd_test_get_matrix(p, ND_MATRIX_LUMPED_MASS);
  double sum = 0, sum_lumped = 0, lowest = INFINITY;
  for (int64_t k = 0; k < M.nnz; ++k) sum += M.val[k];
  for (int64_t k = 0; k < L.nnz; ++k) sum_lumped += L.val[k], lowest = fmin(lowest, L.val[k]);
  printf("mixed P%d/Q%d: rigid |K r| <= %.3g of its terms; patch: interior |K u| = %.3g (terms %.3g), u'Ku = %.17g "
         "(exact %.17g); sum M = %.17g, lumped %.17g (rho |Omega| dim = %g), smallest lumped %.3g\n",
         degree, degree, worst_rigid, worst, scale, energy, exact, sum, sum_lumped, rho * 2, lowest);
  /* sums of at most ~100 terms (a P2/Q2 row): round-off below 1e-13 of them;
     the rules are exact on these cells (fem/cube.cpp, the simplex rules) */
  ck_assert_double_le(worst_rigid, 1e-13);
  ck_assert_double_le(worst, 1e-13 * scale);
  ck_assert_double_le(fabs(energy - exact), 1e-12 * exact);
  ck_assert_double_le(fabs(sum - 2 * rho), 1e-13 * 2 * rho);
  ck_assert_double_le(fabs(sum_lumped - 2 * rho), 1e-13 * 2 * rho);
  ck_assert_double_gt(lowest, 0);
  free(u);
  nd_test_csr_free(&K), nd_test_csr_free(&M), nd_test_csr_free(&L);
  places_free(&d);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* ---- the Gmsh reader ------------------------------------------------------------ */

/* examples/meshes/mixed_v2.msh's cells as the reader takes them: the
   vertices of triangles (type 2) and quadrilaterals (3) numbered by first
   use, a clockwise cell turned (the reader's swaps) */
static nd_mesh create_from_v2_file(void) {
  char path[512];
  snprintf(path, sizeof path, "%s/mixed_v2.msh", ND_MESH_DIR);
  FILE *f = fopen(path, "r");
  ck_assert_ptr_nonnull(f);
  char word[64];
  while (fscanf(f, "%63s", word) == 1 && strcmp(word, "$Nodes") != 0) continue;
  long n_nodes = 0;
  ck_assert_int_eq(fscanf(f, "%ld", &n_nodes), 1);
  double *xyz = malloc(sizeof(double) * (size_t)(3 * n_nodes)), *x = malloc(sizeof(double) * (size_t)(2 * n_nodes));
  long *index = malloc(sizeof(long) * (size_t)(n_nodes + 1));
  for (long i = 0; i < n_nodes; ++i) {
    long tag = 0;
    ck_assert_int_eq(fscanf(f, "%ld %lf %lf %lf", &tag, &xyz[3 * i], &xyz[3 * i + 1], &xyz[3 * i + 2]), 4);
    ck_assert_int_eq(tag, i + 1); /* (Gmsh numbers them so) */
    index[i + 1] = -1;
  }
  while (fscanf(f, "%63s", word) == 1 && strcmp(word, "$Elements") != 0) continue;
  long n_elements = 0, used = 0, n_cells = 0, n_indices = 0;
  ck_assert_int_eq(fscanf(f, "%ld", &n_elements), 1);
  int *types = malloc(sizeof(int) * (size_t)n_elements);
  int64_t *cells = malloc(sizeof(int64_t) * (size_t)(4 * n_elements));
  for (long e = 0; e < n_elements; ++e) {
    long tag, type, n_tags, t, v[4];
    ck_assert_int_eq(fscanf(f, "%ld %ld %ld", &tag, &type, &n_tags), 3);
    for (long k = 0; k < n_tags; ++k) ck_assert_int_eq(fscanf(f, "%ld", &t), 1);
    const int nv = type == 15 ? 1 : type == 1 ? 2 : type == 2 ? 3 : 4;
    for (int k = 0; k < nv; ++k) ck_assert_int_eq(fscanf(f, "%ld", &v[k]), 1);
    if (type != 2 && type != 3) continue;
    double area = 0; /* (shoelace, twice the signed area) */
    for (int k = 0; k < nv; ++k) {
      const double *a = &xyz[3 * (v[k] - 1)], *b = &xyz[3 * (v[(k + 1) % nv] - 1)];
      area += a[0] * b[1] - a[1] * b[0];
    }
    if (area < 0) { /* the reader's swaps */
      const long s = v[1];
      if (nv == 3) v[1] = v[0], v[0] = s;
      else v[1] = v[3], v[3] = s;
    }
    types[n_cells++] = nv == 3 ? ND_CELL_SIMPLEX : ND_CELL_QUADRILATERAL;
    for (int k = 0; k < nv; ++k) {
      if (index[v[k]] < 0) index[v[k]] = used, x[2 * used] = xyz[3 * (v[k] - 1)], x[2 * used + 1] = xyz[3 * (v[k] - 1) + 1], ++used;
      cells[n_indices++] = index[v[k]];
    }
  }
  fclose(f);
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_mixed(2, used, x, n_cells, types, cells, &m));
  free(xyz), free(x), free(index), free(types), free(cells);
  return m;
}

START_TEST(gmsh_mixed_files_give_the_arrays_operators) {
  const char *files[3] = {"mixed.msh", "mixed_v2.msh", "mixed_o2.msh"};
  const int which[3] = {ND_MATRIX_STIFFNESS, ND_MATRIX_MASS, ND_MATRIX_LUMPED_MASS};
  for (int file = 0; file < 3; ++file)
    for (int degree = 1; degree <= 2; ++degree) {
      char path[512];
      snprintf(path, sizeof path, "%s/%s", ND_MESH_DIR, files[file]);
      nd_mesh read = NULL;
      ND_OK_OR_FAIL(nd_mesh_read_gmsh(path, &read));
      int64_t contact = 0, top = 0;
      ND_OK_OR_FAIL(nd_mesh_get_region_size(read, 1, &contact));
      ND_OK_OR_FAIL(nd_mesh_get_region_size(read, 2, &top));
      ck_assert_int_gt(contact, 0);
      ck_assert_int_gt(top, 0);
      nd_problem from_file = problem_of(read, degree, 1.5), from_arrays = problem_of(create_from_v2_file(), degree, 1.5);
      /* triangles and quadrilaterals both there: a triangle's row padded */
      int64_t nc = 0, padded = 0;
      int per_cell = 0;
      ND_OK_OR_FAIL(nd_problem_get_cells(from_file, &nc, &per_cell, NULL));
      ck_assert_int_eq(per_cell, degree == 1 ? 4 : 9);
      int64_t *nodes = malloc(sizeof(int64_t) * (size_t)(nc * per_cell));
      ND_OK_OR_FAIL(nd_problem_get_cells(from_file, &nc, &per_cell, nodes));
      for (int64_t c = 0; c < nc; ++c) padded += nodes[c * per_cell + per_cell - 1] < 0;
      ck_assert_int_gt(padded, 0);
      ck_assert_int_lt(padded, nc);
      free(nodes);
      for (int w = 0; w < 3; ++w) {
        /* the same cells (the files are one Gmsh run's: the same nodes,
           elements and order), the same contributions: equal to round-off
           of the sums' order (bitwise when the numbering agrees) */
        const double diff = difference(from_file, from_arrays, which[w]);
        printf("%s P%d/Q%d matrix %d: |file - arrays| = %.3g of the largest entry (%lld cells, %lld triangles)\n",
               files[file], degree, degree, which[w], diff, (long long)nc, (long long)padded);
        ck_assert_double_le(diff, 8 * DBL_EPSILON);
      }
      ND_OK_OR_FAIL(nd_problem_destroy(&from_file));
      ND_OK_OR_FAIL(nd_problem_destroy(&from_arrays));
    }
}
END_TEST

/* ---- contact ---------------------------------------------------------------- */

/* The patch as a block [0,1]^2 dropped from 0.01 above the plane y = 0 at
   speed 1, gravity 1, hybrid scheme with Theta = 1 (docs/design.md §2): with
   no friction and no damping, E_Theta - W never increases, step by step, to
   round-off, through impacts and releases; also with the mass of the
   contact nodes redistributed (each cell's by its own type). */
START_TEST(contact_ledger_on_a_mixed_block) {
  const int degree = 1 + _i % 2, redistributed = _i / 2;
  patch q = mixed_patch();
  for (int v = 0; v < NV; ++v) q.x[2 * v + 1] += 0.01;
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_mixed(2, NV, q.x, q.n_cells, q.types, q.cells, &m));
  const double lo[2] = {-1, 0.005}, hi[2] = {2, 0.015};
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, lo, hi));
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 100.0, 0.3, 1.0));
  const double point[2] = {0, 0}, up[2] = {0, 1}, g[2] = {0, -1};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, point, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 2e-3));
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, redistributed));
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *v0 = calloc((size_t)(2 * nn), sizeof(double));
  for (int64_t i = 0; i < nn; ++i) v0[2 * i + 1] = -1;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v0));
  free(v0);
  double before = 0, scale = 0, worst = -INFINITY;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &before));
  scale = fabs(before);
  int contact_steps = 0;
  for (int n = 0; n < 200; ++n) {
    ND_OK_OR_FAIL(nd_step(p));
    double E = 0, W = 0, active = 0;
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &E));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_WORK, &W));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
    contact_steps += active > 0;
    scale = fmax(scale, fabs(W));
    worst = fmax(worst, E - W - before);
    before = E - W;
  }
  printf("mixed block P%d/Q%d%s, hybrid Theta = 1: max step increase of E_Theta - W = %.3g (scale %.3g), %d steps "
         "in contact\n",
         degree, degree, redistributed ? " (redistributed mass)" : "", worst, scale, contact_steps);
  /* (as test_friction's ledger: sums over a few hundred DOFs, 1e-12 of the
     energies; a wrong contact row on one cell type breaks it at O(1e-3)) */
  ck_assert_double_le(worst, 1e-12 * scale);
  ck_assert_int_gt(contact_steps, 5);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* Two mixed patches, the upper one shifted by (0.1, 1.02) and falling at
   speed 1 onto the lower one, clamped at y = 0: a contact pair (docs/design.md
   §10.3) whose slave and master facets are triangles' and quadrilaterals'
   edges. Hybrid scheme, Theta = 1: E_Theta - W - W_geometry never rises,
   step by step, to round-off (as tests/test_pairs.c's ledger). */
START_TEST(contact_pair_of_mixed_blocks) {
  const int degree = 1 + _i;
  const patch q = mixed_patch();
  double x[4 * NV];
  int types[2 * MAX_CELLS];
  int64_t cells[8 * MAX_CELLS];
  for (int v = 0; v < NV; ++v) {
    x[2 * v] = q.x[2 * v], x[2 * v + 1] = q.x[2 * v + 1];
    x[2 * (NV + v)] = q.x[2 * v] + 0.1, x[2 * (NV + v) + 1] = q.x[2 * v + 1] + 1.02;
  }
  for (int64_t c = 0; c < q.n_cells; ++c) types[c] = types[q.n_cells + c] = q.types[c];
  for (int64_t k = 0; k < q.n_indices; ++k) cells[k] = q.cells[k], cells[q.n_indices + k] = q.cells[k] + NV;
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_mixed(2, 2 * NV, x, 2 * q.n_cells, types, cells, &m));
  const double slave_lo[2] = {-1, 1.01}, slave_hi[2] = {2, 1.03}, master_lo[2] = {-1, 0.99}, master_hi[2] = {2, 1.001};
  const double clamp_lo[2] = {-1, -0.001}, clamp_hi[2] = {2, 0.001};
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, slave_lo, slave_hi));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, master_lo, master_hi));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 3, clamp_lo, clamp_hi));
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 100.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 3));
  ND_OK_OR_FAIL(nd_problem_set_contact_pair(p, 1, 2));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 2e-3));
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *nx = malloc(sizeof(double) * (size_t)(2 * nn)), *v0 = calloc((size_t)(2 * nn), sizeof(double));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, nx));
  for (int64_t i = 0; i < nn; ++i) v0[2 * i + 1] = nx[2 * i + 1] > 1.01 ? -1.0 : 0.0;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v0));
  free(nx), free(v0);
  double before = 0, E = 0, W = 0, Wg = 0, active = 0, worst = -INFINITY;
  ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &before));
  const double scale = before;
  int contact_steps = 0;
  for (int n = 0; n < 100; ++n) {
    ND_OK_OR_FAIL(nd_step(p));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ENERGY_AUGMENTED, &E));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_WORK, &W));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_WORK_GEOMETRY, &Wg));
    ND_OK_OR_FAIL(nd_get_scalar(p, ND_ACTIVE_POINTS, &active));
    contact_steps += active > 0;
    worst = fmax(worst, E - W - Wg - before);
    before = E - W - Wg;
  }
  printf("mixed pair P%d/Q%d, hybrid Theta = 1: max step rise of E_Theta - W - W_geometry = %.3g (E0 %.3g), %d steps "
         "in contact\n",
         degree, degree, worst, scale, contact_steps);
  ck_assert_double_le(worst, 1e-12 * scale);
  ck_assert_int_gt(contact_steps, 5);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* ---- refusals ---------------------------------------------------------------- */

/* an MSH 2.2 file of these sections is refused (ND_ERR_FORMAT), the
   message naming `what` */
static void file_refused(const char *sections, const char *what) {
  char path[] = "/tmp/nd_mixed_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  char text[1024];
  snprintf(text, sizeof text, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n%s", sections);
  nd_test_write_file(path, text);
  nd_mesh m = NULL;
  ck_assert_int_eq(nd_mesh_read_gmsh(path, &m), ND_ERR_FORMAT);
  ck_assert_msg(strstr(nd_last_error(), what) != NULL, "%s", nd_last_error());
  ck_assert_ptr_null(m);
  remove(path);
}

START_TEST(refusals) {
  nd_mesh m = NULL;
  /* a hexahedron and a tetrahedron on its top face */
  const double x[27] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0, 0, 2};
  const int types[2] = {ND_CELL_HEXAHEDRON, ND_CELL_SIMPLEX};
  const int64_t cells[12] = {0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 7, 8};
  ck_assert_int_eq(nd_mesh_create_mixed(3, 9, x, 2, types, cells, &m), ND_ERR_DIMENSION);
  ck_assert_msg(strstr(nd_last_error(), "pyramids or prisms") != NULL, "%s", nd_last_error());
  ck_assert_ptr_null(m);
  /* the same from Gmsh files; prisms (6) and pyramids (7) named */
  file_refused("$Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n9 0 0 2\n$EndNodes\n"
               "$Elements\n2\n1 5 2 1 1 1 2 3 4 5 6 7 8\n2 4 2 1 1 5 6 8 9\n$EndElements\n",
               "tetrahedra and hexahedra");
  file_refused("$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 0 1\n6 0 1 1\n$EndNodes\n"
               "$Elements\n1\n1 6 2 1 1 1 2 3 4 5 6\n$EndElements\n",
               "a prism");
  file_refused("$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0.5 0.5 1\n$EndNodes\n"
               "$Elements\n1\n1 7 2 1 1 1 2 3 4 5\n$EndElements\n",
               "a pyramid");
  /* one type only: the uniform mesh of nd_mesh_create_cells, the same operators */
  const double sq[8] = {0, 0, 1, 0, 1, 1, 0, 1};
  const int quads[1] = {ND_CELL_QUADRILATERAL};
  const int64_t ccw[4] = {0, 1, 2, 3};
  nd_mesh a = NULL, b = NULL;
  ND_OK_OR_FAIL(nd_mesh_create_mixed(2, 4, sq, 1, quads, ccw, &a));
  ND_OK_OR_FAIL(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 1, ccw, &b));
  nd_problem pa = problem_of(a, 2, 1.0), pb = problem_of(b, 2, 1.0);
  ck_assert_double_eq(difference(pa, pb, ND_MATRIX_STIFFNESS), 0);
  int64_t nc = 0;
  int per_cell = 0;
  ND_OK_OR_FAIL(nd_problem_get_cells(pa, &nc, &per_cell, NULL));
  ck_assert_int_eq(per_cell, 9);
  ND_OK_OR_FAIL(nd_problem_destroy(&pa));
  ND_OK_OR_FAIL(nd_problem_destroy(&pb));
}
END_TEST

/* ---- output ------------------------------------------------------------------ */

/* the VTU file gives each cell its VTK type: 5 and 9 (P1/Q1), 22 and 28 (P2/Q2) */
START_TEST(vtu_has_each_cells_type) {
  const int degree = 1 + _i;
  nd_problem p = mixed_problem(degree, 1.0);
  char path[] = "/tmp/nd_mixed_vtu_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  ND_OK_OR_FAIL(nd_problem_write_vtu(p, path));
  FILE *f = fopen(path, "r");
  ck_assert_ptr_nonnull(f);
  char line[256];
  int in_types = 0, count[64] = {0};
  while (fgets(line, sizeof line, f)) {
    if (strstr(line, "Name=\"types\"")) in_types = 1;
    else if (strstr(line, "</DataArray>")) in_types = 0;
    else if (in_types) {
      const int t = atoi(line);
      if (t >= 0 && t < 64) ++count[t];
    }
  }
  fclose(f);
  remove(path);
  const patch q = mixed_patch();
  int quads = 0;
  for (int64_t c = 0; c < q.n_cells; ++c) quads += q.types[c] == ND_CELL_QUADRILATERAL;
  ck_assert_int_eq(count[degree == 1 ? 9 : 28], quads);
  ck_assert_int_eq(count[degree == 1 ? 5 : 22], q.n_cells - quads);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("mixed");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_loop_test(tc, operators_are_the_sums_of_the_parts, 0, 2);
  tcase_add_loop_test(tc, rigid_motions_mass_and_patch_test, 0, 2);
  tcase_add_test(tc, gmsh_mixed_files_give_the_arrays_operators);
  tcase_add_loop_test(tc, contact_ledger_on_a_mixed_block, 0, 4);
  tcase_add_loop_test(tc, contact_pair_of_mixed_blocks, 0, 2);
  tcase_add_test(tc, refusals);
  tcase_add_loop_test(tc, vtu_has_each_cells_type, 0, 2);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
