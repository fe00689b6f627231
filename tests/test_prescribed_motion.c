/* Prescribed motion on Dirichlet regions (docs/design.md §10.5), through the
 * public API: a bar pushed at constant speed into a rigid wall against the
 * closed-form wave solution (reaction rho c v, contact force doubling at the
 * wall), which the lumped P1 central difference at Courant number 1
 * reproduces exactly at the nodes; the hybrid scheme's ledger
 * E_Theta - W - W_obstacle - W_prescribed, step by step, in 1D and 2D; a
 * rigid translation of every clamped region of a body in free flight
 * carried exactly by every scheme (u = d(t) everywhere, no stress, no
 * reaction); no refactorization when only the values change; a restart from
 * a checkpoint bitwise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static int64_t nodes(nd_problem p) {
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  return n;
}

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

static double *field(nd_problem p, int which, int dim) {
  const int64_t n = nodes(p);
  double *f = malloc(sizeof(double) * (size_t)(n * dim));
  ND_OK_OR_FAIL(nd_get_field(p, which, n, f));
  return f;
}

/* The bar (0, 1) in N cells, E = rho = 1 (c = 1): region 1 the end x = 0,
   clamped and pushed; region 2 the end x = 1, against the rigid plane x = 1. */
static nd_problem pushed_bar(int N) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo1 = -0.1, hi1 = 0.1, lo2 = 0.9, hi2 = 1.1, wall = 1, normal = -1;
  ND_OK_OR_FAIL(nd_mesh_create_interval(N, 0, 1, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo1, &hi1));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo2, &hi2));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 2, &wall, &normal));
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50));
  return p;
}

/* The pushed end moves at v from t = 0 (its velocity at t^0 is v, the bar at
   rest): the wave u = v (t - x/c)_+ and its reflections from the wall. At the
   nodes, with h = c tau, the lumped P1 central difference is the exact
   d'Alembert recursion u_j^{n+1} = u_{j+1}^n + u_{j-1}^n - u_j^{n-1}; the
   Nitsche wall keeps its node at 0 exactly (its row reads u_N only while
   active, and P = gamma E u_{N-1}/h), so it is the clamped end of the
   reflection and the contact force is E u_{N-1}/h. In units of rho c v:
     reaction at t^n (n >= 1): 1 until the reflection returns (n < 2N), 2 at
     n = 2N (half a cell of it), 3 after (until n = 4N);
     contact force: 0 for n < N, 1 at n = N, 2 after, 3 at n = 3N (the next
     wave's front at the wall).
   Round-off only: the nodal values are sums of v h, the differences read
   ~n of them: 1e-12 relative for n <= 3N = 90.
   Started from rest instead (the support's velocity 0 at t^0), the
   clamped DOFs' backward differences of an explicit scheme give V_c^1 = v,
   A_c^1 = v/tau, then A_c = 0: the free nodes are the same (a lumped mass
   couples none of them to the end node), and the first reaction gains the
   end node's momentum over the step, (rho h/2) v / tau = rho c v / 2. */
START_TEST(bar_pushed_into_the_wall_closed_form) {
  const int N = 30, from_rest = _i;
  const double v = 0.01, h = 1.0 / N, tau = h, rcv = 1.0 * 1.0 * v;
  const double nm[2] = {0, 0.5};
  nd_problem p = pushed_bar(N);
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.5)); /* gamma0 = 1/(2E): K_Theta >= 0, the wall row stable */
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  /* Courant number 1 is the lumped chain's limit 2/omega_max, up to the
     estimate's round-off: the guard would refuse the step it allows */
  ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_CRITICAL_TIMESTEP, 0));
  const int64_t n = nodes(p);
  double *v0 = calloc((size_t)n, sizeof(double));
  v0[0] = from_rest ? 0 : v; /* the pushed end's velocity at t^0 (node 0 is at x = 0) */
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v0));
  const double zero = 0;
  ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, &zero)); /* t^0 */
  for (int k = 1; k <= 3 * N; ++k) {
    const double d = v * k * tau;
    ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, &d)); /* t^{k} */
    ND_OK_OR_FAIL(nd_step(p));
    double *R = field(p, ND_FIELD_REACTION, 1), *U = field(p, ND_FIELD_DISPLACEMENT, 1);
    const double reaction = (k < 2 * N ? 1 : k == 2 * N ? 2 : 3) + (from_rest && k == 1 ? 0.5 : 0);
    const double contact = k < N ? 0 : k == N ? 1 : k < 3 * N ? 2 : 3;
    ck_assert_msg(fabs(U[0] - d) <= 1e-15 * d, "step %d: u(0) = %.17g, prescribed %.17g", k, U[0], d);
    ck_assert_msg(fabs(R[0] - reaction * rcv) <= 1e-12 * rcv, "step %d: reaction %.17g, closed form %.17g", k, R[0],
                  reaction * rcv);
    const double F = scalar(p, ND_CONTACT_FORCE);
    ck_assert_msg(fabs(F - contact * rcv) <= 1e-12 * rcv, "step %d: contact force %.17g, closed form %.17g", k, F,
                  contact * rcv);
    free(R);
    free(U);
  }
  free(v0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* A 2D strip [0, 2] x [0, 1] (6 x 3 squares), or the bar: region 1 the end
   x = 0 (clamped, moved), region 2 the end x = 2 (x = 1 in 1D) against a
   plane a little beyond it. */
static nd_problem strip(int dim, int degree, int lumped) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double L = dim == 1 ? 1 : 2;
  if (dim == 1) {
    ND_OK_OR_FAIL(nd_mesh_create_interval(16, 0, 1, &m));
  } else {
    const double lo[2] = {0, 0}, hi[2] = {2, 1};
    ND_OK_OR_FAIL(nd_mesh_create_rectangle(8, 4, lo, hi, &m));
  }
  const double l1[2] = {-1e-3, -9}, h1[2] = {1e-3, 9}, l2[2] = {L - 1e-3, -9}, h2[2] = {L + 1e-3, 9};
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, l1, h1));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, l2, h2));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 1));
  const double pt[2] = {L + 0.004, 0}, nu[2] = {-1, 0};
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 2, pt, nu));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50));
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, lumped));
  return p;
}

/* the support's displacement: pushed in, then pulled back (x), and shaken across (y) */
static void motion(double t, double *d) {
  d[0] = 0.02 * sin(3 * t) + 0.004 * t;
  d[1] = 0.003 * sin(5 * t);
}

/* Hybrid, Theta = 1 (docs/design.md §3 and §10.5): the step times dU over
   every DOF, the clamped ones' reactions included, gives
   E_Theta^{n+1} - E_Theta^n = dW + dW_obstacle + dW_prescribed - D^n with
   D^n = 0 unless a point changes sides. So the ledger is conserved to
   round-off on such steps and never rises on the others. Round-off: a few
   ulps of the energies' terms, summed over the DOFs: 1e-12 of the largest
   energy seen. */
START_TEST(hybrid_ledger_with_prescribed_motion) {
  for (int damped = 0; damped <= 1; ++damped)
  for (int dim = 1; dim <= 2; ++dim)
    for (int degree = 1; degree <= 2; ++degree) {
      nd_problem p = strip(dim, degree, 0);
      /* Rayleigh damping (docs/design.md §10.5): its dissipation D joins the ledger */
      if (damped) ND_OK_OR_FAIL(nd_problem_set_damping(p, 0.3, 0.02));
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
      const double tau = 0.01;
      ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
      double d[2];
      motion(0, d);
      ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
      double last = 0, scale = 0;
      int changed_sides = 0, kept = 0;
      double active_before = 0;
      for (int k = 1; k <= 300; ++k) {
        motion(k * tau, d);
        ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
        ND_OK_OR_FAIL(nd_step(p));
        const double E = scalar(p, ND_ENERGY_AUGMENTED),
                     ledger = E + scalar(p, ND_DISSIPATION_DAMPING) - scalar(p, ND_WORK) -
                              scalar(p, ND_WORK_OBSTACLE) - scalar(p, ND_WORK_PRESCRIBED);
        const double active = scalar(p, ND_ACTIVE_POINTS);
        scale = fmax(scale, fabs(E));
        if (k > 1) {
          const double tol = 1e-12 * scale;
          if (active == active_before && (active == 0 || dim == 1)) {
            /* the same points on each side (in 2D: none active before and after) */
            ck_assert_msg(fabs(ledger - last) <= tol, "%s%dD P%d step %d: ledger moved by %.3g (tolerance %.3g)",
                          damped ? "damped " : "", dim, degree, k, ledger - last, tol);
            ++kept;
          } else {
            ck_assert_msg(ledger <= last + tol, "%s%dD P%d step %d: ledger rose by %.3g", damped ? "damped " : "", dim,
                          degree, k, ledger - last);
            ++changed_sides;
          }
        }
        last = ledger, active_before = active;
      }
      ck_assert_int_gt(kept, 50);
      ck_assert_int_gt(changed_sides, 0); /* the support did push the strip into the plane */
      ck_assert(scalar(p, ND_WORK_PRESCRIBED) != 0);
      if (damped) ck_assert(scalar(p, ND_DISSIPATION_DAMPING) > 0);
      /* the energy guard (on, factor 2) counts the supports' work: from rest
         (E^0 = 0), with no load and a fixed plane, every step raising E would
         have been refused otherwise */
      if (!damped) ck_assert(scalar(p, ND_ENERGY_MECHANICAL) > 2 * (scalar(p, ND_WORK) + scalar(p, ND_WORK_OBSTACLE)));
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* the rectangle [0, 2] x [0, 1] (nx x ny, degree), E = 1, nu = 0.3, rho = 1,
   clamped at both ends (regions 1 and 2), no obstacle */
static nd_problem clamped_rectangle(int64_t nx, int64_t ny, int degree) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo[2] = {0, 0}, hi[2] = {2, 1};
  const double l1[2] = {-1e-3, -9}, h1[2] = {1e-3, 9}, l2[2] = {2 - 1e-3, -9}, h2[2] = {2 + 1e-3, 9};
  ND_OK_OR_FAIL(nd_mesh_create_rectangle(nx, ny, lo, hi, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, l1, h1));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, l2, h2));
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 1));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  return p;
}

/* A body in free flight at velocity w whose clamped regions (both ends)
   translate rigidly by d(t) = d0 + w t: u = d(t) everywhere is the exact
   solution, which every scheme integrates exactly (its updates are exact
   for motions linear in t); no stress, so no reaction and no work of the
   supports, and the energy and momentum are the whole body's, m |w|^2 / 2
   and m w (m = rho |Omega| = 2). Round-off: 1e-12 of the motion. The
   nodal form sets the same values on every clamped node. */
START_TEST(rigid_translation_is_exact) {
  const int i = _i;
  const nd_test_scheme *s = &nd_test_schemes[i];
  /* run 2: with stiffness-proportional damping C = beta K, which a rigid
     motion does not strain: exact still, only if the supports' C_fc V_c
     is in the free rows (C_ff V_f alone is not zero) */
  for (int run = 0; run <= 2; ++run) {
    const int nodal = run == 1, damped = run == 2;
    nd_problem p = clamped_rectangle(6, 3, 2);
    const int expl = nd_test_is_explicit(s);
    ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, expl));
    ND_OK_OR_FAIL(nd_problem_set_scheme(p, s->scheme, s->params));
    if (damped) ND_OK_OR_FAIL(nd_problem_set_damping(p, 0, 0.05));
    const double tau = expl ? 0.01 : 0.05, w[2] = {0.3, -0.2}, d0[2] = {0.01, 0.02};
    ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
    const int64_t n = nodes(p);
    double *u0 = malloc(sizeof(double) * (size_t)(2 * n)), *v0 = malloc(sizeof(double) * (size_t)(2 * n));
    for (int64_t j = 0; j < 2 * n; ++j) u0[j] = d0[j % 2], v0[j] = w[j % 2];
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, v0));
    for (int k = 0; k <= 40; ++k) { /* k = 0: t^0's value, then t^k's before step k */
      const double t = k * tau, d[2] = {d0[0] + w[0] * t, d0[1] + w[1] * t};
      if (nodal) {
        for (int64_t j = 0; j < 2 * n; ++j) u0[j] = d[j % 2];
        ND_OK_OR_FAIL(nd_problem_set_dirichlet_nodal(p, n, u0));
      } else {
        ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
        ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 2, d));
      }
      if (k == 0) continue;
      ND_OK_OR_FAIL(nd_step(p));
      double *U = field(p, ND_FIELD_DISPLACEMENT, 2), *V = field(p, ND_FIELD_VELOCITY, 2),
             *R = field(p, ND_FIELD_REACTION, 2);
      for (int64_t j = 0; j < 2 * n; ++j) {
        ck_assert_msg(fabs(U[j] - d[j % 2]) <= 1e-12, "scheme %d step %d: u[%ld] = %.17g, d = %.17g", i, k, (long)j,
                      U[j], d[j % 2]);
        ck_assert_msg(fabs(V[j] - w[j % 2]) <= 1e-11, "scheme %d step %d: v[%ld] = %.17g, w = %.17g", i, k, (long)j,
                      V[j], w[j % 2]);
        ck_assert_msg(fabs(R[j]) <= 1e-11, "scheme %d step %d: reaction[%ld] = %.3g", i, k, (long)j, R[j]);
      }
      const double kinetic = 0.5 * 2 * (w[0] * w[0] + w[1] * w[1]);
      ck_assert_msg(fabs(scalar(p, ND_ENERGY_MECHANICAL) - kinetic) <= 1e-12 * kinetic, "scheme %d: E = %.17g, %.17g",
                    i, scalar(p, ND_ENERGY_MECHANICAL), kinetic);
      ck_assert_msg(fabs(scalar(p, ND_WORK_PRESCRIBED)) <= 1e-12, "scheme %d: W_prescribed %.3g", i,
                    scalar(p, ND_WORK_PRESCRIBED));
      ck_assert_msg(fabs(scalar(p, ND_DISSIPATION_DAMPING)) <= 1e-12, "scheme %d: D_damping %.3g", i,
                    scalar(p, ND_DISSIPATION_DAMPING));
      for (int c = 0; c < 2; ++c) /* the whole body's momentum m w, the supports' nodes included */
        ck_assert_msg(fabs(scalar(p, ND_MOMENTUM_X + c) - 2 * w[c]) <= 1e-12, "scheme %d: momentum %.17g, m w %.17g", i,
                      scalar(p, ND_MOMENTUM_X + c), 2 * w[c]);
      free(U);
      free(V);
      free(R);
    }
    free(u0);
    free(v0);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* Hybrid scheme, Rayleigh damping C = alpha M + beta K, one support moving
   and the other fixed, no load, no contact: summing the step's mean
   equation over every DOF, the supports' rows giving the reactions,
   K's and beta K's columns sum to zero (a rigid translation is in K's
   kernel) and alpha M's to alpha P, so
     P^{n+1} - P^n = tau (sum R - alpha (P^{n+1} + P^n)/2)
   per component (P the whole body's momentum, the supports' nodes
   included). The reactions must carry C's clamped rows (C_cf V_f + C_cc
   V_c) for it to hold. Round-off: 1e-12 of the momenta's scale. */
START_TEST(damped_momentum_with_a_moving_support) {
  const double alpha = 0.4, beta = 0.03, tau = 0.02;
  nd_problem p = clamped_rectangle(8, 4, 1);
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  ND_OK_OR_FAIL(nd_problem_set_damping(p, alpha, beta));
  const int64_t n = nodes(p);
  double worst = 0, scale = 0, d[2];
  for (int k = 0; k <= 200; ++k) {
    motion(k * tau, d);
    ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
    if (k == 0) continue;
    const double P0[2] = {scalar(p, ND_MOMENTUM_X), scalar(p, ND_MOMENTUM_Y)};
    ND_OK_OR_FAIL(nd_step(p));
    double *R = field(p, ND_FIELD_REACTION, 2);
    for (int c = 0; c < 2; ++c) {
      double sumR = 0;
      for (int64_t j = 0; j < n; ++j) sumR += R[2 * j + c];
      const double P1 = scalar(p, ND_MOMENTUM_X + c);
      const double defect = (P1 - P0[c]) - tau * (sumR - alpha * 0.5 * (P1 + P0[c]));
      scale = fmax(scale, fmax(fabs(P1), tau * fabs(sumR)));
      worst = fmax(worst, fabs(defect));
    }
    free(R);
  }
  printf("damped strip, moving support: momentum balance off by %.3g (scale %.3g)\n", worst, scale);
  ck_assert_double_gt(scale, 0);
  ck_assert_double_le(worst, 1e-12 * scale);
  ck_assert(scalar(p, ND_DISSIPATION_DAMPING) > 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* Only the step's right-hand side changes with the values: A = c M + K_Theta
   on the free DOFs is factored once, and so is M for the explicit scheme. */
START_TEST(no_refactorization_when_only_the_values_change) {
  const int i = _i;
  const nd_test_scheme *s = &nd_test_schemes[i];
  nd_problem p = strip(2, 1, nd_test_is_explicit(s));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, s->scheme, s->params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, nd_test_is_explicit(s) ? 0.005 : 0.01));
  double d[2];
  motion(0, d);
  ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
  double after_first = 0;
  for (int k = 1; k <= 30; ++k) {
    motion(0.01 * k, d);
    ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
    ND_OK_OR_FAIL(nd_step(p));
    if (k == 1) after_first = scalar(p, ND_STAT_FACTORIZATIONS);
  }
  /* (the plane stays beyond the reach of this motion: no contact tangent) */
  ck_assert_double_eq(scalar(p, ND_ACTIVE_POINTS), 0);
  ck_assert_msg(scalar(p, ND_STAT_FACTORIZATIONS) == after_first, "scheme %d: %g factorizations after step 1, %g after 30",
                i, after_first, scalar(p, ND_STAT_FACTORIZATIONS));
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* A run resumed from a checkpoint is bitwise the uninterrupted one: the
   checkpoint carries the clamped DOFs' U, V, A and W_prescribed. */
START_TEST(restart_is_bitwise) {
  const int i = _i;
  const nd_test_scheme *s = &nd_test_schemes[i];
  nd_problem p = strip(2, 2, nd_test_is_explicit(s)), q = strip(2, 2, nd_test_is_explicit(s));
  const double tau = nd_test_is_explicit(s) ? 0.002 : 0.01;
  for (int r = 0; r < 2; ++r) {
    nd_problem x = r ? q : p;
    ND_OK_OR_FAIL(nd_problem_set_scheme(x, s->scheme, s->params));
    ND_OK_OR_FAIL(nd_problem_set_timestep(x, tau));
  }
  double d[2];
  motion(0, d);
  ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
  int64_t size = 0;
  unsigned char *buf = NULL;
  for (int k = 1; k <= 20; ++k) {
    motion(k * tau * 10, d);
    ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(p, 1, d));
    ND_OK_OR_FAIL(nd_step(p));
    if (k == 10) buf = nd_test_checkpoint(p, &size);
  }
  ND_OK_OR_FAIL(nd_problem_load_state(q, size, buf));
  for (int k = 11; k <= 20; ++k) {
    motion(k * tau * 10, d);
    ND_OK_OR_FAIL(nd_problem_set_dirichlet_value(q, 1, d));
    ND_OK_OR_FAIL(nd_step(q));
  }
  const int fields[4] = {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY, ND_FIELD_ACCELERATION, ND_FIELD_REACTION};
  for (int f = 0; f < 4; ++f) {
    double *a = field(p, fields[f], 2), *b = field(q, fields[f], 2);
    ck_assert_msg(memcmp(a, b, sizeof(double) * (size_t)(2 * nodes(p))) == 0, "scheme %d: field %d differs", i,
                  fields[f]);
    free(a);
    free(b);
  }
  const double wp = scalar(p, ND_WORK_PRESCRIBED), wq = scalar(q, ND_WORK_PRESCRIBED);
  ck_assert(memcmp(&wp, &wq, sizeof wp) == 0);
  ck_assert(wp != 0);
  free(buf);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

/* The region form refuses a region that is not clamped; a failed call changes nothing. */
START_TEST(only_clamped_regions_move) {
  nd_problem p = strip(2, 1, 0);
  const double d[2] = {0.1, 0};
  ck_assert_int_eq(nd_problem_set_dirichlet_value(p, 2, d), ND_ERR_REGION);
  ck_assert_int_eq(nd_problem_set_dirichlet_value(p, 7, d), ND_ERR_REGION);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("prescribed_motion");
  TCase *tc = tcase_create("prescribed_motion");
  tcase_set_timeout(tc, 600);
  tcase_add_loop_test(tc, bar_pushed_into_the_wall_closed_form, 0, 2);
  tcase_add_test(tc, hybrid_ledger_with_prescribed_motion);
  tcase_add_loop_test(tc, rigid_translation_is_exact, 0, ND_TEST_N_SCHEMES);
  tcase_add_loop_test(tc, no_refactorization_when_only_the_values_change, 0, ND_TEST_N_SCHEMES);
  tcase_add_loop_test(tc, restart_is_bitwise, 0, ND_TEST_N_SCHEMES);
  tcase_add_test(tc, only_clamped_regions_move);
  tcase_add_test(tc, damped_momentum_with_a_moving_support);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
