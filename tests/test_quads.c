/* Quadrilaterals and hexahedra, Q1 and Q2 (issue 60), by identities that hold
 * exactly (to round-off):
 *  - a strip of one row of Q cells (one cell thick), nu = 0, moving along its
 *    axis, is the 1D bar of P1 (P2) cells: with u_x = u(x) alone the Q
 *    operators are the 1D ones times the cross-section's weights, the
 *    consistent mass a tensor product, the lumped one too (row sums for Q1;
 *    HRZ for Q2, whose 1D factor is P2's HRZ, Simpson's weights);
 *  - the patch test: on distorted cells a linear field is in the space, its
 *    stress constant: K u vanishes at the interior nodes and u'Ku is
 *    |Omega| sigma:eps (the rules integrate both exactly, fem/cube.cpp);
 *  - the mass: sum of M's entries and of the lumped diagonal is
 *    rho |Omega| per component, consistent and lumped, the lumped positive;
 *  - the Gmsh reader: a file of quadrilaterals or hexahedra (4, 8, 9, 27
 *    nodes) gives the generator's operators; curved and serendipity
 *    elements are refused;
 *  - contact on Q facets: the strip bouncing on a plane is the bar bouncing,
 *    gamma matched cell by cell (h_K = sqrt(dim) h), every implicit scheme
 *    and Theta = 1, 0, -1;
 *  - mass redistribution keeps the mass; on a Q1 strip it is the P1 bar's
 *    (for rectangles it factors by direction as the mass does);
 *  - the refusals: a bad cell type, a dimension that does not match it, an
 *    inverted or non-convex cell; facets by their vertices. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testutil.h"

typedef nd_test_csr csr;
static csr get_matrix(nd_problem p, int which) { return nd_test_get_matrix(p, which); }
static void csr_free(csr *a) { nd_test_csr_free(a); }

/* ---- the strip is the bar -------------------------------------------------- */

enum { NX = 6, STEPS = 80 };
static const double kLength = 2.0, kYoung = 3.0, kTau = 0.01;

static double v0_of(double x) { return 0.3 * sin(1.0 + 2.0 * x); }

/* the bar (dim 1) or the strip (dim 2, 3: one cell across, thickness 0.3),
   clamped at x = 0, free at x = L, nu = 0, initial velocity v0(x) along x */
static nd_problem strip(int dim, int degree, const nd_test_scheme *sc, int lumped) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[3] = {0, 0, 0}, hi[3] = {kLength, 0.3, 0.3};
  const double clamp_lo[3] = {-1, -1, -1}, clamp_hi[3] = {1e-9, 2, 2};
  if (dim == 1) ND_OK_OR_FAIL(nd_mesh_create_interval(NX, 0.0, kLength, &m));
  if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(NX, 1, lo, hi, ND_CELL_QUADRILATERAL, &m));
  if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box_cells(NX, 1, 1, lo, hi, ND_CELL_HEXAHEDRON, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, clamp_lo, clamp_hi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, kYoung, 0.0, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, sc->scheme, sc->params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, kTau));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *x = malloc(sizeof(double) * (size_t)(n * dim)), *v0 = calloc((size_t)(n * dim), sizeof(double));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n; ++i) v0[i * dim] = v0_of(x[i * dim]);
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v0));
  free(x);
  free(v0);
  return p;
}

/* Steps the bar and the strip side by side, comparing the strip's nodes with
   the bar's node at the same x: |u_x - u|, |v_x - v| and the transverse
   components (0), over the steps; the contact forces, the strip's per unit
   of cross-section (area). Destroys both. */
typedef struct {
  double worst, size, first;        /* max difference, max |u|, |v|, the difference after one step */
  double force, force_size, contact_steps;
} comparison;

static comparison side_by_side(nd_problem bar, nd_problem q, int dim, int steps, double area) {
  comparison r = {0, 0, 0, 0, 0, 0};
  int64_t nb = 0, nq = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(bar, &nb));
  ND_OK_OR_FAIL(nd_problem_get_node_count(q, &nq));
  double *xb = malloc(sizeof(double) * (size_t)nb), *xq = malloc(sizeof(double) * (size_t)(nq * dim));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(bar, nb, xb));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(q, nq, xq));
  int64_t *twin = malloc(sizeof(int64_t) * (size_t)nq); /* the bar's node at the same x */
  for (int64_t i = 0; i < nq; ++i) {
    twin[i] = -1;
    for (int64_t j = 0; j < nb; ++j)
      if (fabs(xq[i * dim] - xb[j]) <= 1e-12) twin[i] = j;
    ck_assert_msg(twin[i] >= 0, "node %lld of the strip has no twin in the bar", (long long)i);
  }
  double *ub = malloc(sizeof(double) * (size_t)nb), *uq = malloc(sizeof(double) * (size_t)(nq * dim));
  for (int k = 0; k < steps; ++k) {
    ND_OK_OR_FAIL(nd_step(bar));
    ND_OK_OR_FAIL(nd_step(q));
    for (int field = ND_FIELD_DISPLACEMENT; field <= ND_FIELD_VELOCITY; ++field) {
      ND_OK_OR_FAIL(nd_get_field(bar, field, nb, ub));
      ND_OK_OR_FAIL(nd_get_field(q, field, nq, uq));
      for (int64_t i = 0; i < nq; ++i) {
        r.worst = fmax(r.worst, fabs(uq[i * dim] - ub[twin[i]]));
        for (int c = 1; c < dim; ++c) r.worst = fmax(r.worst, fabs(uq[i * dim + c]));
        r.size = fmax(r.size, fabs(ub[twin[i]]));
      }
    }
    if (k == 0) r.first = r.worst;
    double fb = 0, fq = 0;
    ND_OK_OR_FAIL(nd_get_scalar(bar, ND_CONTACT_FORCE, &fb));
    ND_OK_OR_FAIL(nd_get_scalar(q, ND_CONTACT_FORCE, &fq));
    r.force = fmax(r.force, fabs(fq / area - fb)), r.force_size = fmax(r.force_size, fabs(fb));
    r.contact_steps += fb > 0;
  }
  free(xb), free(xq), free(twin), free(ub), free(uq);
  ND_OK_OR_FAIL(nd_problem_destroy(&bar));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
  return r;
}

START_TEST(strip_is_the_bar) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  for (int s = 0; s < ND_TEST_N_SCHEMES; ++s)
    for (int lumped = 0; lumped <= 1; ++lumped) {
      const nd_test_scheme *sc = &nd_test_schemes[s];
      if (nd_test_is_explicit(sc) && !lumped) continue; /* (explicit: lumped mass only) */
      const comparison r = side_by_side(strip(1, degree, sc, lumped), strip(dim, degree, sc, lumped), dim, STEPS,
                                        0.3 * (dim == 3 ? 0.3 : 1.0));
      /* the same equations solved with other round-off (larger systems,
         other factorizations): a few ulps after one step (printed), growing
         about linearly over the 80 steps to ~1e-12 relative; 1e-11 bounds
         that with margin, while any difference of the discretizations
         would be of the order of its error, h^2 ~ 1e-2 */
      printf("strip %dD Q%d scheme %d%s: max |strip - bar| = %.3g, after one step %.3g (|u|, |v| up to %.3g)\n", dim,
             degree, sc->scheme, lumped ? " lumped" : "", r.worst, r.first, r.size);
      ck_assert_msg(r.worst <= 1e-11 * r.size, "%dD Q%d scheme %d lumped %d: %.3g", dim, degree, sc->scheme, lumped,
                    r.worst);
    }
}
END_TEST

/* ---- the strip bounces as the bar ------------------------------------------ */

/* nd_test_bar's bar (E = rho = 1, nu = 0, clamped at x = 1, the obstacle at
   x <= 0, u0 = (1 - x)/2) as a strip of square cells (cubes), gamma matched
   cell by cell: gamma_q = gamma0 h_K with h_K the cell's diameter, sqrt(dim) h */
enum { BAR_NX = 8 };
static nd_problem bouncing_strip(int dim, int degree, const nd_test_scheme *sc, double theta, double gamma0_bar) {
  return nd_test_strip(dim, dim == 2 ? ND_CELL_QUADRILATERAL : ND_CELL_HEXAHEDRON, BAR_NX, degree, sc->scheme,
                       sc->params, theta, gamma0_bar / sqrt((double)dim), kTau);
}

START_TEST(strip_bounces_as_the_bar) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double thetas[3] = {1, 0, -1}, gamma0 = 0.1; /* (below the bar's limits 1 and 1/4: K_Theta >= 0) */
  /* mass: 0 consistent; Q1 also 1 redistributed, 2 redistributed and lumped
     (for rectangles the redistribution factors by direction: the rows of
     the affine functions on the kept nodes are 1 and y, those of the bar's
     node 1, and both cells' masses are tensor products) */
  for (int mass = 0; mass <= (degree == 1 ? 2 : 0); ++mass)
    for (int s = 0; s < ND_TEST_N_SCHEMES; ++s)
      for (int t = 0; t < 3; ++t) {
        const nd_test_scheme *sc = &nd_test_schemes[s];
        if (nd_test_is_explicit(sc)) continue; /* (the explicit scheme's lumped mass: strip_is_the_bar) */
        nd_problem bar = nd_test_bar(BAR_NX, degree, sc->scheme, sc->params, thetas[t], gamma0, kTau);
        nd_problem q = bouncing_strip(dim, degree, sc, thetas[t], gamma0);
        /* (Theta <= 0 gains energy at impacts, the method's own (Theta - 1) term, docs/design.md §3b: the
           energy-balance guard refuses it (test_guards_scale); this test compares the strip with the bar) */
        if (thetas[t] <= 0)
          for (int k = 0; k < 2; ++k) ND_OK_OR_FAIL(nd_problem_set_guard(k ? q : bar, ND_GUARD_ENERGY_BALANCE, 0));
        for (int k = 0; k < 2 && mass > 0; ++k) {
          ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(k ? q : bar, 1));
          ND_OK_OR_FAIL(nd_problem_set_mass_lumping(k ? q : bar, mass == 2));
        }
        /* Newton to round-off in both (the active set fixed, it ends in one
           more iteration): the runs then differ by round-off alone */
        ND_OK_OR_FAIL(nd_problem_set_newton(bar, 1e-14, 1e-300, 50));
        ND_OK_OR_FAIL(nd_problem_set_newton(q, 1e-14, 1e-300, 50));
        const comparison r = side_by_side(bar, q, dim, 150, pow(1.0 / BAR_NX, dim - 1));
        printf("bounce %dD Q%d mass %d scheme %d theta %g: max |strip - bar| = %.3g (|u|, |v| up to %.3g), "
               "force %.3g of %.3g, %g steps in contact\n",
               dim, degree, mass, sc->scheme, thetas[t], r.worst, r.size, r.force, r.force_size, r.contact_steps);
        ck_assert(r.contact_steps > 0); /* (it does bounce) */
        /* as strip_is_the_bar (1e-11 there, over 80 steps), here over 150
           steps and the impacts: round-off; a wrong gamma, normal stress or
           facet rule would show at 1e-2 */
        ck_assert_msg(r.worst <= 1e-10 * r.size, "%dD Q%d mass %d scheme %d theta %g: %.3g", dim, degree, mass,
                      sc->scheme, thetas[t], r.worst);
        ck_assert_msg(r.force <= 1e-10 * r.force_size, "force %.3g of %.3g", r.force, r.force_size);
      }
}
END_TEST

/* Coulomb friction on the strip's contact facet: the impact is normal, the
   tangential displacement stays 0 (to round-off), so does the friction
   force: the strip still bounces as the frictionless bar (Theta = 1, the
   implicit schemes but the explicit one) */
START_TEST(normal_impact_with_friction_is_the_bar) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double coefficient = 0.3, gamma0 = 0.1;
  for (int s = 0; s < ND_TEST_N_SCHEMES; ++s) {
    const nd_test_scheme *sc = &nd_test_schemes[s];
    if (nd_test_is_explicit(sc)) continue;
    nd_problem bar = nd_test_bar(BAR_NX, degree, sc->scheme, sc->params, 1.0, gamma0, kTau);
    nd_problem q = bouncing_strip(dim, degree, sc, 1.0, gamma0);
    ND_OK_OR_FAIL(nd_problem_set_friction(q, 1, ND_FRICTION_COULOMB, &coefficient));
    const comparison r = side_by_side(bar, q, dim, 150, pow(1.0 / BAR_NX, dim - 1));
    printf("friction %dD Q%d scheme %d: max |strip - bar| = %.3g (|u|, |v| up to %.3g), force %.3g of %.3g\n", dim,
           degree, sc->scheme, r.worst, r.size, r.force, r.force_size);
    ck_assert(r.contact_steps > 0);
    ck_assert_msg(r.worst <= 1e-10 * r.size, "%dD Q%d scheme %d: %.3g", dim, degree, sc->scheme, r.worst);
    ck_assert_msg(r.force <= 1e-10 * r.force_size, "force %.3g of %.3g", r.force, r.force_size);
  }
}
END_TEST

/* the 3D Q2 strip in contact written as VTU: its 8 triquadratic hexahedra
   (VTK type 29, 27 nodes each) and its contact facet, a quadrilateral (9) */
START_TEST(vtu_of_hexahedra_in_contact) {
  const nd_test_scheme hybrid = {ND_SCHEME_HYBRID, {0, 0}};
  nd_problem q = bouncing_strip(3, 2, &hybrid, 1.0, 0.1);
  double active = 0;
  for (int k = 0; k < 150 && active == 0; ++k) {
    ND_OK_OR_FAIL(nd_step(q));
    ND_OK_OR_FAIL(nd_get_scalar(q, ND_ACTIVE_POINTS, &active));
  }
  ck_assert(active > 0);
  char path[] = "/tmp/nd_quads_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  ND_OK_OR_FAIL(nd_problem_write_vtu(q, path));
  FILE *f = fopen(path, "r");
  ck_assert_ptr_nonnull(f);
  static char text[1 << 20];
  const size_t got = fread(text, 1, sizeof text - 1, f);
  text[got] = '\0';
  fclose(f);
  remove(path);
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(q, &n));
  char expect[128];
  snprintf(expect, sizeof expect, "NumberOfPoints=\"%lld\" NumberOfCells=\"%d\"", (long long)n, BAR_NX + 1);
  ck_assert_msg(strstr(text, expect) != NULL, "missing %s", expect);
  const char *types = strstr(text, "Name=\"types\"");
  ck_assert_ptr_nonnull(types);
  types = strchr(types, '>') + 1;
  for (int c = 0; c <= BAR_NX; ++c) {
    char *end = NULL;
    ck_assert_int_eq(strtol(types, &end, 10), c < BAR_NX ? 29 : 9);
    types = end;
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

/* ---- distorted patches ----------------------------------------------------- */

/* [0,1]^dim in 2 cells a side, the interior vertex (2D) or the centre and the
   face centres' vertices (3D) moved off the grid: the boundary stays the
   box's, so |Omega| = 1 */
static nd_mesh distorted_patch(int dim) {
  nd_mesh m = NULL;
  const int nv = dim == 2 ? 9 : 27, nc = dim == 2 ? 4 : 8;
  double x[27 * 3];
  int64_t cells[8 * 8];
  for (int v = 0; v < nv; ++v) {
    const int i[3] = {v % 3, (v / 3) % 3, v / 9};
    for (int k = 0; k < dim; ++k) x[v * dim + k] = 0.5 * i[k];
    int interior = 0; /* coordinates strictly inside (0, 1) */
    for (int k = 0; k < dim; ++k) interior += i[k] == 1;
    /* move the coordinates that are interior: along the free directions */
    for (int k = 0; k < dim; ++k)
      if (i[k] == 1) x[v * dim + k] += 0.035 * (k + 1) * (interior == dim ? 1.0 : -0.6) + 0.01 * v / nv;
  }
  static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int c = 0; c < nc; ++c) {
    const int ci[3] = {c % 2, (c / 2) % 2, c / 4};
    for (int k = 0; k < (1 << dim); ++k) {
      const int a = ci[0] + corner[k][0], b = ci[1] + corner[k][1], z = dim == 3 ? ci[2] + corner[k][2] : 0;
      cells[c * (1 << dim) + k] = a + 3 * b + 9 * z;
    }
  }
  ND_OK_OR_FAIL(nd_mesh_create_cells(dim, dim == 2 ? ND_CELL_QUADRILATERAL : ND_CELL_HEXAHEDRON, nv, x, nc, cells, &m));
  return m;
}

static nd_problem patch_problem(int dim, int degree, double young, double nu, double rho) {
  nd_mesh m = distorted_patch(dim);
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, young, nu, rho));
  return p;
}

START_TEST(patch_test_on_distorted_cells) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double young = 5.0, nu = 0.3;
  nd_problem p = patch_problem(dim, degree, young, nu, 1.0);
  csr K = get_matrix(p, ND_MATRIX_STIFFNESS);
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  ck_assert_int_eq(K.n, nn * dim); /* nothing clamped */
  double *x = malloc(sizeof(double) * (size_t)(nn * dim)), *u = malloc(sizeof(double) * (size_t)K.n);
  int64_t *node = malloc(sizeof(int64_t) * (size_t)K.n);
  int *comp = malloc(sizeof(int) * (size_t)K.n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, x));
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, K.n, node, comp));
  /* u = G x + b, G neither symmetric nor trace-free */
  const double G[3][3] = {{0.3, -0.2, 0.15}, {0.1, -0.25, 0.05}, {-0.12, 0.07, 0.2}}, b[3] = {0.4, -0.3, 0.2};
  for (int64_t r = 0; r < K.n; ++r) {
    u[r] = b[comp[r]];
    for (int k = 0; k < dim; ++k) u[r] += G[comp[r]][k] * x[node[r] * dim + k];
  }
  double energy = 0, worst = 0, scale = 0;
  for (int64_t r = 0; r < K.n; ++r) {
    double Ku = 0, absKu = 0;
    for (int64_t k = K.ptr[r]; k < K.ptr[r + 1]; ++k) Ku += K.val[k] * u[K.col[k]], absKu += fabs(K.val[k] * u[K.col[k]]);
    energy += u[r] * Ku;
    scale = fmax(scale, absKu);
    int inside = 1; /* interior node: every coordinate strictly inside (0, 1) */
    for (int k = 0; k < dim; ++k) inside &= x[node[r] * dim + k] > 1e-12 && x[node[r] * dim + k] < 1 - 1e-12;
    if (inside) worst = fmax(worst, fabs(Ku));
  }
  /* sigma:eps |Omega| with lambda of plane strain (2D) or 3D, |Omega| = 1 */
  const double lambda = young * nu / ((1 + nu) * (1 - 2 * nu)), mu = young / (2 * (1 + nu));
  double tr = 0, ee = 0;
  for (int a = 0; a < dim; ++a) tr += G[a][a];
  for (int a = 0; a < dim; ++a)
    for (int c = 0; c < dim; ++c) ee += 0.25 * (G[a][c] + G[c][a]) * (G[a][c] + G[c][a]);
  const double exact = lambda * tr * tr + 2 * mu * ee;
  printf("patch %dD Q%d: max interior |K u| = %.3g (terms up to %.3g); u'Ku = %.17g, exact %.17g\n", dim, degree, worst,
         scale, energy, exact);
  /* sums of a few hundred terms of size `scale`: round-off ~1e-13 of it */
  ck_assert_msg(worst <= 1e-12 * scale, "interior residual %.3g", worst);
  ck_assert_msg(fabs(energy - exact) <= 1e-12 * exact, "energy %.17g vs %.17g", energy, exact);
  free(x), free(u), free(node), free(comp);
  csr_free(&K);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(mass_is_rho_times_volume) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double rho = 2.5; /* |Omega| = 1 */
  for (int lumped = 0; lumped <= 1; ++lumped) {
    nd_problem p = patch_problem(dim, degree, 1.0, 0.25, rho);
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
    csr M = get_matrix(p, ND_MATRIX_MASS), L = get_matrix(p, ND_MATRIX_LUMPED_MASS);
    double sum = 0, sum_lumped = 0, lowest = INFINITY;
    for (int64_t k = 0; k < M.nnz; ++k) sum += M.val[k];
    for (int64_t k = 0; k < L.nnz; ++k) sum_lumped += L.val[k], lowest = fmin(lowest, L.val[k]);
    printf("mass %dD Q%d%s: sum M = %.17g, sum lumped = %.17g, smallest lumped %.3g (rho |Omega| dim = %g)\n", dim, degree,
           lumped ? " (lumped)" : "", sum, sum_lumped, lowest, rho * dim);
    /* exact rules (det J's degree included): round-off of a few hundred sums */
    ck_assert(fabs(sum - rho * dim) <= 1e-13 * rho * dim);
    ck_assert(fabs(sum_lumped - rho * dim) <= 1e-13 * rho * dim);
    ck_assert(lowest > 0);
    csr_free(&M), csr_free(&L);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* ---- the Gmsh reader ---------------------------------------------------------- */

/* A 2 x 1 (x 1) grid of [0,2] x [0,1] (x [0,1]) in MSH 2.2: quadrilaterals
   or hexahedra, first order (types 3, 5) or 9/27 nodes (types 10, 12), the
   facets at x = 0 in physical group 5, the cells in group 1. The nodes are
   those of the grid refined twice, their tags in reverse order (the reader
   numbers vertices by first use: not the generator's numbering). With
   `bend`, the first cell's centre node moves off the mean of its corners. */
static const int kHex27[19][8] = {{0, 1, -1}, {0, 3, -1}, {0, 4, -1}, {1, 2, -1}, {1, 5, -1}, {2, 3, -1}, {2, 6, -1},
                                  {3, 7, -1}, {4, 5, -1}, {4, 7, -1}, {5, 6, -1}, {6, 7, -1}, {0, 3, 2, 1, -1},
                                  {0, 1, 5, 4, -1}, {0, 4, 7, 3, -1}, {1, 2, 6, 5, -1}, {2, 3, 7, 6, -1},
                                  {4, 5, 6, 7, -1}, {0, 1, 2, 3, 4, 5, 6, 7}};
static const int kQuad9[5][8] = {{0, 1, -1}, {1, 2, -1}, {2, 3, -1}, {3, 0, -1}, {0, 1, 2, 3, -1}};
static const int kCorner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

enum { GX = 5, GY = 3, GZ = 3 }; /* the refined grid's points a direction */
static int grid_tag(int i, int j, int k) { return GX * GY * GZ - ((k * GY + j) * GX + i); }

/* the refined-grid point of the mean of corners list (of the cell at x offset cx) */
static int mean_tag(int dim, int cx, const int *list) {
  int at[3] = {0, 0, 0}, m = 0;
  while (m < 8 && list[m] >= 0) {
    for (int k = 0; k < dim; ++k) at[k] += 2 * kCorner[list[m]][k];
    ++m;
  }
  return grid_tag(2 * cx + at[0] / m, at[1] / m, dim == 3 ? at[2] / m : 0);
}

static void write_grid_msh(const char *path, int dim, int degree, int bend) {
  FILE *f = fopen(path, "w");
  ck_assert_ptr_nonnull(f);
  fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n", GX * GY * (dim == 3 ? GZ : 1));
  for (int k = 0; k < (dim == 3 ? GZ : 1); ++k)
    for (int j = 0; j < GY; ++j)
      for (int i = 0; i < GX; ++i) {
        const int centre_of_first = bend && i == 1 && j == 1 && (dim == 2 || k == 1);
        fprintf(f, "%d %.17g %.17g %.17g\n", grid_tag(i, j, k), 0.5 * i + (centre_of_first ? 0.01 : 0.0), 0.5 * j,
                dim == 3 ? 0.5 * k : 0.0);
      }
  const int n_facet_nodes = dim == 2 ? (degree == 1 ? 2 : 3) : (degree == 1 ? 4 : 9);
  fprintf(f, "$EndNodes\n$Elements\n%d\n", 2 + 1);
  int tag = 1;
  for (int cx = 0; cx < 2; ++cx) { /* the cells */
    const int nc = 1 << dim, n = degree == 1 ? nc : dim == 2 ? 9 : 27;
    fprintf(f, "%d %d 2 1 1", tag++, dim == 2 ? (degree == 1 ? 3 : 10) : (degree == 1 ? 5 : 12));
    for (int c = 0; c < nc; ++c)
      fprintf(f, " %d", grid_tag(2 * (cx + kCorner[c][0]), 2 * kCorner[c][1], dim == 3 ? 2 * kCorner[c][2] : 0));
    for (int e = 0; e < n - nc; ++e) fprintf(f, " %d", mean_tag(dim, cx, dim == 2 ? kQuad9[e] : kHex27[e]));
    fprintf(f, "\n");
  }
  /* the facet x = 0 of the first cell: a line (3 nodes) or a quadrilateral (9) */
  static const int line[2] = {3, 0}, face[4] = {0, 4, 7, 3};
  fprintf(f, "%d %d 2 5 2", tag++, dim == 2 ? (degree == 1 ? 1 : 8) : (degree == 1 ? 3 : 10));
  for (int c = 0; c < (dim == 2 ? 2 : 4); ++c) {
    const int v = dim == 2 ? line[c] : face[c];
    fprintf(f, " %d", grid_tag(0, 2 * kCorner[v][1], dim == 3 ? 2 * kCorner[v][2] : 0));
  }
  if (n_facet_nodes == 3) fprintf(f, " %d", grid_tag(0, 1, 0));
  if (n_facet_nodes == 9) /* edges (0,1) (1,2) (2,3) (3,0) of the face, then its centre */
    fprintf(f, " %d %d %d %d %d", grid_tag(0, 0, 1), grid_tag(0, 1, 2), grid_tag(0, 2, 1), grid_tag(0, 1, 0),
            grid_tag(0, 1, 1));
  fprintf(f, "\n$EndElements\n");
  fclose(f);
}

/* the dense operator of a problem, rows and columns by node coordinates: the
   index of DOF (node, component) in the generator's numbering is found by
   position, so that two numberings compare */
static double *dense_by_position(nd_problem p, int which, int dim, const double *x_ref, int64_t n_ref) {
  csr A = get_matrix(p, which);
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  ck_assert_int_eq(nn, n_ref);
  double *x = malloc(sizeof(double) * (size_t)(nn * dim));
  int64_t *node = malloc(sizeof(int64_t) * (size_t)A.n), *ref = malloc(sizeof(int64_t) * (size_t)nn);
  int *comp = malloc(sizeof(int) * (size_t)A.n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, x));
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, A.n, node, comp));
  for (int64_t i = 0; i < nn; ++i) {
    ref[i] = -1;
    for (int64_t j = 0; j < n_ref; ++j) {
      double d = 0;
      for (int k = 0; k < dim; ++k) d = fmax(d, fabs(x[i * dim + k] - x_ref[j * dim + k]));
      if (d <= 1e-14) ref[i] = j;
    }
    ck_assert_msg(ref[i] >= 0, "node %lld has no twin", (long long)i);
  }
  const int64_t n = n_ref * dim;
  double *D = calloc((size_t)(n * n), sizeof(double));
  for (int64_t r = 0; r < A.n; ++r)
    for (int64_t k = A.ptr[r]; k < A.ptr[r + 1]; ++k) {
      const int64_t c = A.col[k];
      D[(ref[node[r]] * dim + comp[r]) * n + ref[node[c]] * dim + comp[c]] = A.val[k];
    }
  free(x), free(node), free(ref), free(comp);
  csr_free(&A);
  return D;
}

/* The mesh read from path against the generator's 2 x 1 (x 1) grid of
   [0,2] x [0,1] (x [0,1]): one facet in region 5 (x = 0) in both, and the
   same M, K and lumped M (clamped on region 5), DOFs matched by position */
static void same_as_generated(const char *path, int dim, int degree) {
  nd_mesh read = NULL, made = NULL;
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(path, &read));
  const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1}, blo[3] = {-1, -1, -1}, bhi[3] = {1e-9, 2, 2};
  if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(2, 1, lo, hi, ND_CELL_QUADRILATERAL, &made));
  if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box_cells(2, 1, 1, lo, hi, ND_CELL_HEXAHEDRON, &made));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(made, 5, blo, bhi));
  int64_t n_read = 0, n_made = 0;
  ND_OK_OR_FAIL(nd_mesh_get_region_size(read, 5, &n_read));
  ND_OK_OR_FAIL(nd_mesh_get_region_size(made, 5, &n_made));
  ck_assert_int_eq(n_read, 1);
  ck_assert_int_eq(n_made, 1);
  nd_problem p = NULL, q = NULL;
  ND_OK_OR_FAIL(nd_problem_create(read, degree, &p));
  ND_OK_OR_FAIL(nd_problem_create(made, degree, &q));
  ND_OK_OR_FAIL(nd_mesh_destroy(&read));
  ND_OK_OR_FAIL(nd_mesh_destroy(&made));
  for (int k = 0; k < 2; ++k) {
    ND_OK_OR_FAIL(nd_problem_set_material(k ? q : p, 2.0, 0.3, 1.5));
    ND_OK_OR_FAIL(nd_problem_set_dirichlet(k ? q : p, 5));
  }
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(q, &nn));
  double *x = malloc(sizeof(double) * (size_t)(nn * dim));
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(q, nn, x));
  const int which[3] = {ND_MATRIX_MASS, ND_MATRIX_STIFFNESS, ND_MATRIX_LUMPED_MASS};
  for (int w = 0; w < 3; ++w) {
    double *A = dense_by_position(p, which[w], dim, x, nn), *B = dense_by_position(q, which[w], dim, x, nn);
    double diff = 0, size = 0;
    for (int64_t i = 0; i < nn * dim * nn * dim; ++i) diff = fmax(diff, fabs(A[i] - B[i])), size = fmax(size, fabs(B[i]));
    /* the same cells, their vertices in another order: the same integrals
       summed in another order, a few ulps apart */
    ck_assert_msg(diff <= 1e-14 * size, "%s: %dD Q%d operator %d: %.3g of %.3g", path, dim, degree, which[w], diff,
                  size);
    free(A), free(B);
  }
  free(x);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}

START_TEST(gmsh_reads_quadrilaterals_and_hexahedra) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  char path[] = "/tmp/nd_quads_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  write_grid_msh(path, dim, degree, 0);
  same_as_generated(path, dim, degree);
  if (degree == 2) { /* a curved element: refused */
    nd_mesh read = NULL;
    write_grid_msh(path, dim, degree, 1);
    ck_assert_int_eq(nd_mesh_read_gmsh(path, &read), ND_ERR_FORMAT);
    ck_assert_msg(strstr(nd_last_error(), "curved") != NULL, "%s", nd_last_error());
  }
  remove(path);
}
END_TEST

/* MSH 4.1: the 2 x 1 quadrilaterals, entities carrying the physical groups
   (the curve x = 0: group 5; the surface: group 1), node and element blocks */
START_TEST(gmsh_41_reads_quadrilaterals) {
  char path[] = "/tmp/nd_quads_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  nd_test_write_file(path,
                     "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                     "$Entities\n0 1 1 0\n1 0 0 0 0 1 0 1 5 0\n1 0 0 0 2 1 0 1 1 0\n$EndEntities\n"
                     "$Nodes\n1 6 1 6\n2 1 0 6\n1\n2\n3\n4\n5\n6\n"
                     "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n$EndNodes\n"
                     "$Elements\n2 3 1 3\n1 1 1 1\n1 4 1\n2 1 3 2\n2 1 2 5 4\n3 2 3 6 5\n$EndElements\n");
  for (int degree = 1; degree <= 2; ++degree) same_as_generated(path, 2, degree);
  remove(path);
}
END_TEST

/* (mixed meshes: tests/test_mixed.c) */
START_TEST(gmsh_refuses_serendipity) {
  char path[] = "/tmp/nd_quads_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  nd_mesh m = NULL;
  nd_test_write_file(path,
                     "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
                     "5 0.5 0 0\n6 1 0.5 0\n7 0.5 1 0\n8 0 0.5 0\n"
                     "$EndNodes\n$Elements\n1\n1 16 2 1 1 1 2 3 4 5 6 7 8\n$EndElements\n");
  ck_assert_int_eq(nd_mesh_read_gmsh(path, &m), ND_ERR_FORMAT);
  ck_assert_msg(strstr(nd_last_error(), "serendipity") != NULL, "%s", nd_last_error());
  ck_assert_ptr_null(m);
  remove(path);
}
END_TEST

/* Gmsh's own 9-node quadrilateral and 27-node hexahedron (one cell each,
   tests/fixtures/q2_cell.geo, written by gmsh 4.8 with -order 2): the
   reader checks each of the element's other nodes against the mean of the
   corners its table (gmsh.cpp's kQuad9, kHex27) says, so a wrong table
   refuses the file; then the Q2 space's 9 (27) nodes are gmsh's, one to one
   by position. The tolerance: gmsh places these nodes through its curves'
   parametrizations, 1.3e-12 off the means here (the reader's 1e-9 of the
   cell's extent); a node of another place is off by a quarter of an edge
   at least. */
static int64_t read_msh41_nodes(const char *path, double *x, int64_t room) {
  FILE *f = fopen(path, "r");
  ck_assert_ptr_nonnull(f);
  char line[256];
  while (fgets(line, sizeof line, f) && strncmp(line, "$Nodes", 6) != 0) {
  }
  long blocks = 0, total = 0, tag_min = 0, tag_max = 0;
  ck_assert_int_eq(fscanf(f, "%ld %ld %ld %ld", &blocks, &total, &tag_min, &tag_max), 4);
  ck_assert(total <= room && tag_min == 1 && tag_max == total); /* (gmsh numbers them 1..n) */
  for (long b = 0; b < blocks; ++b) {
    long edim = 0, etag = 0, param = 0, n = 0, tags[32];
    ck_assert_int_eq(fscanf(f, "%ld %ld %ld %ld", &edim, &etag, &param, &n), 4);
    ck_assert(n <= 32 && param == 0);
    for (long i = 0; i < n; ++i) ck_assert_int_eq(fscanf(f, "%ld", &tags[i]), 1);
    for (long i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) ck_assert_int_eq(fscanf(f, "%lf", &x[(tags[i] - 1) * 3 + k]), 1);
  }
  fclose(f);
  return total;
}

START_TEST(gmsh_q2_node_order_is_gmsh_s) {
  const int dim = 2 + _i;
  const char *path = dim == 2 ? ND_FIXTURE_DIR "/q2_quad.msh" : ND_FIXTURE_DIR "/q2_hex.msh";
  double xg[27 * 3];
  const int64_t ng = read_msh41_nodes(path, xg, 27);
  ck_assert_int_eq(ng, dim == 2 ? 9 : 27);
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(path, &m));
  int64_t cells = 0, facets = 0;
  ND_OK_OR_FAIL(nd_mesh_get_cell_count(m, &cells));
  ND_OK_OR_FAIL(nd_mesh_get_region_size(m, 5, &facets));
  ck_assert_int_eq(cells, 1);
  ck_assert_int_eq(facets, 1); /* (its 3- or 9-node facet read as the cell's) */
  ND_OK_OR_FAIL(nd_problem_create(m, 2, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  ck_assert_int_eq(n, ng);
  double x[27 * 3];
  int taken[27] = {0};
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  const double extent = 3.0; /* the cell's */
  for (int64_t g = 0; g < ng; ++g) {
    int64_t twin = -1;
    for (int64_t i = 0; i < n; ++i) {
      double d = 0;
      for (int k = 0; k < dim; ++k) d = fmax(d, fabs(x[i * dim + k] - xg[g * 3 + k]));
      if (d <= 1e-9 * extent) twin = i;
    }
    ck_assert_msg(twin >= 0 && !taken[twin], "gmsh's node %lld (%g, %g, %g) is not one of the space's",
                  (long long)g + 1, xg[g * 3], xg[g * 3 + 1], xg[g * 3 + 2]);
    taken[twin] = 1;
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* ---- refusals -------------------------------------------------------------- */

START_TEST(refusals) {
  nd_mesh m = NULL;
  const double sq[8] = {0, 0, 1, 0, 1, 1, 0, 1};
  const int64_t ccw[4] = {0, 1, 2, 3}, cw[4] = {0, 3, 2, 1}, crossed[4] = {0, 1, 3, 2};
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  ck_assert_int_eq(nd_mesh_create_cells(2, 7, 4, sq, 1, ccw, &m), ND_ERR_VALUE);
  ck_assert_ptr_null(m);
  ck_assert_int_eq(nd_mesh_create_cells(3, ND_CELL_QUADRILATERAL, 4, sq, 1, ccw, &m), ND_ERR_DIMENSION);
  ck_assert_int_eq(nd_mesh_create_cells(2, ND_CELL_HEXAHEDRON, 4, sq, 1, ccw, &m), ND_ERR_DIMENSION);
  ck_assert_int_eq(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 1, cw, &m), ND_ERR_DEGENERATE);
  ck_assert_int_eq(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 1, crossed, &m), ND_ERR_DEGENERATE);
  ck_assert_int_eq(nd_mesh_create_rectangle_cells(2, 2, lo, hi, ND_CELL_HEXAHEDRON, &m), ND_ERR_VALUE);
  ck_assert_int_eq(nd_mesh_create_box_cells(2, 2, 2, lo, hi, ND_CELL_QUADRILATERAL, &m), ND_ERR_VALUE);
  ck_assert_int_eq(nd_mesh_create_rectangle_cells(2, 2, lo, NULL, ND_CELL_QUADRILATERAL, &m), ND_ERR_NULL);
  ck_assert_int_eq(nd_mesh_create_cells(2, ND_CELL_QUADRILATERAL, 4, sq, 1, ccw, NULL), ND_ERR_NULL);
  /* boundary facets by their vertices */
  for (int dim = 2; dim <= 3; ++dim) {
    if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(2, 2, lo, hi, ND_CELL_QUADRILATERAL, &m));
    if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box_cells(2, 2, 2, lo, hi, ND_CELL_HEXAHEDRON, &m));
    int64_t n_facets = 0;
    /* a facet by its vertices: 2 (a segment) or 4 (a hexahedron's face), in
       any order; the grid's vertex (i, j, k) is i + 3 j + 9 k: the face
       z = 0 of the first cell, a diagonal of it not a facet */
    const int64_t face[4] = {4, 0, 3, 1}, segment[2] = {1, 0}, diagonal[2] = {0, 4};
    ND_OK_OR_FAIL(nd_mesh_set_region(m, 2, 1, dim == 2 ? segment : face));
    ND_OK_OR_FAIL(nd_mesh_get_region_size(m, 2, &n_facets));
    ck_assert_int_eq(n_facets, 1);
    ck_assert_int_eq(nd_mesh_set_region(m, 3, 1, dim == 2 ? diagonal : (const int64_t[4]){0, 1, 4, 13}), ND_ERR_REGION);
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  }
}
END_TEST

/* Mass redistribution on Q cells keeps the mass: the entries of M and of
   its lumped diagonal (HRZ of the redistributed element masses) sum to
   rho |Omega| per component, the contact nodes' rows are 0, the lumped
   diagonal positive elsewhere */
START_TEST(redistribution_keeps_the_mass) {
  const int dim = 2 + _i / 2, degree = 1 + _i % 2;
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, rho = 1.5;
  const double blo[3] = {-1, -1, -1}, bhi[3] = {2, 1e-9, 2}, point[3] = {0, -0.1, 0}, normal[3] = {0, 1, 0};
  nd_mesh m = NULL;
  nd_problem p = NULL;
  if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(2, 2, lo, hi, ND_CELL_QUADRILATERAL, &m));
  if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box_cells(2, 2, 2, lo, hi, ND_CELL_HEXAHEDRON, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.3, rho));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, point, normal));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 0.0, 0.1));
  ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.01));
  ND_OK_OR_FAIL(nd_problem_setup(p));
  csr M = get_matrix(p, ND_MATRIX_MASS), L = get_matrix(p, ND_MATRIX_LUMPED_MASS);
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *x = malloc(sizeof(double) * (size_t)(nn * dim));
  int64_t *node = malloc(sizeof(int64_t) * (size_t)M.n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, x));
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, M.n, node, NULL));
  double sum = 0, sum_lumped = 0, on_contact = 0, lowest = INFINITY;
  for (int64_t r = 0; r < M.n; ++r) {
    const int contact = x[node[r] * dim + 1] == 0; /* the bottom, y = 0 */
    for (int64_t k = M.ptr[r]; k < M.ptr[r + 1]; ++k) {
      sum += M.val[k];
      if (contact) on_contact = fmax(on_contact, fabs(M.val[k]));
    }
    for (int64_t k = L.ptr[r]; k < L.ptr[r + 1]; ++k) {
      sum_lumped += L.val[k];
      if (contact) on_contact = fmax(on_contact, fabs(L.val[k]));
      else lowest = fmin(lowest, L.val[k]);
    }
  }
  const double exact = rho * dim; /* |Omega| = 1 */
  printf("redistributed %dD Q%d: sum M = %.17g, sum lumped = %.17g, smallest off contact %.3g (exact %g)\n", dim, degree,
         sum, sum_lumped, lowest, exact);
  ck_assert(on_contact == 0);
  /* the redistribution keeps each cell's mass up to its small solves' round-off */
  ck_assert_msg(fabs(sum - exact) <= 1e-12 * exact, "sum M %.17g", sum);
  ck_assert_msg(fabs(sum_lumped - exact) <= 1e-12 * exact, "sum lumped %.17g", sum_lumped);
  ck_assert(lowest > 0);
  free(x), free(node);
  csr_free(&M), csr_free(&L);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("quads");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_loop_test(tc, strip_is_the_bar, 0, 4);
  tcase_add_loop_test(tc, strip_bounces_as_the_bar, 0, 4);
  tcase_add_loop_test(tc, normal_impact_with_friction_is_the_bar, 0, 4);
  tcase_add_test(tc, vtu_of_hexahedra_in_contact);
  tcase_add_loop_test(tc, patch_test_on_distorted_cells, 0, 4);
  tcase_add_loop_test(tc, mass_is_rho_times_volume, 0, 4);
  tcase_add_loop_test(tc, gmsh_reads_quadrilaterals_and_hexahedra, 0, 4);
  tcase_add_test(tc, gmsh_41_reads_quadrilaterals);
  tcase_add_test(tc, gmsh_refuses_serendipity);
  tcase_add_loop_test(tc, gmsh_q2_node_order_is_gmsh_s, 0, 2);
  tcase_add_test(tc, refusals);
  tcase_add_loop_test(tc, redistribution_keeps_the_mass, 0, 4);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
