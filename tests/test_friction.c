/* Friction (docs/design.md §10.2) on a block resting on the rigid plane:
 * the rectangle [0,2] x [0,1] (2D) or the box [0,2] x [0,1] x [0,1] (3D),
 * rho = 1, its lowest face the contact region, under gravity g = 1 tilted
 * by alpha along x (the slope of a plane inclined by alpha). Checked:
 *  - Coulomb's law at the points: when every active point slides, the
 *    tangential resultant is F times the normal one (2D: equal, exactly
 *    opposite to x; 3D: within the cone) for every scheme, P1 and P2;
 *  - the momentum along the slope is the impulse of gravity and friction,
 *    step by step, and the block accelerates at g sin(alpha) - F N/m with the
 *    step's N (g (sin - F cos) when N is the weight's share);
 *  - tan(alpha) < F: every point sticks, the block stops creeping (D_f and
 *    the mean displacement stay), friction carries m g sin(alpha);
 *  - Tresca: the tangential resultant is s times the contact length when
 *    the block slides, and it sticks below;
 *  - the hybrid scheme with Theta = 1: E_Theta + D_f - W never increases
 *    (to round-off), D_f >= 0 and non-decreasing;
 *  - a block launched at v0 stops after v0/(F g), having slid v0^2/(2 F g);
 *  - an oblique impact at gross slip (a disk, a ball): J_t = F J_n, and the
 *    spin is the angular impulse of the contact forces, step by step, as a
 *    rigid body's (oblique_impact_spin);
 *  - F = 0 with Theta = 0 is the frictionless method; a restart is bitwise;
 *  - a moving plane (slip is relative): body and plane carried along
 *    together are the static run shifted; a conveyor drags the resting
 *    block to its speed and carries it (momentum, the plane's work v dP,
 *    D_f = m v^2/2); the hybrid ledger with the plane's work W_obstacle,
 *    tangential part included, never increases; a restart is bitwise. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

typedef struct {
  int dim, degree, law;
  double coefficient, alpha, theta, tau;
  const nd_test_scheme *scheme;
  int quads; /* 1: quadrilaterals (hexahedra) on the same grid, 0 (default): simplices */
} block_spec;

/* the block's mass: rho = 1, volume 2 (area 2 in 2D, per unit thickness) */
static const double kMass = 2;

static nd_problem block(const block_spec *b) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const int coarse = b->degree == 2;
  if (b->dim == 2) {
    const double lo[2] = {0, 0}, hi[2] = {2, 1}, blo[2] = {-1, -1e-9}, bhi[2] = {3, 1e-9};
    if (b->quads) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(coarse ? 4 : 8, coarse ? 2 : 4, lo, hi,
                                                               ND_CELL_QUADRILATERAL, &m));
    else ND_OK_OR_FAIL(nd_mesh_create_rectangle(coarse ? 4 : 8, coarse ? 2 : 4, lo, hi, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  } else {
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1}, blo[3] = {-1, -1, -1e-9}, bhi[3] = {3, 2, 1e-9};
    if (b->quads) ND_OK_OR_FAIL(nd_mesh_create_box_cells(coarse ? 2 : 4, coarse ? 1 : 2, coarse ? 1 : 2, lo, hi,
                                                         ND_CELL_HEXAHEDRON, &m));
    else ND_OK_OR_FAIL(nd_mesh_create_box(coarse ? 2 : 4, coarse ? 1 : 2, coarse ? 1 : 2, lo, hi, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  }
  ND_OK_OR_FAIL(nd_problem_create(m, b->degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1e4, 0.3, 1));
  const double point[3] = {0, 0, 0}, normal2[2] = {0, 1}, normal3[3] = {0, 0, 1};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, point, b->dim == 2 ? normal2 : normal3));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, b->theta, 0));
  ND_OK_OR_FAIL(nd_problem_set_friction(p, 1, b->law, &b->coefficient));
  double g[3] = {sin(b->alpha), 0, 0};
  g[b->dim - 1] = -cos(b->alpha);
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, b->scheme->scheme, b->scheme->params));
  if (nd_test_is_explicit(b->scheme)) {
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
    double tau_c = 0;
    ND_OK_OR_FAIL(nd_problem_estimate_critical_timestep(p, &tau_c));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.5 * tau_c));
  } else {
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, b->tau));
  }
  return p;
}

/* the block's plane through (x, z) in 2D, (x, y, z) in 3D (z along its
   normal, up): a translation of the plane, whose tangential part the slip
   follows (docs/design.md §10.2) */
static void place_plane(nd_problem p, int dim, double x, double y, double z) {
  const double point2[2] = {x, z}, point3[3] = {x, y, z}, up2[2] = {0, 1}, up3[3] = {0, 0, 1};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, dim == 2 ? point2 : point3, dim == 2 ? up2 : up3));
}

/* every node's velocity (vx, 0[, 0]) */
static void launch(nd_problem p, int dim, double vx) {
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *v = calloc((size_t)(dim * nn), sizeof *v);
  for (int64_t i = 0; i < nn; ++i) v[dim * i] = vx;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v));
  free(v);
}

static const nd_test_scheme kTheta1 = {ND_SCHEME_THETA, {1, 0}}, kHybrid = {ND_SCHEME_HYBRID, {0, 0}};

/* Coulomb's law seen from the resultants: whenever every active point
   slides, |f_t| = F f_n in 2D (f_t along -x: the block slides down the
   slope), and |f_t| <= F f_n (the cone) in 3D; for every scheme (the
   explicit one too), P1, P2; on simplices (_i = 0) and Q cells (_i = 1). */
START_TEST(coulomb_tangential_is_F_times_normal) {
  const double F = 0.3;
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= (dim == 2 ? 2 : 1); ++degree)  /* (3D P2: the cone holds alike; its cost, not) */
      for (int k = 0; k < ND_TEST_N_SCHEMES; ++k) {
        const block_spec b = {dim, degree, ND_FRICTION_COULOMB, F, 0.5, 1, 2e-3, &nd_test_schemes[k], _i};
        nd_problem p = block(&b);
        int sliding_steps = 0;
        double worst = 0;
        const int steps = nd_test_is_explicit(b.scheme) ? 250 : 100;
        for (int n = 0; n < steps; ++n) {
          ND_OK_OR_FAIL(nd_step(p));
          const double fn = scalar(p, ND_CONTACT_FORCE_APPLIED), fx = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X),
                       fy = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_Y), fz = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_Z);
          /* (the points the step applied a normal value at: sliding + sticking) */
          const double stick = scalar(p, ND_STICKING_POINTS), slide = scalar(p, ND_SLIDING_POINTS);
          const double ft = sqrt(fx * fx + fy * fy + fz * fz);
          ck_assert_double_le(ft, F * fn * (1 + 1e-12) + 1e-300);  /* the cone, always */
          if (slide > 0 && stick == 0 && dim == 2) {
            ++sliding_steps;
            worst = fmax(worst, fabs(fx + F * fn) / (F * fn));
          }
        }
        if (dim == 2)
          printf("dim 2 %s%d scheme %d: %d steps all sliding, max |f_x + F f_n|/(F f_n) = %.2e\n", _i ? "Q" : "P",
                 degree, k, sliding_steps, worst);
        if (dim == 2) {
          ck_assert_int_gt(sliding_steps, 0);
          ck_assert_double_le(worst, 1e-12);
        }
        ck_assert_double_gt(scalar(p, ND_DISSIPATION_FRICTION), 0);
        ND_OK_OR_FAIL(nd_problem_destroy(&p));
      }
}
END_TEST

/* theta = 1: M (V^{n+1} - V^n) = tau (F - K_Theta U^{n+1} - N^{n+1}); summed
   over the x rows K_Theta drops out (it annihilates translations), so the
   momentum gains tau (m g sin(alpha) + f_t,x) a step, to round-off; and with
   every point sliding f_t,x = -F f_n, the acceleration is g sin - F f_n/m. */
START_TEST(coulomb_momentum_is_the_impulse) {
  const double F = 0.3, alpha = 0.5;
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, F, alpha, 1, 2e-3, &kTheta1, 0};
  nd_problem p = block(&b);
  double P = scalar(p, ND_MOMENTUM_X), worst = 0, fn_sum = 0;
  const int steps = 1000, from = 500;
  double P_from = 0;
  for (int n = 1; n <= steps; ++n) {
    ND_OK_OR_FAIL(nd_step(p));
    const double P_new = scalar(p, ND_MOMENTUM_X), fx = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X);
    const double impulse = b.tau * (kMass * sin(alpha) + fx);
    worst = fmax(worst, fabs(P_new - P - impulse));
    P = P_new;
    if (n == from) P_from = P;
    if (n > from) fn_sum += scalar(p, ND_CONTACT_FORCE_APPLIED);
    if (n > from) ck_assert_double_eq(scalar(p, ND_STICKING_POINTS), 0);
  }
  const double T = (steps - from) * b.tau, N = fn_sum / (steps - from);
  const double a = (P - P_from) / (kMass * T), a_law = sin(alpha) - F * N / kMass;
  const double a_rigid = sin(alpha) - F * cos(alpha);
  printf("momentum: max |dP - impulse| = %.2e; acceleration %.10f, g sin - F N/m = %.10f, g (sin - F cos) = %.10f "
         "(N/(m g cos) = %.8f)\n", worst, a, a_law, a_rigid, N / (kMass * cos(alpha)));
  ck_assert_double_le(worst, 1e-13 * kMass);
  /* (the identity's round-off, step by step, over the steps averaged) */
  ck_assert_double_le(fabs(a - a_law), (steps - from) * worst / (kMass * T) + 1e-14);
  /* the rigid block's value, to the share of the weight the vibrating block's N carries */
  ck_assert_double_le(fabs(a - a_rigid), F * fabs(N / kMass - cos(alpha)) + (steps - from) * worst / (kMass * T) + 1e-14);
  ck_assert_double_le(fabs(N / (kMass * cos(alpha)) - 1), 1e-4);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* tan(alpha) = 0.2 < F = 0.3: every active point sticks, nothing more is
   dissipated (D_f stays, bitwise), the block does not creep, and the
   friction carries the slope's share of the weight, m g sin(alpha). */
START_TEST(coulomb_sticks_below_the_angle) {
  const double F = 0.3, alpha = atan(0.2);
  for (int dim = 2; dim <= 3; ++dim) {
    const block_spec b = {dim, 1, ND_FRICTION_COULOMB, F, alpha, 1, 2e-3, &kTheta1, 0};
    nd_problem p = block(&b);
    for (int n = 0; n < 500; ++n) ND_OK_OR_FAIL(nd_step(p));
    const double D = scalar(p, ND_DISSIPATION_FRICTION), P0 = scalar(p, ND_MOMENTUM_X);
    for (int n = 0; n < 500; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      ck_assert_double_eq(scalar(p, ND_SLIDING_POINTS), 0);
      ck_assert_double_eq(scalar(p, ND_STICKING_POINTS), scalar(p, ND_ACTIVE_POINTS));
    }
    const double mass = kMass, fx = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X);
    printf("dim %d sticking: D_f %.6e -> %.6e, momentum %.2e -> %.2e, f_t,x = %.12f, -m g sin = %.12f\n", dim, D,
           scalar(p, ND_DISSIPATION_FRICTION), P0, scalar(p, ND_MOMENTUM_X), fx, -mass * sin(alpha));
    ck_assert_double_eq(scalar(p, ND_DISSIPATION_FRICTION), D);
    /* at rest (theta = 1 damps the landing's vibration: momentum below 1e-6 m g tau) */
    ck_assert_double_le(fabs(scalar(p, ND_MOMENTUM_X)), 1e-9);
    ck_assert_double_le(fabs(fx + mass * sin(alpha)), 1e-6 * mass);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* Tresca, threshold s: sliding, the tangential resultant is s times the
   contact length (2 in 2D); below the threshold (m g sin < 2 s) it sticks. */
START_TEST(tresca_threshold) {
  /* m g sin(alpha) = 0.959: above s L = 0.4, below 1.2 */
  const double s_slide = 0.2, s_stick = 0.6, alpha = 0.5;
  {
    const block_spec b = {2, 1, ND_FRICTION_TRESCA, s_slide, alpha, 1, 2e-3, &kTheta1, 0};
    nd_problem p = block(&b);
    double worst = 0;
    for (int n = 0; n < 300; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      if (scalar(p, ND_STICKING_POINTS) == 0 && scalar(p, ND_SLIDING_POINTS) > 0)
        worst = fmax(worst, fabs(scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X) + 2 * s_slide));
    }
    printf("Tresca sliding: max |f_t,x + s L| = %.2e\n", worst);
    ck_assert_double_le(worst, 1e-12);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
  {  /* sticking: nothing slides, nothing more is dissipated, and (theta = 1:
        the momentum is the impulse) friction carries m g sin - dP_x/tau */
    const block_spec b = {2, 1, ND_FRICTION_TRESCA, s_stick, alpha, 1, 2e-3, &kTheta1, 0};
    nd_problem p = block(&b);
    for (int n = 0; n < 200; ++n) ND_OK_OR_FAIL(nd_step(p));
    const double D = scalar(p, ND_DISSIPATION_FRICTION);
    double P = scalar(p, ND_MOMENTUM_X), worst = 0;
    for (int n = 0; n < 300; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      ck_assert_double_eq(scalar(p, ND_SLIDING_POINTS), 0);
      const double P_new = scalar(p, ND_MOMENTUM_X);
      worst = fmax(worst, fabs(scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X) + kMass * sin(alpha) - (P_new - P) / b.tau));
      P = P_new;
    }
    printf("Tresca sticking: D_f stays %.6e, max |f_t,x + m g sin - dP/tau| = %.2e\n", D, worst);
    ck_assert_double_eq(scalar(p, ND_DISSIPATION_FRICTION), D);
    ck_assert_double_le(worst, 1e-10 * kMass);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* The hybrid scheme with Theta = 1 (docs/design.md §10.2): with D_f the
   frictional dissipation, E_Theta + D_f - W never increases, step by step,
   to round-off; D_f is non-decreasing. 2D and 3D, P1 and P2, both laws,
   sliding and sticking. */
/* steps of the hybrid scheme with Theta = 1 (docs/design.md §10.2): D_f
   non-decreasing, E_Theta + D_f - W never increasing, step by step, to
   round-off; with F > 0 (Coulomb, 2D) also f_t,x = -F f_n at every step
   where every active point slides. Returns those steps' count. */
static int hybrid_ledger(nd_problem p, int steps, double F, const char *label) {
  double before = scalar(p, ND_ENERGY_AUGMENTED), D = 0, worst = -INFINITY, scale = fabs(before), coulomb = 0;
  int sliding_steps = 0;
  for (int n = 0; n < steps; ++n) {
    ND_OK_OR_FAIL(nd_step(p));
    const double D_new = scalar(p, ND_DISSIPATION_FRICTION);
    ck_assert_double_ge(D_new, D);
    D = D_new;
    const double L = scalar(p, ND_ENERGY_AUGMENTED) + D - scalar(p, ND_WORK);
    scale = fmax(scale, fabs(scalar(p, ND_WORK)));
    worst = fmax(worst, L - before);
    before = L;
    if (F > 0 && scalar(p, ND_STICKING_POINTS) == 0 && scalar(p, ND_SLIDING_POINTS) > 0) {
      const double fn = scalar(p, ND_CONTACT_FORCE_APPLIED);
      coulomb = fmax(coulomb, fabs(scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X) + F * fn) / (F * fn));
      ++sliding_steps;
    }
  }
  printf("%s: max step increase of E_Theta + D_f - W = %.2e (W %.3e, D_f %.3e)", label, worst, scalar(p, ND_WORK), D);
  if (F > 0) printf("; %d steps all sliding, max |f_t,x + F f_n|/(F f_n) = %.2e", sliding_steps, coulomb);
  printf("\n");
  ck_assert_double_le(worst, 1e-12 * scale);
  ck_assert_double_le(coulomb, 1e-12);
  return sliding_steps;
}

/* (_i = 0: simplices, 1: quadrilaterals and hexahedra, Q1 and Q2) */
START_TEST(hybrid_ledger_never_increases) {
  struct {
    int law;
    double coefficient, alpha;
  } cases[] = {{ND_FRICTION_COULOMB, 0.3, 0.5}, {ND_FRICTION_COULOMB, 0.3, 0.1}, {ND_FRICTION_TRESCA, 0.2, 0.5}};
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        if (dim == 3 && degree == 2 && c > 0) continue;  /* (3D P2: one case; the others' cost, not their checks) */
        const block_spec b = {dim, degree, cases[c].law, cases[c].coefficient, cases[c].alpha, 1, 2e-3, &kHybrid, _i};
        nd_problem p = block(&b);
        char label[64];
        snprintf(label, sizeof label, "hybrid dim %d %s%d law %d alpha %.1f", dim, _i ? "Q" : "P", degree, cases[c].law,
                 cases[c].alpha);
        hybrid_ledger(p, 150, 0, label);
        ND_OK_OR_FAIL(nd_problem_destroy(&p));
      }
}
END_TEST

/* A block launched at v0 along the flat plane (alpha = 0): friction F N
   stops it after v0 m/(F N) having slid v0^2 m/(2 F N), N = m g for the
   rigid block: v0/(F g) and v0^2/(2 F g). The vibrating block's N is the
   weight's to its mean over the slide (measured, and the rigid values are
   checked to that share and a step); once stopped it sticks for good. */
START_TEST(launched_block_stops) {
  const double F = 0.3, v0 = 0.3;
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, F, 0, 1, 1e-3, &kTheta1, 0};
  nd_problem p = block(&b);
  launch(p, 2, v0);
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *u = calloc((size_t)(2 * nn), sizeof *u);
  double t_stop = -1, N_sum = 0, D_stop = 0;
  int sliding_steps = 0;
  const double t_exact = v0 / F, d_exact = v0 * v0 / (2 * F);
  for (int n = 1; n <= 1500; ++n) {
    ND_OK_OR_FAIL(nd_step(p));
    const int slides = scalar(p, ND_SLIDING_POINTS) > 0;
    if (t_stop < 0 && slides) N_sum += scalar(p, ND_CONTACT_FORCE_APPLIED), ++sliding_steps;
    if (t_stop < 0 && !slides && n > 10) t_stop = scalar(p, ND_TIME);
    if (t_stop > 0 && scalar(p, ND_TIME) > t_stop + 0.2) {  /* stopped for good */
      if (D_stop == 0) D_stop = scalar(p, ND_DISSIPATION_FRICTION);
      ck_assert_double_eq(scalar(p, ND_SLIDING_POINTS), 0);
      ck_assert_double_eq(scalar(p, ND_DISSIPATION_FRICTION), D_stop);
    }
  }
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, u));
  double mean = 0;  /* the centre of mass: a uniform mesh of equal triangles, P1 */
  for (int64_t i = 0; i < nn; ++i) mean += u[2 * i] / (double)nn;
  const double share = fabs(N_sum / sliding_steps / kMass - 1);
  printf("launched: stops at %.4f (v0/(F g) = %.4f), slid %.6f (v0^2/(2 F g) = %.6f), N/(m g) - 1 = %.2e\n", t_stop,
         t_exact, mean, d_exact, share);
  ck_assert_double_le(fabs(t_stop - t_exact), b.tau + 2 * share * t_exact);
  ck_assert_double_le(fabs(mean - d_exact), v0 * b.tau + 2 * share * d_exact);
  free(u);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* The oblique impact's scene (Maw, Barber and Fawcett 1976): the disk of
   docs/design.md §7 (radius 20, centre (0, 25), h = 4, P1; lambda = mu =
   20) or the ball (3D, h = 4) a distance 0.1 above the plane, moving at
   normal speed vn and tangential speed vt along x, F = 0.1, no gravity,
   hybrid scheme, Nitsche's theta given. */
static nd_problem oblique_impact(int dim, double theta, double vt, double vn, int64_t *nn) {
  const double F = 0.1;
  nd_mesh m = NULL;
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_mesh_read_gmsh(dim == 2 ? ND_MESH_DIR "/disk_h4.msh" : ND_MESH_DIR "/ball_h4.msh", &m));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  const double lambda = 20, mu = 20;
  ND_OK_OR_FAIL(nd_problem_set_material(p, mu * (3 * lambda + 2 * mu) / (lambda + mu), lambda / (2 * (lambda + mu)), 1));
  const double point2[2] = {0, 4.9}, up2[2] = {0, 1}, point3[3] = {0, 0, 4.9}, up3[3] = {0, 0, 1};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, dim == 2 ? point2 : point3, dim == 2 ? up2 : up3));
  ND_OK_OR_FAIL(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, 0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, dim == 2 ? 0.05 : 0.1));
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, nn));
  double *v = calloc((size_t)(dim * *nn), sizeof *v);
  for (int64_t i = 0; i < *nn; ++i) v[dim * i] = vt, v[dim * i + dim - 1] = -vn;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, *nn, NULL, v));
  free(v);
  return p;
}

/* Oblique impact at gross slip: the scene above hits the plane at normal
   speed 1 with a tangential speed 2 > 7 F, Theta = 1. Every pressed point
   slides throughout, so the tangential impulse is F times the normal one:
   in 2D exactly, step by step (the momentum of the hybrid step is its
   applied impulse, f_t = -F f_n at every step), in 3D within the cone
   (equality when the points slide in one direction: 1 % here). The spin it
   gives: oblique_impact_spin below. */
START_TEST(oblique_impact_at_gross_slip) {
  const double F = 0.1, vt = 2, vn = 1;
  for (int dim = 2; dim <= 3; ++dim) {
    int64_t nn = 0;
    nd_problem p = oblique_impact(dim, 1, vt, vn, &nn);
    const int up = dim == 2 ? ND_MOMENTUM_Y : ND_MOMENTUM_Z;
    const double Px0 = scalar(p, ND_MOMENTUM_X), Pn0 = scalar(p, up);
    int sticking_steps = 0, contact_steps = 0, after = 0;
    for (int n = 0; n < 400 && after < 5; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      sticking_steps += scalar(p, ND_STICKING_POINTS) > 0;
      const int pressed = scalar(p, ND_SLIDING_POINTS) + scalar(p, ND_STICKING_POINTS) > 0;
      contact_steps += pressed;
      if (contact_steps > 0 && !pressed) ++after;  /* (the rebound: five steps off the plane) */
    }
    const double Jt = scalar(p, ND_MOMENTUM_X) - Px0, Jn = scalar(p, up) - Pn0, mass = Px0 / vt;
    printf("oblique impact %dD: %d steps pressed (%d with a sticking point), J_t = %.10f, -F J_n = %.10f, ratio %.12f\n",
           dim, contact_steps, sticking_steps, Jt, -F * Jn, Jt / (-F * Jn));
    ck_assert_int_gt(contact_steps, 10);
    ck_assert_int_eq(sticking_steps, 0);
    ck_assert_double_gt(Jn, 1.5 * mass * vn);  /* (it rebounds: J_n = m (1 + e) v_n) */
    if (dim == 2) {
      /* (the momenta are sums over the nodes, each step's added: their round-off) */
      ck_assert_double_le(fabs(Jt + F * Jn), (double)nn * contact_steps * DBL_EPSILON * F * Jn);
    } else {
      ck_assert_double_le(fabs(Jt), F * Jn * (1 + 1e-12));
      ck_assert_double_ge(fabs(Jt), 0.99 * F * Jn);
    }
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* The rotation about the axis normal to x (the sliding direction,
   component a = 0) and to the contact normal (component b = dim - 1),
   through c: rho(x) has the components -s (x_b - c_b), s (x_a - c_a) in a, b,
   s = 1 in 2D (about z), s = -1 in 3D (about y, so that rho_O' m is
   ND_ANGULAR_MOMENTUM_Y = sum_i z m_x - x m_z). */
typedef struct {
  int dim, s, key;
  double c[3];
} spin_axis;

static double rho(const spin_axis *ax, const double *x, int comp) {
  const int a = 0, b = ax->dim - 1;
  return comp == a ? -ax->s * (x[b] - ax->c[b]) : comp == b ? ax->s * (x[a] - ax->c[a]) : 0.0;
}

/* rho_c' M V from the library's rho_O' M V (ND_ANGULAR_MOMENTUM_*, the mass
   the scheme uses): rho_O - rho_c is the translation s (-c_b, c_a) */
static double spin_momentum(nd_problem p, const spin_axis *ax) {
  const int b = ax->dim - 1;
  const double Pa = scalar(p, ND_MOMENTUM_X), Pb = scalar(p, b == 1 ? ND_MOMENTUM_Y : ND_MOMENTUM_Z);
  return scalar(p, ax->key) + ax->s * (ax->c[b] * Pa - ax->c[0] * Pb);
}

/* The spin the oblique impact gives (issue 56; Maw, Barber and Fawcett
   1976), the scene of oblique_impact_at_gross_slip. The stiffness
   annihilates the infinitesimal rotations, K rho = 0, and so does K_Theta
   (its Nitsche rows are stresses, sigma(rho) = 0); both are symmetric, so
   rho' times the hybrid step, M (V^{n+1} - V^n) = tau (F^{n+1/2} - K_Theta
   U^{n+1/2} - Nbar) + (tau/2) G(U^{n+1}), leaves, with no load,

     (i)  L^{n+1} - L^n = tau rho' (-Nbar),   L = rho' M V,

   Nbar the contact term the step applied (nd_problem_contact_step_residual
   from U^n to U^{n+1}: the state's new slip references give back the
   step's phi_t, docs/design.md §10.2), rho' b_q = rho' a_q the moment of the
   point's force: the angular momentum is the angular impulse of the contact
   forces, step by step, to round-off (Newton is run to round-off, rtol = 0:
   G's part is then the solve's). Checked about the origin; with the momenta
   it holds about the centre of mass G. After the contact the spin omega =
   L_G / I_G, I_G = rho_G' M rho_G (M consistent here), is a rigid body's:

     (ii) omega = s h J_t / I_G,

   h the depth below G at which the line of action of the contact impulse
   crosses G's vertical (the sum of (i)). Maw, Barber and Fawcett's rigid
   body at gross slip has h = R (the normal impulse through G). With Theta =
   0 the step's force is the point forces spread by the shape functions
   (b_q = a_q), so its first moments are the points': h = d_t - e J_n/J_t,
   d_t the depth of the tangential impulse (the friction's lever, close to R)
   and e the reference offset from G of the normal impulse. e is mostly
   kinematic: the small-strain rotation theta (rho_G' M U / I_G, the sum of
   the trapezoidal omega as the hybrid U is) moves the body by theta rho_G,
   which lowers the material points where s (x_a - c_a) theta < 0, so the
   pressed ones sit at x_a - c_a ~ -s theta R in the reference and their
   normal force opposes the friction's torque. Measured (2D Theta 0 / 3D
   Theta 0): (i) to 1.6e-9 / 1.6e-8 (L gains ~ 16 / 1e3 a step; 5e-4 / 8e-5 of
   the bound below); omega = -0.0119533 / 0.0134799, 0.61 / 0.53 of the
   nominal rigid value s R J_t / I_G (-0.0195474 / 0.0253211); h = 12.23 /
   10.65, d_t = 19.41 / 18.76, e = 0.718 / 0.811 of which -s sum tau theta
   R f_n / J_n = 0.581 / 0.724 is the rotation's shift (the rest: the
   patch's asymmetric pressure); the normal torque against the friction's is
   ~ theta / F, and theta reaches 0.11 / 0.14 at the rebound. Theta = 1
   alike (h = 12.22 / 10.60). */
START_TEST(oblique_impact_spin) {
  const double vt = 2, vn = 1, R = 20, eps = DBL_EPSILON;
  for (int dim = 2; dim <= 3; ++dim)
    for (int theta = 0; theta <= (dim == 2); ++theta) {  /* (3D Theta = 1: 1.8e-8, h = 10.60; its cost, not its check) */
      int64_t nn = 0;
      nd_problem p = oblique_impact(dim, theta, vt, vn, &nn);
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50));
      const int64_t n = dim * nn;
      const int a = 0, b = dim - 1;
      spin_axis ax = {dim, dim == 2 ? 1 : -1, dim == 2 ? ND_ANGULAR_MOMENTUM_Z : ND_ANGULAR_MOMENTUM_Y, {0, 0, 0}};
      const spin_axis O = ax;
      double *x = malloc(sizeof(double) * (size_t)n), *v = malloc(sizeof(double) * (size_t)n);
      double *U = malloc(sizeof(double) * (size_t)n), *Un = malloc(sizeof(double) * (size_t)n);
      double *r = malloc(sizeof(double) * (size_t)n);
      int64_t *node = malloc(sizeof(int64_t) * (size_t)n);
      int *comp = malloc(sizeof(int) * (size_t)n);
      ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, nn, x));
      ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
      /* the mass and G from the momenta of the translations e_a, e_b
         (rho_O' M e_a = -s m c_b, rho_O' M e_b = s m c_a), I_G from rho_G's */
      double mass = 0, xmax = 0;
      for (int k = 0; k < 2; ++k) {
        const int t = k ? b : a;
        for (int64_t i = 0; i < n; ++i) v[i] = i % dim == t;
        ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v));
        mass = scalar(p, t == 0 ? ND_MOMENTUM_X : t == 1 ? ND_MOMENTUM_Y : ND_MOMENTUM_Z);
        ax.c[k ? a : b] = (k ? 1 : -1) * scalar(p, ax.key) / (ax.s * mass);
      }
      for (int64_t i = 0; i < n; ++i) v[i] = rho(&ax, &x[dim * (i / dim)], (int)(i % dim));
      ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v));
      const double I = spin_momentum(p, &ax);
      for (int64_t i = 0; i < n; ++i) v[i] = i % dim == a ? vt : i % dim == b ? -vn : 0;
      ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v));
      for (int64_t i = 0; i < n; ++i) xmax = fmax(xmax, fabs(x[i]));
      const double tau = scalar(p, ND_TIMESTEP), LG0 = spin_momentum(p, &ax);
      double L = scalar(p, ax.key), worst = 0, worst_ratio = 0, sum_bound = 0, Umax_old = 0, Vmax_old = vt;
      double Ja = 0, Jb = 0, Ht = 0, Hn = 0, rot = 0, omega = LG0 / I, kinematic = 0;
      int contact_steps = 0, after = 0;
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, U));
      for (int step = 0; step < 400 && after < 5; ++step) {
        memcpy(Un, U, sizeof(double) * (size_t)n);
        ND_OK_OR_FAIL(nd_step(p));
        ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, U));
        ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, nn, v));
        ND_OK_OR_FAIL(nd_problem_contact_step_residual(p, n, U, Un, r));
        double T = 0, Tabs = 0, fa = 0, fb = 0, ht = 0, hn = 0, Umax = 0, Vmax = 0;
        for (int64_t j = 0; j < n; ++j) {
          const double *xj = &x[dim * node[j]], f = -r[j];  /* (the force on the body) */
          T += rho(&O, xj, comp[j]) * f, Tabs += fabs(rho(&O, xj, comp[j]) * f);
          if (comp[j] == a) fa += f, ht += rho(&ax, xj, a) * f;
          if (comp[j] == b) fb += f, hn += rho(&ax, xj, b) * f;
          Umax = fmax(Umax, fabs(U[j])), Vmax = fmax(Vmax, fabs(v[j]));
        }
        /* (i) to the round-off of its sums, n terms each (recursive summation:
           (n - 1) eps times the sum of their magnitudes): L = sum_i x_i x (M V)_i
           over nn nodes, M's rows of at most 64 entries, |M| |V| summing to at
           most m max|V| (M >= 0 entrywise: P1's consistent mass); V^{n+1} =
           2 (U^{n+1} - U^n)/tau - V^n carries eps max|U| 2/tau; and T */
        const double Lnew = scalar(p, ax.key), defect = fabs(Lnew - L - tau * T);
        const double bound = (double)(nn + 64) * eps *
                             (dim * xmax * mass * (Vmax + Vmax_old + 2 / tau * (Umax + Umax_old)) + tau * Tabs);
        worst = fmax(worst, defect), worst_ratio = fmax(worst_ratio, defect / bound);
        sum_bound += bound;
        L = Lnew, Umax_old = Umax, Vmax_old = Vmax;
        Ja += tau * fa, Jb += tau * fb, Ht += tau * ht, Hn += tau * hn;
        const double omega_new = spin_momentum(p, &ax) / I;
        kinematic += tau * (rot + 0.25 * tau * (omega + omega_new)) * R * fb;  /* (theta at mid-step) */
        rot += 0.5 * tau * (omega + omega_new), omega = omega_new;
        const int pressed = fb != 0;
        contact_steps += pressed;
        if (contact_steps > 0 && !pressed) ++after;  /* (the rebound: five steps off the plane) */
      }
      const double LG = spin_momentum(p, &ax), h = (Ht + Hn) / (ax.s * Ja), d_t = Ht / (ax.s * Ja), e = Hn / (ax.s * Jb);
      const double rigid = ax.s * R * Ja / I;
      printf("spin %dD Theta %d: max |dL - tau T| = %.2e (%.2e of the bound); G = (%.2e, %.6f), I_G = %.6e (m R^2 %s "
             "= %.6e)\n  omega = %.8f, s h J_t / I_G = %.8f, h = %.4f, d_t = %.4f, e = %.4f, -s sum tau theta R f_n / J_n "
             "= %.4f; nominal rigid s R J_t / I_G = %.8f (omega / that = %.4f); |L_G - s h J_t| = %.2e; theta = %.4f\n",
             dim, theta, worst, worst_ratio, ax.c[a], ax.c[b], I, dim == 2 ? "/ 2" : "2 / 5",
             (dim == 2 ? 0.5 : 0.4) * mass * R * R, LG / I, ax.s * h * Ja / I, h, d_t, e, -ax.s * kinematic / Jb, rigid,
             LG / I / rigid, fabs(LG - ax.s * h * Ja), rot);
      ck_assert_int_gt(contact_steps, 10);
      ck_assert_double_le(worst_ratio, 1);
      /* (ii): the sum of (i) over the steps, from L_G^0 = 0 (a translation) to
         its round-off */
      ck_assert_double_le(fabs(LG - ax.s * h * Ja), sum_bound + fabs(LG0));
      free(x), free(v), free(U), free(Un), free(r), free(node), free(comp);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* sum_ij |A_ij| |U_j| for A = K and K_Theta - K (nd_problem_get_matrix,
   no Dirichlet DOF: the free DOFs are the field's, by the DOF map): the size
   of the terms of K_Theta U, its round-off's scale */
static double stiffness_terms(nd_problem p, const double *U) {
  double sum = 0;
  for (int which = ND_MATRIX_STIFFNESS; which <= ND_MATRIX_NITSCHE; ++which) {
    int64_t n = 0, nnz = 0;
    ND_OK_OR_FAIL(nd_problem_get_matrix(p, which, &n, &nnz, NULL, NULL, NULL));
    int64_t *ptr = malloc(sizeof(int64_t) * (size_t)(n + 1)), *col = malloc(sizeof(int64_t) * (size_t)nnz);
    int64_t *node = malloc(sizeof(int64_t) * (size_t)n);
    int *comp = malloc(sizeof(int) * (size_t)n), dim = 0;
    double *val = malloc(sizeof(double) * (size_t)nnz);
    ND_OK_OR_FAIL(nd_problem_get_matrix(p, which, &n, &nnz, ptr, col, val));
    ND_OK_OR_FAIL(nd_problem_get_dof_map(p, n, node, comp));
    for (int64_t i = 0; i < n; ++i) dim = comp[i] + 1 > dim ? comp[i] + 1 : dim;
    for (int64_t i = 0; i < n; ++i)
      for (int64_t k = ptr[i]; k < ptr[i + 1]; ++k) sum += fabs(val[k] * U[node[col[k]] * dim + comp[col[k]]]);
    free(ptr), free(col), free(node), free(comp), free(val);
  }
  return sum;
}

/* Friction with mass redistribution (nd_problem_set_mass_redistribution):
   the contact DOFs carry no mass, their rows are static, (K_Theta U +
   N(U))_m = F_m, the frictional law included: an implicit step solves them
   with the rest, an explicit one for U_m alone (problem/massless.cpp). The
   hybrid scheme with Theta = 1 keeps its ledger (2D and 3D, P1 and P2; the
   kinetic energy is V'M V with the redistributed M), sliding obeys Coulomb
   (2D: f_t = -F f_n; F = 0 with Theta = 0 is the frictionless method:
   zero_coefficient_is_frictionless). Measured: ledger 3.2e-16 a step,
   Coulomb 4.1e-16 (5.7e-16 explicit), the explicit momentum identity 1.5e-3
   to 2.6e-3 of its bound (1e10 to 1e11 times it with the static rows solved
   without the tangential pairs or without their slip references' shift). */
START_TEST(friction_with_mass_redistribution) {
  const double F = 0.3;
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= (dim == 2 ? 2 : 1); ++degree) {  /* (3D P2: its cost, not its check) */
      const block_spec b = {dim, degree, ND_FRICTION_COULOMB, F, 0.5, 1, 2e-3, &kHybrid, 0};
      nd_problem p = block(&b);
      ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
      char label[64];
      snprintf(label, sizeof label, "redistributed mass, hybrid dim %d P%d", dim, degree);
      const int sliding_steps = hybrid_ledger(p, 150, dim == 2 ? F : 0, label);
      if (dim == 2) ck_assert_int_gt(sliding_steps, 100);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
  /* the central difference (explicit: U_m from the static rows, their
     Newton run to round-off): summed over every DOF's row, K_Theta drops out
     and the static rows add nothing, so from the second step on (the first
     starts from A^0, whose massless rows were not in equilibrium) the
     momentum gains tau/2 (F_x^n + F_x^{n+1}), F_x = m g sin(alpha) + f_t,x,
     step by step; and sliding obeys Coulomb (2D) */
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= (dim == 2 ? 2 : 1); ++degree) {
      const nd_test_scheme central = {ND_SCHEME_NEWMARK, {0, 0.5}};
      const block_spec b = {dim, degree, ND_FRICTION_COULOMB, F, 0.5, 1, 0, &central, 0};
      nd_problem p = block(&b);
      ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, 1));
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50));
      int64_t nn = 0;
      ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
      double *U = calloc((size_t)(dim * nn), sizeof *U);
      const double tau = scalar(p, ND_TIMESTEP), eps = DBL_EPSILON;
      double P = 0, Fx = 0, SK = 0, worst = 0, coulomb = 0;
      int sliding_steps = 0;
      for (int n = 0; n < 1000; ++n) {
        ND_OK_OR_FAIL(nd_step(p));
        ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, U));
        const double P_new = scalar(p, ND_MOMENTUM_X), SK_new = stiffness_terms(p, U);
        const double Fx_new = kMass * sin(0.5) + scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X);
        /* (round-off: the sums over the dim nn rows of M V (m |V| each, P's
           terms) and of the forces (K_Theta U's terms), 64 a row's entries) */
        const double bound = (double)(dim * nn + 64) * eps * (fabs(P) + fabs(P_new) + tau * (SK + SK_new));
        if (n > 0) worst = fmax(worst, fabs(P_new - P - 0.5 * tau * (Fx + Fx_new)) / bound);
        P = P_new, Fx = Fx_new, SK = SK_new;
        if (scalar(p, ND_STICKING_POINTS) == 0 && scalar(p, ND_SLIDING_POINTS) > 0) {
          const double fn = scalar(p, ND_CONTACT_FORCE_APPLIED);
          coulomb = fmax(coulomb, fabs(scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X) + F * fn) / (F * fn));
          ++sliding_steps;
        }
      }
      printf("redistributed mass, central difference dim %d P%d: max |dP - impulse| = %.2e of its bound, %d steps all "
             "sliding, max |f_t,x + F f_n|/(F f_n) = %.2e, D_f %.3e\n", dim, degree, worst, sliding_steps, coulomb,
             scalar(p, ND_DISSIPATION_FRICTION));
      ck_assert_double_le(worst, 1);
      ck_assert_int_gt(sliding_steps, 500);
      if (dim == 2) ck_assert_double_le(coulomb, 1e-12);
      free(U);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* Friction with the rest of the physics (issue 58): Rayleigh damping, two
   materials (the block's lowest row of cells twice as stiff and dense),
   plane stress; the hybrid scheme with Theta = 1: E_Theta + D_f + D_damping
   - W still never increases, step by step, to round-off. */
START_TEST(ledger_with_damping_and_materials) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[2] = {0, 0}, hi[2] = {2, 1}, blo[2] = {-1, -1e-9}, bhi[2] = {3, 1e-9};
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(8, 4, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  int64_t lowest[16];
  for (int i = 0; i < 16; ++i) lowest[i] = i; /* (the generator's first row: 8 squares, 2 triangles each) */
  ND_OK_OR_FAIL(nd_mesh_set_cell_region(m, 2, 16, lowest));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1e4, 0.3, 1));
  ND_OK_OR_FAIL(nd_problem_set_material_region(p, 2, 2e4, 0.25, 2));
  ND_OK_OR_FAIL(nd_problem_set_plane_stress(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_damping(p, 0.1, 1e-4));
  const double point[2] = {0, 0}, up[2] = {0, 1}, F = 0.3, g[2] = {sin(0.5), -cos(0.5)};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, point, up));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1, 0));
  ND_OK_OR_FAIL(nd_problem_set_friction(p, 1, ND_FRICTION_COULOMB, &F));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 2e-3));
  double before = scalar(p, ND_ENERGY_AUGMENTED), worst = -INFINITY, scale = fabs(before);
  for (int n = 0; n < 300; ++n) {
    ND_OK_OR_FAIL(nd_step(p));
    const double L = scalar(p, ND_ENERGY_AUGMENTED) + scalar(p, ND_DISSIPATION_FRICTION) +
                     scalar(p, ND_DISSIPATION_DAMPING) - scalar(p, ND_WORK);
    scale = fmax(scale, fabs(scalar(p, ND_WORK)));
    worst = fmax(worst, L - before);
    before = L;
  }
  printf("friction, damping, two materials, plane stress: max step increase of E_Theta + D_f + D_d - W = %.2e "
         "(D_f %.4e, D_d %.4e, W %.4e)\n", worst, scalar(p, ND_DISSIPATION_FRICTION), scalar(p, ND_DISSIPATION_DAMPING),
         scalar(p, ND_WORK));
  ck_assert_double_gt(scalar(p, ND_DISSIPATION_FRICTION), 0);
  ck_assert_double_gt(scalar(p, ND_DISSIPATION_DAMPING), 0);
  ck_assert_double_le(worst, 1e-12 * scale);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* Theta = 0 carries no tangential term in K_Theta, and F = 0 applies none:
   the frictionless trajectory, to the Newton tolerance. */
START_TEST(zero_coefficient_is_frictionless) {
  for (int redistributed = 0; redistributed <= 1; ++redistributed) {  /* (and with mass redistribution, both) */
    const block_spec b = {2, 1, ND_FRICTION_COULOMB, 0, 0.5, 0, 2e-3, &kTheta1, 0};
    block_spec f = b;
    f.law = ND_FRICTION_NONE;
    nd_problem p = block(&b), q = block(&f);
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, redistributed));
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(q, redistributed));
    int64_t nn = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
    double *up = calloc((size_t)(2 * nn), sizeof *up), *uq = calloc((size_t)(2 * nn), sizeof *uq), diff = 0, scale = 0;
    for (int n = 0; n < 200; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_step(q));
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, up));
      ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_DISPLACEMENT, nn, uq));
      for (int64_t i = 0; i < 2 * nn; ++i) diff = fmax(diff, fabs(up[i] - uq[i])), scale = fmax(scale, fabs(uq[i]));
    }
    printf("F = 0, Theta = 0%s: max |u - u_frictionless| = %.2e (max |u| %.2e)\n",
           redistributed ? ", mass redistribution" : "", diff, scale);
    ck_assert_double_le(diff, 1e-9 * scale);
    free(up), free(uq);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    ND_OK_OR_FAIL(nd_problem_destroy(&q));
  }
}
END_TEST

/* ---- a moving plane (docs/design.md §10.2: slip is relative) ----------- */

/* Galilean invariance: the block on the slope (sliding, F = 0.3 < tan 0.5)
   and on the flat plane with a stick phase after landing (alpha = 0.1),
   body and plane carried along x at v = 0.7, is the static run shifted by
   v t, u_y alike, D_f the same: the plane's translation moves the slip
   references by v tau a step, the block's T u likewise. Every scheme
   (each integrates a uniform translation exactly; generalized-alpha mixes
   P_t^n at the state's reference, which moves with the body as P_t^{n+1}
   at the shifted one does). */
START_TEST(galilean_moving_plane) {
  const double v = 0.7, alphas[2] = {0.5, 0.1};
  for (int a = 0; a < 2; ++a)
    for (int k = 0; k < ND_TEST_N_SCHEMES; ++k) {
      const block_spec b = {2, 1, ND_FRICTION_COULOMB, 0.3, alphas[a], 1, 2e-3, &nd_test_schemes[k], 0};
      nd_problem still = block(&b), moving = block(&b);
      launch(moving, 2, v);
      int64_t nn = 0;
      ND_OK_OR_FAIL(nd_problem_get_node_count(still, &nn));
      double *us = calloc((size_t)(2 * nn), sizeof *us), *um = calloc((size_t)(2 * nn), sizeof *um);
      double diff = 0, scale = 0, dD = 0;
      const int steps = 200;
      const double tau = scalar(still, ND_TIMESTEP);  /* (the explicit one's: half its critical step) */
      for (int n = 1; n <= steps; ++n) {
        const double t = n * tau;
        place_plane(moving, 2, v * t, 0, 0);
        ND_OK_OR_FAIL(nd_step(still));
        ND_OK_OR_FAIL(nd_step(moving));
        ND_OK_OR_FAIL(nd_get_field(still, ND_FIELD_DISPLACEMENT, nn, us));
        ND_OK_OR_FAIL(nd_get_field(moving, ND_FIELD_DISPLACEMENT, nn, um));
        for (int64_t i = 0; i < nn; ++i) {
          diff = fmax(diff, fabs(um[2 * i] - v * t - us[2 * i]));
          diff = fmax(diff, fabs(um[2 * i + 1] - us[2 * i + 1]));
          scale = fmax(scale, fabs(um[2 * i]));
        }
        dD = fmax(dD, fabs(scalar(moving, ND_DISSIPATION_FRICTION) - scalar(still, ND_DISSIPATION_FRICTION)));
      }
      const double D = scalar(still, ND_DISSIPATION_FRICTION);
      printf("Galilean, alpha %.1f scheme %d: max |u_moving - v t - u_still| = %.2e (max |u| %.2e), "
             "|dD_f| = %.2e (D_f %.3e, sliding %g sticking %g)\n", alphas[a], k, diff, scale, dD, D,
             scalar(still, ND_SLIDING_POINTS), scalar(still, ND_STICKING_POINTS));
      /* the two runs differ by the rounding of v t in U and in the references
         (ulp(|u|) a step) amplified through the solves, and by Newton's
         stopping point (its tolerance, 1e-10 of the right-hand side with the
         translation in it): 1e-9 |u| covers both with room (measured: see
         the printout) */
      ck_assert_double_le(diff, 1e-9 * scale);
      ck_assert_double_le(dD, 1e-9 * fmax(D, 1e-300) + 1e-15);
      free(us), free(um);
      ND_OK_OR_FAIL(nd_problem_destroy(&still));
      ND_OK_OR_FAIL(nd_problem_destroy(&moving));
    }
}
END_TEST

/* The conveyor: the block resting on the flat plane (alpha = 0, g = 1;
   theta = 1 has damped its landing for 0.3 s), then the plane moves along
   x at v = 0.1. Friction drags the block at F g until it has the plane's
   speed, after v/(F g), then it sticks and rides along. Checked:
    - theta = 1: the momentum gains tau f_t,x a step (the only force along
      x), to Newton's tolerance (the steps where every point slides, or
      sticks, solve exactly: the 2D law is linear there; a step where the
      points change status stops within the tolerance);
    - the plane's work is its velocity times the impulse it gave, W_obstacle
      = v (P - P_0): each step's -sum (w/gamma) phi_t . shift with shift =
      v tau t_x is v tau f_t,x;
    - the rigid block's ledger: the plane does m v^2, friction dissipates
      F N (v t_s - v t_s/2) = m v^2/2 (whatever N: t_s = m v/(F N)), the
      block keeps m v^2/2; theta = 1's velocity steps F g tau slip
      m sum dv^2/2 = m F g v tau/2 less (bound: twice that), the elastic
      block's N the weight's to a share (measured, as in launched_block_stops);
    - carried: from 0.3 s after, no point slides and D_f stays, bitwise. */
START_TEST(conveyor_drags_then_carries) {
  const double F = 0.1, v = 0.1;
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, F, 0, 1, 1e-3, &kTheta1, 0};
  nd_problem p = block(&b);
  int64_t nn = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
  double *u = calloc((size_t)(2 * nn), sizeof *u);
  for (int n = 0; n < 300; ++n) ND_OK_OR_FAIL(nd_step(p));
  const double D0 = scalar(p, ND_DISSIPATION_FRICTION), W0 = scalar(p, ND_WORK_OBSTACLE), P0 = scalar(p, ND_MOMENTUM_X);
  double P = P0, worst = 0, defects = 0, t_reach = -1, N_sum = 0, D_carried = -1;
  int drag_steps = 0;
  for (int n = 1; n <= 1600; ++n) {
    const double t = n * b.tau;
    place_plane(p, 2, v * t, 0, 0);
    ND_OK_OR_FAIL(nd_step(p));
    const double P_new = scalar(p, ND_MOMENTUM_X), fx = scalar(p, ND_CONTACT_FORCE_TANGENTIAL_X);
    /* Newton's residual G, ||G|| <= 1e-10 (||r|| + c ||M U||), c = 1/tau^2,
       enters dP as tau sum_x G_i <= tau sqrt(2 nn) ||G||; ||M U|| <= 2 m
       max |u| (M >= 0 entrywise, its entries summing to 2 m), and ||r||
       (c M times the predictor, plus the loads) is of the same size */
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, u));
    double umax = 0;
    for (int64_t i = 0; i < 2 * nn; ++i) umax = fmax(umax, fabs(u[i]));
    const double newton = b.tau * sqrt(2.0 * nn) * 1e-10 * 2 * (2 * kMass * umax / (b.tau * b.tau) + kMass);
    const double defect = fabs(P_new - P - b.tau * fx);
    ck_assert_double_le(defect, newton);
    worst = fmax(worst, defect), defects += defect;
    P = P_new;
    if (t_reach < 0) N_sum += scalar(p, ND_CONTACT_FORCE_APPLIED), ++drag_steps;
    if (t_reach < 0 && P - P0 >= kMass * v) t_reach = t;
    if (t_reach > 0 && t > t_reach + 0.3) {
      if (D_carried < 0) D_carried = scalar(p, ND_DISSIPATION_FRICTION);
      ck_assert_double_eq(scalar(p, ND_SLIDING_POINTS), 0);
      ck_assert_double_eq(scalar(p, ND_DISSIPATION_FRICTION), D_carried);
    }
  }
  const double share = fabs(N_sum / drag_steps / kMass - 1), t_exact = v / F;
  const double D = scalar(p, ND_DISSIPATION_FRICTION) - D0, W = scalar(p, ND_WORK_OBSTACLE) - W0;
  const double E = kMass * v * v / 2;
  printf("conveyor: max |dP - tau f_t,x| = %.2e; reaches v at %.4f (v/(F g) = %.4f), D_f %.8f (m v^2/2 = %.4f), "
         "W_obstacle %.8f, v (P - P0) = %.8f, N/(m g) - 1 = %.2e\n", worst, t_reach, t_exact, D, E, W, v * (P - P0),
         share);
  ck_assert_double_ge(D_carried, 0);  /* (it was carried for 0.3 s at least) */
  /* (the step that crosses v, and the crossing step's P = m v to round-off) */
  ck_assert_double_le(fabs(t_reach - t_exact), 2 * b.tau + 2 * share * t_exact);
  /* (each step's shift rounds v tau: 1e-15 of W a step) */
  ck_assert_double_le(fabs(W - v * (P - P0)), v * defects + 1600 * 1e-15 * fabs(W));
  ck_assert_double_le(fabs(D - E), kMass * F * v * b.tau + 2 * share * E);
  free(u);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* The hybrid scheme with Theta = 1 against a moving plane (docs/design.md
   §10.2): E_Theta + D_f - W - W_obstacle never increases, step by step, to
   round-off, W_obstacle the plane's work with the tangential traction's
   part (its velocity times the whole contact force). The plane slides
   under the block along x (3D: along (1, 1/2)) at v = 0.3 and rises and
   falls by 1e-4 (pressing the block), from rest; 2D and 3D, both laws,
   sliding (drag) and sticking (carried, alpha = 0.1 and F = 0.3). Without
   the tangential work the same sum rises by the drag's work (printed). */
START_TEST(hybrid_ledger_moving_plane) {
  struct {
    int law;
    double coefficient, alpha;
  } cases[] = {{ND_FRICTION_COULOMB, 0.3, 0.1}, {ND_FRICTION_COULOMB, 0.05, 0.5}, {ND_FRICTION_TRESCA, 0.2, 0.3}};
  const double v = 0.3, a = 1e-4, omega = 20;
  for (int dim = 2; dim <= 3; ++dim)
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
      const block_spec b = {dim, 1, cases[c].law, cases[c].coefficient, cases[c].alpha, 1, 2e-3, &kHybrid, 0};
      nd_problem p = block(&b);
      /* (the identity is the solved step's: in 3D the sliding turns, the
         projection on the disk is curved, and Newton's default tolerance
         1e-10 left steps 3e-9 off it; at 1e-12 they solve to round-off) */
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 1e-12, 0, 50));
      double before = scalar(p, ND_ENERGY_AUGMENTED), worst = -INFINITY, scale = fabs(before), rise = 0;
      double bare = before;
      for (int n = 1; n <= 300; ++n) {
        const double t = n * b.tau, s = v * t, h = a * (1 - cos(omega * t));
        place_plane(p, dim, s, dim == 3 ? s / 2 : 0, h);
        ND_OK_OR_FAIL(nd_step(p));
        const double E = scalar(p, ND_ENERGY_AUGMENTED) + scalar(p, ND_DISSIPATION_FRICTION) - scalar(p, ND_WORK);
        const double L = E - scalar(p, ND_WORK_OBSTACLE);
        scale = fmax(scale, fmax(fabs(scalar(p, ND_WORK)), fabs(scalar(p, ND_WORK_OBSTACLE))));
        worst = fmax(worst, L - before);
        rise = fmax(rise, E - bare);
        before = L, bare = E;
      }
      printf("hybrid, moving plane, dim %d law %d F|s %.2f alpha %.1f: max step increase of E_Theta + D_f - W - "
             "W_obstacle = %.2e (W %.3e, W_obstacle %.3e, D_f %.3e; sliding %g sticking %g); without W_obstacle "
             "%.2e\n", dim, cases[c].law, cases[c].coefficient, cases[c].alpha, worst, scalar(p, ND_WORK),
             scalar(p, ND_WORK_OBSTACLE), scalar(p, ND_DISSIPATION_FRICTION), scalar(p, ND_SLIDING_POINTS),
             scalar(p, ND_STICKING_POINTS), rise);
      ck_assert_double_le(worst, 1e-12 * scale);
      ck_assert_double_gt(rise, 1e-6 * scale);  /* (the plane's work is in the test) */
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* A run resumed from a checkpoint taken while the block slides is bitwise
   the uninterrupted one (the slip references travel in the checkpoint):
   the hybrid scheme in 2D and 3D (in 3D the tangent's preconditioner is
   made from the state's tangent history: the same one), and the central
   difference with mass redistribution in 2D (its massless solve reads
   them); a frictionless problem refuses it. */
START_TEST(restart_is_bitwise) {
  const nd_test_scheme central = {ND_SCHEME_NEWMARK, {0, 0.5}};
  const int dim = _i;
  for (int redistributed = 0; redistributed <= (dim == 2); ++redistributed) {  /* (and an explicit step with it) */
    const block_spec b = {dim, 1, ND_FRICTION_COULOMB, 0.3, 0.5, 1, 2e-3, redistributed ? &central : &kHybrid, 0};
    nd_problem p = block(&b), q = block(&b);
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(p, redistributed));
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(q, redistributed));
    for (int n = 0; n < 60; ++n) ND_OK_OR_FAIL(nd_step(p));
    int64_t size = 0;
    unsigned char *buf = nd_test_checkpoint(p, &size);
    ND_OK_OR_FAIL(nd_problem_load_state(q, size, buf));
    for (int n = 0; n < 60; ++n) {
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_step(q));
    }
    int64_t nn = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
    double *up = calloc((size_t)(dim * nn), sizeof *up), *uq = calloc((size_t)(dim * nn), sizeof *uq);
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, up));
    ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_DISPLACEMENT, nn, uq));
    ck_assert_int_eq(memcmp(up, uq, sizeof(double) * (size_t)(dim * nn)), 0);
    ck_assert_double_gt(scalar(p, ND_DISSIPATION_FRICTION), 0);
    ck_assert_double_eq(scalar(p, ND_DISSIPATION_FRICTION), scalar(q, ND_DISSIPATION_FRICTION));
    block_spec f = b;
    f.law = ND_FRICTION_NONE;
    nd_problem r = block(&f);
    ND_OK_OR_FAIL(nd_problem_set_mass_redistribution(r, redistributed));
    ck_assert_int_eq(nd_problem_load_state(r, size, buf), ND_ERR_STATE);
    free(buf), free(up), free(uq);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    ND_OK_OR_FAIL(nd_problem_destroy(&q));
    ND_OK_OR_FAIL(nd_problem_destroy(&r));
  }
}
END_TEST

/* A run against a moving plane resumed from a checkpoint is bitwise the
   uninterrupted one: the planes' points at t^n travel in the checkpoint's
   friction section, and the next step's shift of the references is the
   same. 2D and 3D, the hybrid scheme, the block dragged (sliding). */
START_TEST(restart_moving_plane_is_bitwise) {
  const double v = 0.3;
  for (int dim = 2; dim <= 3; ++dim) {
    const block_spec b = {dim, 1, ND_FRICTION_COULOMB, 0.3, 0.1, 1, 2e-3, &kHybrid, 0};
    nd_problem p = block(&b), q = block(&b);
    for (int n = 1; n <= 60; ++n) {
      place_plane(p, dim, v * n * b.tau, 0, 0);
      ND_OK_OR_FAIL(nd_step(p));
    }
    int64_t size = 0;
    unsigned char *buf = nd_test_checkpoint(p, &size);
    ND_OK_OR_FAIL(nd_problem_load_state(q, size, buf));
    for (int n = 61; n <= 120; ++n) {
      place_plane(p, dim, v * n * b.tau, 0, 0);
      place_plane(q, dim, v * n * b.tau, 0, 0);
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_step(q));
    }
    ck_assert_double_gt(scalar(p, ND_SLIDING_POINTS), 0);
    int64_t nn = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
    const size_t bytes = sizeof(double) * (size_t)(dim * nn);
    double *up = malloc(bytes), *uq = malloc(bytes);
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, nn, up));
    ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_DISPLACEMENT, nn, uq));
    ck_assert_int_eq(memcmp(up, uq, bytes), 0);
    ck_assert_double_eq(scalar(p, ND_DISSIPATION_FRICTION), scalar(q, ND_DISSIPATION_FRICTION));
    ck_assert_double_eq(scalar(p, ND_WORK_OBSTACLE), scalar(q, ND_WORK_OBSTACLE));
    free(buf), free(up), free(uq);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
    ND_OK_OR_FAIL(nd_problem_destroy(&q));
  }
}
END_TEST

/* A plane replaced by another (another normal: a new obstacle, not a
   motion) holds from t^n on: its point is not a displacement of the old
   one, so no slip is shifted and no work counted (the block's plane
   through (5, 0), tilted by 1e-6, in place of the one through the origin). */
START_TEST(replaced_plane_counts_no_work) {
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, 0.3, 0.5, 1, 2e-3, &kTheta1, 0};
  nd_problem p = block(&b);
  for (int n = 0; n < 50; ++n) ND_OK_OR_FAIL(nd_step(p));
  const double point[2] = {5, 0}, tilted[2] = {1e-6, 1};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, point, tilted));
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert_double_gt(scalar(p, ND_SLIDING_POINTS), 0);
  ck_assert_double_eq(scalar(p, ND_WORK_OBSTACLE), 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("friction");
  TCase *tc = tcase_create("friction");
  tcase_set_timeout(tc, 600);
  tcase_add_loop_test(tc, coulomb_tangential_is_F_times_normal, 0, 2);
  tcase_add_test(tc, coulomb_momentum_is_the_impulse);
  tcase_add_test(tc, coulomb_sticks_below_the_angle);
  tcase_add_test(tc, tresca_threshold);
  tcase_add_loop_test(tc, hybrid_ledger_never_increases, 0, 2);
  tcase_add_test(tc, launched_block_stops);
  tcase_add_test(tc, oblique_impact_at_gross_slip);
  tcase_add_test(tc, oblique_impact_spin);
  tcase_add_test(tc, friction_with_mass_redistribution);
  tcase_add_test(tc, ledger_with_damping_and_materials);
  tcase_add_test(tc, zero_coefficient_is_frictionless);
  tcase_add_loop_test(tc, restart_is_bitwise, 2, 4);
  tcase_add_test(tc, galilean_moving_plane);
  tcase_add_test(tc, conveyor_drags_then_carries);
  tcase_add_test(tc, hybrid_ledger_moving_plane);
  tcase_add_test(tc, restart_moving_plane_is_bitwise);
  tcase_add_test(tc, replaced_plane_counts_no_work);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
