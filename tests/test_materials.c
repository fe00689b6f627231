/* Several materials, one per cell region (docs/design.md §10.6), through the
 * public API: a wave splits at the interface of a bar of two materials into
 * the exact transmitted and reflected waves; a layered column at rest on the
 * obstacle carries its weight; the Gmsh reader makes cell regions of the
 * physical groups of cells (MSH 2.2 and 4.1); regions of one material give
 * the single-material trajectory bit for bit. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

static int64_t nodes(nd_problem p) {
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  return n;
}

/* the smooth pulse (1 - s^2)^3 on |s| < 1, s = (x - 1)/0.5 */
static double pulse(double x) {
  const double s = (x - 1) / 0.5;
  return fabs(s) < 1 ? 1e-3 * (1 - s * s) * (1 - s * s) * (1 - s * s) : 0.0;
}

START_TEST(wave_splits_at_the_interface) {
  /* The bar (0, L1) of E1, rho1 joined at L1 to (L1, L1 + L2) of E2, rho2,
     P1, lumped mass, the central difference (explicit Newmark) at Courant
     number 1 in both: h_i = c_i tau. Each part is then the exact
     d'Alembert recurrence u_j^{n+1} + u_j^{n-1} = u_{j-1}^n + u_{j+1}^n,
     and the interface node (mass (Z1 + Z2) tau/2, springs Z_i/tau, with
     rho_i h_i = Z_i tau and E_i/h_i = Z_i/tau) gives
       (Z1 + Z2)(G(n+1) - G(n-1)) = (Z1 - Z2)(F(n+1) - F(n-1))
     for u = F(n - j) + G(n + j) on the left and H(n - j) on the right: the
     reflected wave is R F, the transmitted one T F, with the continuum's
       R = (Z1 - Z2)/(Z1 + Z2),   T = 1 + R = 2 Z1/(Z1 + Z2)   (displacement),
     Z = sqrt(E rho). So the nodal displacements are the closed form
       u(x, t) = f(x - c1 t) + R f(2 L1 - x - c1 t)        x <= L1,
               = T f(L1 - c1 (t - (x - L1)/c2))             x >= L1,
     to round-off (no dispersion at Courant number 1): checked to 1e-9 of
     the pulse's height after the pulse has fully split. */
  const double E1 = 1, rho1 = 1, E2 = 8, rho2 = 2;
  const double c1 = sqrt(E1 / rho1), c2 = sqrt(E2 / rho2), Z1 = sqrt(E1 * rho1), Z2 = sqrt(E2 * rho2);
  const double R = (Z1 - Z2) / (Z1 + Z2), T = 2 * Z1 / (Z1 + Z2);
  const double tau = 0.01, h1 = c1 * tau, h2 = c2 * tau;
  const int n1 = 200, n2 = 200, steps = 200; /* L1 = 2, L2 = 4; t = 2: the split pulse inside */
  const double L1 = n1 * h1;
  const int64_t nv = n1 + n2 + 1;
  double *x = malloc(sizeof(double) * (size_t)nv), *u0 = malloc(sizeof(double) * (size_t)nv),
         *v0 = malloc(sizeof(double) * (size_t)nv), *u = malloc(sizeof(double) * (size_t)nv);
  int64_t *cells = malloc(sizeof(int64_t) * (size_t)(2 * (n1 + n2))), *right = malloc(sizeof(int64_t) * (size_t)n2);
  for (int64_t j = 0; j < nv; ++j) x[j] = j <= n1 ? j * h1 : L1 + (double)(j - n1) * h2;
  for (int64_t c = 0; c < n1 + n2; ++c) cells[2 * c] = c, cells[2 * c + 1] = c + 1;
  for (int64_t k = 0; k < n2; ++k) right[k] = n1 + k;
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_create(1, nv, x, n1 + n2, cells, &m));
  ND_OK_OR_FAIL(nd_mesh_set_cell_region(m, 2, n2, right));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, E1, 0, rho1));
  ND_OK_OR_FAIL(nd_problem_set_material_region(p, 2, E2, 0, rho2));
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  const double explicit_newmark[2] = {0, 0.5};
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, explicit_newmark));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  /* The critical step: Gershgorin on the lumped M^-1 K (every row 2/tau^2 on
     the diagonal, 2/tau^2 off it, the interface's too) gives omega_max <= 2/tau,
     tau_c >= tau; the alternating mode nearly reaches it. */
  double tau_c = 0;
  ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
  printf("bar of two materials: tau_c / tau = %.9f (Courant number 1 in both)\n", tau_c / tau);
  ck_assert_double_ge(tau_c, 0.98 * tau);
  ck_assert_double_le(tau_c, 1.02 * tau);
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0)); /* at tau_c itself */
  /* u^1 = F(1 - j) exactly: v0 the centred difference of the wave in time
     (with a^0 = (u_{j-1} - 2 u_j + u_{j+1})/tau^2, the pulse's nodes inside part 1) */
  for (int64_t j = 0; j < nv; ++j) {
    u0[j] = pulse(x[j]);
    v0[j] = j < n1 ? (pulse(x[j] - h1) - pulse(x[j] + h1)) / (2 * tau) : 0.0;
  }
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nv, u0, v0));
  for (int s = 0; s < steps; ++s) ND_OK_OR_FAIL(nd_step(p));
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nv, u));
  const double t = steps * tau;
  double err = 0, transmitted = 0, reflected = 0;
  for (int64_t j = 0; j < nv; ++j) {
    const double exact = x[j] <= L1 ? pulse(x[j] - c1 * t) + R * pulse(2 * L1 - x[j] - c1 * t)
                                    : T * pulse(L1 - c1 * (t - (x[j] - L1) / c2));
    err = fmax(err, fabs(u[j] - exact));
    if (x[j] > L1) transmitted = fmax(transmitted, fabs(u[j]));
    else reflected = fmax(reflected, fabs(u[j]));
  }
  printf("  T = %.6f, R = %.6f: peaks %.9f and %.9f of the incident's, max error %.3g of it\n", T, R,
         transmitted / 1e-3, reflected / 1e-3, err / 1e-3);
  ck_assert_double_le(err, 1e-9 * 1e-3);
  ck_assert_double_le(fabs(transmitted / 1e-3 - fabs(T)), 1e-6); /* the peak sits on a node: s = 0 */
  ck_assert_double_le(fabs(reflected / 1e-3 - fabs(R)), 1e-6);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  free(x), free(u0), free(v0), free(u), free(cells), free(right);
}
END_TEST

/* nx x ny squares of [0, W] x [0, H], two triangles each (cell 2 (j nx + i)
   and the next), in `layers` horizontal layers: cell regions 1, 2, ...
   from the bottom; facet region 1 the bottom y = 0 */
static nd_mesh layered_rectangle(int nx, int ny, double W, double H, int layers) {
  const int64_t nv = (int64_t)(nx + 1) * (ny + 1), nc = 2 * (int64_t)nx * ny;
  double *xy = malloc(sizeof(double) * (size_t)(2 * nv));
  int64_t *cells = malloc(sizeof(int64_t) * (size_t)(3 * nc)), *in = malloc(sizeof(int64_t) * (size_t)nc);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const int64_t v = (int64_t)j * (nx + 1) + i;
      xy[2 * v] = W * i / nx, xy[2 * v + 1] = H * j / ny;
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int64_t c = 2 * ((int64_t)j * nx + i), a = (int64_t)j * (nx + 1) + i, b = a + 1, d = a + nx + 1, e = d + 1;
      const int64_t tri[6] = {a, b, e, a, e, d};
      memcpy(&cells[3 * c], tri, sizeof tri);
    }
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create(2, nv, xy, nc, cells, &m));
  for (int l = 1; l <= layers; ++l) {
    int64_t n = 0;
    for (int64_t c = 0; c < nc; ++c)
      if ((c / 2 / nx) * layers / ny + 1 == l) in[n++] = c;
    ND_OK_OR_FAIL(nd_mesh_set_cell_region(m, l, n, in));
  }
  const double lo[2] = {-1, -1e-9}, hi[2] = {W + 1, 1e-9};
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, lo, hi));
  free(xy), free(cells), free(in);
  return m;
}

/* three layers: (E, nu, rho), and a default material no cell takes */
static const double kLayers[3][3] = {{100, 0.3, 1}, {400, 0.25, 3}, {50, 0.2, 0.5}};
static const double kDefault[3] = {70, 0.35, 2};

/* 1_y' M 1_y of the mass `which` (ND_MATRIX_MASS, ND_MATRIX_LUMPED_MASS; every
   DOF free) and, unless f is NULL, the nodal forces f = -g M 1_y */
static double mass_y(nd_problem p, int which, double g, double *f) {
  int64_t n = 0, nnz = 0;
  ND_OK_OR_FAIL(nd_problem_get_matrix(p, which, &n, &nnz, NULL, NULL, NULL));
  int64_t *ptr = malloc(sizeof(int64_t) * (size_t)(n + 1)), *col = malloc(sizeof(int64_t) * (size_t)nnz),
          *node = malloc(sizeof(int64_t) * (size_t)n);
  double *val = malloc(sizeof(double) * (size_t)nnz);
  int *comp = malloc(sizeof(int) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_matrix(p, which, &n, &nnz, ptr, col, val));
  ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
  ck_assert_int_eq(n, 2 * nodes(p));
  double mass = 0;
  for (int64_t i = 0; i < n; ++i)
    for (int64_t k = ptr[i]; k < ptr[i + 1]; ++k)
      if (comp[i] == 1 && comp[col[k]] == 1) {
        if (f) f[2 * node[i] + 1] -= g * val[k];
        mass += val[k];
      }
  free(ptr), free(col), free(node), free(val), free(comp);
  return mass;
}

/* gravity g downwards as nodal forces -g M 1_y: the weight of each cell's
   own density; returns the total weight g 1_y' M 1_y */
static double gravity(nd_problem p, double g) {
  double *f = calloc((size_t)(2 * nodes(p)), sizeof(double));
  const double weight = g * mass_y(p, ND_MATRIX_MASS, g, f);
  ND_OK_OR_FAIL(nd_problem_set_nodal_forces(p, nodes(p), f));
  free(f);
  return weight;
}

START_TEST(layered_column_carries_its_weight) {
  /* A column [0, 1] x [0, 3] of three layers of different stiffness and
     density on the plane y = 0, under gravity, implicit Euler (theta = 1,
     large steps: it settles). Each step's rows summed over the vertical
     DOFs (K and s_q vanish on a translation): (Pi^{n+1} - Pi^n)/tau =
     f^{n+1} - W, Pi the momentum, f the contact resultant, W the weight;
     at rest f = W to Newton's tolerance (relative 1e-10, the default). The weight itself
     is g 1_y' M 1_y = g sum_i rho_i V_i: the mass matrix integrates each
     cell's own density exactly (and so do its HRZ lumping and its
     redistribution, which keep each cell's mass). The default material is no layer's: the
     contact rows s_q and gamma_q = gamma0 h_K E/E_K are the bottom layer's,
     so gamma0* (ND_GAMMA0_LIMIT) is the bottom material's alone times E_K/E
     (S_K scales by E/E_K, K_e stays), to the eigensolver's round-off. */
  const double g = 9.81, tau = 2, theta = 1, up[2] = {0, 1}, origin[2] = {0, 0};
  for (int degree = 1; degree <= 2; ++degree) {
    nd_mesh m = layered_rectangle(3, 9, 1.0, 3.0, 3);
    nd_problem p = NULL;
    ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
    ND_OK_OR_FAIL(nd_mesh_destroy(&m));
    ND_OK_OR_FAIL(nd_problem_set_material(p, kLayers[0][0], kLayers[0][1], kLayers[0][2]));
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, origin, up));
    ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
    const double bottom_alone = scalar(p, ND_GAMMA0_LIMIT);
    ND_OK_OR_FAIL(nd_problem_set_material(p, kDefault[0], kDefault[1], kDefault[2]));
    for (int l = 0; l < 3; ++l)
      ND_OK_OR_FAIL(nd_problem_set_material_region(p, l + 1, kLayers[l][0], kLayers[l][1], kLayers[l][2]));
    const double limit = scalar(p, ND_GAMMA0_LIMIT), expected = bottom_alone * kLayers[0][0] / kDefault[0];
    printf("layered column, P%d: gamma0* %.15g, the bottom material's alone times E_K/E %.15g\n", degree, limit,
           expected);
    ck_assert_double_le(fabs(limit - expected), 1e-12 * expected);
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_THETA, &theta));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
    const double W = gravity(p, g), exact = g * (kLayers[0][2] + kLayers[1][2] + kLayers[2][2]) * 1.0;
    ck_assert_double_le(fabs(W - exact), 1e-12 * exact);
    /* the HRZ lumping and the mass redistribution keep each cell's mass */
    ck_assert_double_le(fabs(g * mass_y(p, ND_MATRIX_LUMPED_MASS, g, NULL) - exact), 1e-12 * exact);
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
    ck_assert_double_le(fabs(g * mass_y(p, ND_MATRIX_MASS, g, NULL) - exact), 1e-12 * exact);
    ck_assert_double_le(fabs(g * mass_y(p, ND_MATRIX_LUMPED_MASS, g, NULL) - exact), 1e-12 * exact);
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 0));
    double f = 0, pi = 0, worst = 0;
    for (int s = 0; s < 60; ++s) {
      ND_OK_OR_FAIL(nd_step(p));
      const double pi_new = scalar(p, ND_MOMENTUM_Y);
      f = scalar(p, ND_CONTACT_FORCE);
      worst = fmax(worst, fabs((pi_new - pi) / tau - (f - W)));
      pi = pi_new;
    }
    printf("layered column, P%d: contact force %.15g, weight %.15g (sum rho_i g V_i %.15g), |f - W|/W %.2g, "
           "momentum identity off by %.2g W, last |Pi| %.2g\n",
           degree, f, W, exact, fabs(f - W) / W, worst / W, fabs(pi));
    ck_assert_double_le(worst, 1e-9 * W);
    ck_assert_double_le(fabs(f - W), 1e-9 * W);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

static void expect_cell_regions(const char *path, const char *text, const int *expected) {
  nd_test_write_file(path, text);
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(path, &m));
  int64_t n = 0, facets = 0;
  ND_OK_OR_FAIL(nd_mesh_get_cell_count(m, &n));
  ck_assert_int_eq(n, 4);
  int region[4];
  ND_OK_OR_FAIL(nd_mesh_get_cell_regions(m, 4, region));
  for (int c = 0; c < 4; ++c) ck_assert_int_eq(region[c], expected[c]);
  ND_OK_OR_FAIL(nd_mesh_get_region_size(m, 1, &facets)); /* the facet group stays a facet region */
  ck_assert_int_eq(facets, 2);
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
}

START_TEST(gmsh_physical_groups_of_cells) {
  /* [0, 2] x [0, 1] in four triangles: the left square's two in group 5,
     then one in 7 (2.2) or in a surface of groups 3 and 9 (4.1: the largest
     tag), one in none; the bottom's two lines in group 1 */
  char path[] = "/tmp/nd_materials_XXXXXX";
  const int fd = mkstemp(path);
  ck_assert_int_ge(fd, 0);
  close(fd);
  const char *v2 = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                   "$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n6 2 1 0\n$EndNodes\n"
                   "$Elements\n6\n1 1 2 1 1 1 2\n2 1 2 1 1 2 3\n3 2 2 5 1 1 2 5\n4 2 2 5 1 1 5 4\n"
                   "5 2 2 7 2 2 3 6\n6 2 2 0 3 2 6 5\n$EndElements\n";
  const int expected2[4] = {5, 5, 7, 0};
  expect_cell_regions(path, v2, expected2);
  const char *v4 = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                   "$Entities\n0 1 3 0\n"
                   "1 0 0 0 2 0 0 1 1 0\n"
                   "1 0 0 0 1 1 0 1 5 0\n3 1 0 0 2 1 0 2 3 9 0\n4 1 0 0 2 1 0 0 0\n"
                   "$EndEntities\n"
                   "$Nodes\n1 6 1 6\n2 1 0 6\n1\n2\n3\n4\n5\n6\n"
                   "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n$EndNodes\n"
                   "$Elements\n4 6 1 6\n1 1 1 2\n1 1 2\n2 2 3\n2 1 2 2\n3 1 2 5\n4 1 5 4\n"
                   "2 3 2 1\n5 2 3 6\n2 4 2 1\n6 2 6 5\n$EndElements\n";
  const int expected4[4] = {5, 5, 9, 0};
  expect_cell_regions(path, v4, expected4);
  unlink(path);
}
END_TEST

/* the layered column dropped onto the plane (v0 = -1), its three regions
   given `mats` (NULL: none); `base` the default material */
static nd_problem column(const double *base, const double (*mats)[3], int scheme, const double *params) {
  nd_mesh m = layered_rectangle(3, 9, 1.0, 3.0, 3);
  nd_problem p = NULL;
  const double up[2] = {0, 1}, below[2] = {0, -0.001};
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, base[0], base[1], base[2]));
  for (int l = 0; mats && l < 3; ++l)
    ND_OK_OR_FAIL(nd_problem_set_material_region(p, l + 1, mats[l][0], mats[l][1], mats[l][2]));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, below, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  const int explicit_scheme = scheme == ND_SCHEME_NEWMARK && params[0] == 0;
  if (explicit_scheme) ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, explicit_scheme ? 2e-4 : 2e-3));
  const int64_t n = nodes(p);
  double *v0 = calloc((size_t)(2 * n), sizeof(double));
  for (int64_t i = 0; i < n; ++i) v0[2 * i + 1] = -1;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v0));
  free(v0);
  return p;
}

START_TEST(one_material_in_regions_is_bitwise_one_material) {
  /* Regions all of the default's material take the single-material path;
     regions all of another material than the default's but with its E (so
     gamma_q = gamma0 h_K E/E_K is gamma0 h_K) take the per-cell path: both
     must give the single material's trajectory bit for bit. */
  const double mat[3] = {100, 0.3, 1}, other[3] = {100, 0.1, 7};
  const double same[3][3] = {{100, 0.3, 1}, {100, 0.3, 1}, {100, 0.3, 1}};
  const double hybrid[2] = {0, 0}, explicit_newmark[2] = {0, 0.5};
  const double *params[2] = {hybrid, explicit_newmark};
  const int schemes[2] = {ND_SCHEME_HYBRID, ND_SCHEME_NEWMARK};
  for (int k = 0; k < 2; ++k) {
    nd_problem p[3] = {column(mat, NULL, schemes[k], params[k]), column(mat, same, schemes[k], params[k]),
                       column(other, same, schemes[k], params[k])};
    const int64_t n = 2 * nodes(p[0]);
    double *a = malloc(sizeof(double) * (size_t)n), *b = malloc(sizeof(double) * (size_t)n);
    double active = 0;
    for (int s = 0; s < 40; ++s)
      for (int i = 0; i < 3; ++i) {
        ND_OK_OR_FAIL(nd_step(p[i]));
        for (int field = ND_FIELD_DISPLACEMENT; field <= ND_FIELD_CONTACT_FORCE; ++field) {
          ND_OK_OR_FAIL(nd_get_field(p[0], field, n / 2, a));
          ND_OK_OR_FAIL(nd_get_field(p[i], field, n / 2, b));
          ck_assert_msg(memcmp(a, b, sizeof(double) * (size_t)n) == 0, "scheme %d, problem %d, step %d, field %d", k,
                        i, s, field);
        }
        if (i == 0) active = fmax(active, scalar(p[0], ND_ACTIVE_POINTS));
      }
    printf("one material in regions, %s: 40 steps bitwise, up to %g active points\n", k ? "explicit" : "hybrid",
           active);
    ck_assert_double_gt(active, 0);
    for (int i = 0; i < 3; ++i) ND_OK_OR_FAIL(nd_problem_destroy(&p[i]));
    free(a), free(b);
  }
}
END_TEST

START_TEST(stress_and_restart_take_the_cells_material) {
  /* The bar (0, 1) | (1, 2) of E = 1 | 4 at the uniform stress s = 0.3 of
     uniaxial tension: u = s x / E1, then s (x - 1)/E2 past the interface
     (continuous, piecewise linear: exact for P1 and P2). Each cell's stress
     in the VTU is s to round-off. Then a checkpoint: a problem of the same
     materials resumes it bit for bit; one of another region material refuses
     it (ND_ERR_STATE, naming the material). */
  const double E1 = 1, E2 = 4, s = 0.3, tau = 0.01;
  for (int degree = 1; degree <= 2; ++degree) {
    nd_problem p[3] = {NULL, NULL, NULL};
    for (int k = 0; k < 3; ++k) {
      nd_mesh m = NULL;
      const int64_t right[3] = {3, 4, 5};
      ND_OK_OR_FAIL(nd_mesh_create_interval(6, 0.0, 2.0, &m));
      ND_OK_OR_FAIL(nd_mesh_set_cell_region(m, 1, 3, right));
      ND_OK_OR_FAIL(nd_problem_create(m, degree, &p[k]));
      ND_OK_OR_FAIL(nd_mesh_destroy(&m));
      ND_OK_OR_FAIL(nd_problem_set_material(p[k], E1, 0, 1));
      ND_OK_OR_FAIL(nd_problem_set_material_region(p[k], 1, k == 2 ? 2 * E2 : E2, 0, 3));
      ND_OK_OR_FAIL(nd_problem_set_scheme(p[k], ND_SCHEME_HYBRID, NULL));
      ND_OK_OR_FAIL(nd_problem_set_timestep(p[k], tau));
    }
    const int64_t n = nodes(p[0]);
    double *x = malloc(sizeof(double) * (size_t)n), *u = malloc(sizeof(double) * (size_t)n),
           *a = malloc(sizeof(double) * (size_t)n), *b = malloc(sizeof(double) * (size_t)n);
    ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p[0], n, x));
    for (int64_t i = 0; i < n; ++i) u[i] = x[i] <= 1 ? s * x[i] / E1 : s / E1 + s * (x[i] - 1) / E2;
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p[0], n, u, NULL));
    char vtu[64];
    snprintf(vtu, sizeof vtu, "/tmp/nd_materials_%d.vtu", (int)getpid());
    ND_OK_OR_FAIL(nd_problem_write_vtu(p[0], vtu));
    static char text[1 << 16];
    FILE *fp = fopen(vtu, "r");
    ck_assert_ptr_nonnull(fp);
    text[fread(text, 1, sizeof text - 1, fp)] = '\0';
    fclose(fp);
    remove(vtu);
    const char *at = strstr(text, "Name=\"stress\"");
    ck_assert_ptr_nonnull(at);
    at = strchr(at, '>') + 1;
    double worst = 0;
    for (int c = 0; c < 6; ++c) {
      char *end = NULL;
      worst = fmax(worst, fabs(strtod(at, &end) - s));
      ck_assert_msg(end != at, "cell %d: no stress", c);
      at = end;
    }
    printf("bar of two materials in tension, P%d: every cell's stress %g to %.2g\n", degree, s, worst);
    ck_assert_double_le(worst, 1e-14 * 4 * s); /* a few ulps of E |grad u| */
    /* the restart */
    for (int k = 0; k < 5; ++k) ND_OK_OR_FAIL(nd_step(p[0]));
    int64_t size = 0;
    unsigned char *buf = nd_test_checkpoint(p[0], &size);
    ND_OK_OR_FAIL(nd_problem_load_state(p[1], size, buf));
    ck_assert_int_eq(nd_problem_load_state(p[2], size, buf), ND_ERR_STATE);
    ck_assert_msg(strstr(nd_last_error(), "material") != NULL, "%s", nd_last_error());
    for (int k = 0; k < 5; ++k) {
      ND_OK_OR_FAIL(nd_step(p[0]));
      ND_OK_OR_FAIL(nd_step(p[1]));
      ND_OK_OR_FAIL(nd_get_field(p[0], ND_FIELD_DISPLACEMENT, n, a));
      ND_OK_OR_FAIL(nd_get_field(p[1], ND_FIELD_DISPLACEMENT, n, b));
      ck_assert(memcmp(a, b, sizeof(double) * (size_t)n) == 0);
    }
    free(buf), free(x), free(u), free(a), free(b);
    for (int k = 0; k < 3; ++k) ND_OK_OR_FAIL(nd_problem_destroy(&p[k]));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("materials");
  TCase *tc = tcase_create("materials");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, wave_splits_at_the_interface);
  tcase_add_test(tc, layered_column_carries_its_weight);
  tcase_add_test(tc, gmsh_physical_groups_of_cells);
  tcase_add_test(tc, one_material_in_regions_is_bitwise_one_material);
  tcase_add_test(tc, stress_and_restart_take_the_cells_material);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
