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
} block_spec;

/* the block's mass: rho = 1, volume 2 (area 2 in 2D, per unit thickness) */
static const double kMass = 2;

static nd_problem block(const block_spec *b) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const int coarse = b->degree == 2;
  if (b->dim == 2) {
    const double lo[2] = {0, 0}, hi[2] = {2, 1}, blo[2] = {-1, -1e-9}, bhi[2] = {3, 1e-9};
    ND_OK_OR_FAIL(nd_mesh_create_rectangle(coarse ? 4 : 8, coarse ? 2 : 4, lo, hi, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, blo, bhi));
  } else {
    const double lo[3] = {0, 0, 0}, hi[3] = {2, 1, 1}, blo[3] = {-1, -1, -1e-9}, bhi[3] = {3, 2, 1e-9};
    ND_OK_OR_FAIL(nd_mesh_create_box(coarse ? 2 : 4, coarse ? 1 : 2, coarse ? 1 : 2, lo, hi, &m));
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
   slope), and |f_t| <= F f_n (the cone) in 3D; for every scheme, P1, P2. */
START_TEST(coulomb_tangential_is_F_times_normal) {
  const double F = 0.3;
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= (dim == 2 ? 2 : 1); ++degree)  /* (3D P2: the cone holds alike; its cost, not) */
      for (int k = 0; k < ND_TEST_N_SCHEMES; ++k) {
        const block_spec b = {dim, degree, ND_FRICTION_COULOMB, F, 0.5, 1, 2e-3, &nd_test_schemes[k]};
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
          printf("dim 2 P%d scheme %d: %d steps all sliding, max |f_x + F f_n|/(F f_n) = %.2e\n", degree, k,
                 sliding_steps, worst);
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
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, F, alpha, 1, 2e-3, &kTheta1};
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
    const block_spec b = {dim, 1, ND_FRICTION_COULOMB, F, alpha, 1, 2e-3, &kTheta1};
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
    const block_spec b = {2, 1, ND_FRICTION_TRESCA, s_slide, alpha, 1, 2e-3, &kTheta1};
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
    const block_spec b = {2, 1, ND_FRICTION_TRESCA, s_stick, alpha, 1, 2e-3, &kTheta1};
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
START_TEST(hybrid_ledger_never_increases) {
  struct {
    int law;
    double coefficient, alpha;
  } cases[] = {{ND_FRICTION_COULOMB, 0.3, 0.5}, {ND_FRICTION_COULOMB, 0.3, 0.1}, {ND_FRICTION_TRESCA, 0.2, 0.5}};
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        if (dim == 3 && degree == 2 && c > 0) continue;  /* (3D P2: one case; the others' cost, not their checks) */
        const block_spec b = {dim, degree, cases[c].law, cases[c].coefficient, cases[c].alpha, 1, 2e-3, &kHybrid};
        nd_problem p = block(&b);
        double before = scalar(p, ND_ENERGY_AUGMENTED), D = 0, worst = -INFINITY, scale = fabs(before);
        for (int n = 0; n < 150; ++n) {
          ND_OK_OR_FAIL(nd_step(p));
          const double D_new = scalar(p, ND_DISSIPATION_FRICTION);
          ck_assert_double_ge(D_new, D);
          D = D_new;
          const double L = scalar(p, ND_ENERGY_AUGMENTED) + D - scalar(p, ND_WORK);
          scale = fmax(scale, fabs(scalar(p, ND_WORK)));
          worst = fmax(worst, L - before);
          before = L;
        }
        printf("hybrid dim %d P%d law %d alpha %.1f: max step increase of E_Theta + D_f - W = %.2e (W %.3e, D_f %.3e)\n",
               dim, degree, cases[c].law, cases[c].alpha, worst, scalar(p, ND_WORK), D);
        ck_assert_double_le(worst, 1e-12 * scale);
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
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, F, 0, 1, 1e-3, &kTheta1};
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

/* Oblique impact at gross slip (Maw, Barber and Fawcett 1976): the disk of
   docs/design.md §7 (radius 20, centre (0, 25), h = 4, P1; lambda = mu =
   20) and the ball (3D, h = 4) hit the plane at normal speed 1 with a
   tangential speed 2 > 7 F (F = 0.1), no gravity, hybrid scheme. Every
   pressed point slides throughout, so the tangential impulse is F times the
   normal one: in 2D exactly, step by step (the momentum of the hybrid step
   is its applied impulse, f_t = -F f_n at every step), in 3D within the cone
   (equality when the points slide in one direction: 1 % here). */
START_TEST(oblique_impact_at_gross_slip) {
  const double F = 0.1, vt = 2, vn = 1, R = 20;
  for (int dim = 2; dim <= 3; ++dim) {
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
    ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1, 0));
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, dim == 2 ? 0.05 : 0.1));
    int64_t nn = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nn));
    double *v = calloc((size_t)(dim * nn), sizeof *v);
    for (int64_t i = 0; i < nn; ++i) v[dim * i] = vt, v[dim * i + dim - 1] = -vn;
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nn, NULL, v));
    const int up = dim == 2 ? ND_MOMENTUM_Y : ND_MOMENTUM_Z;
    const double Px0 = scalar(p, ND_MOMENTUM_X), Pn0 = scalar(p, up), L0 = scalar(p, ND_ANGULAR_MOMENTUM_Z);
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
      /* the spin about the reference centre (0, 25), L_O - x_c x P, against
         the rigid disk's R F J_n / I: printed, not asserted. This disk is
         soft (a contact of 15 s, a rotation of 0.12 rad), so the rigid
         prediction is no reference: the normal force's offset in the sliding
         patch opposes the friction's torque (39 % less spin, measured) */
      const double L = scalar(p, ND_ANGULAR_MOMENTUM_Z), Px = scalar(p, ND_MOMENTUM_X);
      const double L0c = L0 + 25 * Px0, Lc = L + 25 * Px;  /* (x_c x P)_z = x P_y - y P_x, x = 0 */
      const double I = 0.5 * mass * R * R;
      printf("  spin %.6f, the rigid disk's -R F J_n / I = %.6f\n", (Lc - L0c) / I, -R * F * Jn / I);
    } else {
      ck_assert_double_le(fabs(Jt), F * Jn * (1 + 1e-12));
      ck_assert_double_ge(fabs(Jt), 0.99 * F * Jn);
    }
    free(v);
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
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, 0, 0.5, 0, 2e-3, &kTheta1};
  block_spec f = b;
  f.law = ND_FRICTION_NONE;
  nd_problem p = block(&b), q = block(&f);
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
  printf("F = 0, Theta = 0: max |u - u_frictionless| = %.2e (max |u| %.2e)\n", diff, scale);
  ck_assert_double_le(diff, 1e-9 * scale);
  free(up), free(uq);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
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
      const block_spec b = {2, 1, ND_FRICTION_COULOMB, 0.3, alphas[a], 1, 2e-3, &nd_test_schemes[k]};
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
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, F, 0, 1, 1e-3, &kTheta1};
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
      const block_spec b = {dim, 1, cases[c].law, cases[c].coefficient, cases[c].alpha, 1, 2e-3, &kHybrid};
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
   the uninterrupted one (the slip references travel in the checkpoint); a
   frictionless problem refuses it. 2D and 3D (in 3D the tangent's
   preconditioner is made from the state's tangent history: the same one). */
START_TEST(restart_is_bitwise) {
  const int dim = _i;
  const block_spec b = {dim, 1, ND_FRICTION_COULOMB, 0.3, 0.5, 1, 2e-3, &kHybrid};
  nd_problem p = block(&b), q = block(&b);
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
  ck_assert_double_eq(scalar(p, ND_DISSIPATION_FRICTION), scalar(q, ND_DISSIPATION_FRICTION));
  block_spec f = b;
  f.law = ND_FRICTION_NONE;
  nd_problem r = block(&f);
  ck_assert_int_eq(nd_problem_load_state(r, size, buf), ND_ERR_STATE);
  free(buf), free(up), free(uq);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
  ND_OK_OR_FAIL(nd_problem_destroy(&r));
}
END_TEST

/* A run against a moving plane resumed from a checkpoint is bitwise the
   uninterrupted one: the planes' points at t^n travel in the checkpoint's
   friction section, and the next step's shift of the references is the
   same. 2D and 3D, the hybrid scheme, the block dragged (sliding). */
START_TEST(restart_moving_plane_is_bitwise) {
  const double v = 0.3;
  for (int dim = 2; dim <= 3; ++dim) {
    const block_spec b = {dim, 1, ND_FRICTION_COULOMB, 0.3, 0.1, 1, 2e-3, &kHybrid};
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
  const block_spec b = {2, 1, ND_FRICTION_COULOMB, 0.3, 0.5, 1, 2e-3, &kTheta1};
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
  tcase_add_test(tc, coulomb_tangential_is_F_times_normal);
  tcase_add_test(tc, coulomb_momentum_is_the_impulse);
  tcase_add_test(tc, coulomb_sticks_below_the_angle);
  tcase_add_test(tc, tresca_threshold);
  tcase_add_test(tc, hybrid_ledger_never_increases);
  tcase_add_test(tc, launched_block_stops);
  tcase_add_test(tc, oblique_impact_at_gross_slip);
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
