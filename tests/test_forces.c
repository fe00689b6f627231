/* Forces out and the moving obstacle (docs/design.md §8), through the public API:
 * the nodal contact force sums to the resultant times the plane's normal
 * (clamped nodes included); nd_problem_set_contact_plane replaces a region's
 * plane; a moving plane's work closes the hybrid scheme's energy identity;
 * Galilean invariance: a free body hitting a plane that moves at constant
 * velocity w is, in the moving frame, the fixed-plane problem with initial
 * velocity v0 - w; setting the same point again changes nothing. */
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

/* a block [0,2] x [y0,y0+1] (x [0,1]), or the interval [y0, y0+1] in 1D:
   region 1 the bottom (contact), region 2 the side x = 0; of simplices, or
   (quads) of quadrilaterals or hexahedra */
static nd_problem block_of(int dim, int degree, double y0, int quads) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  if (dim == 1) {
    const double lo = y0 - 0.5, hi = y0 + 0.5, lo2 = y0 + 0.5, hi2 = y0 + 1.5;
    ND_OK_OR_FAIL(nd_mesh_create_interval(12, y0, y0 + 1, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo, &hi));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo2, &hi2));
  } else {
    const double lo[3] = {0, y0, 0}, hi[3] = {2, y0 + 1, 1};
    const double l1[3] = {-1, y0 - 1e-3, -1}, h1[3] = {3, y0 + 1e-3, 3};
    const double l2[3] = {-1e-3, -9, -9}, h2[3] = {1e-3, 9, 9};
    if (dim == 2) ND_OK_OR_FAIL(nd_mesh_create_rectangle_cells(6, 3, lo, hi, quads ? ND_CELL_QUADRILATERAL : 0, &m));
    if (dim == 3) ND_OK_OR_FAIL(nd_mesh_create_box_cells(4, 2, 2, lo, hi, quads ? ND_CELL_HEXAHEDRON : 0, &m));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, l1, h1));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, l2, h2));
  }
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 10.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50)); /* to round-off */
  return p;
}
static nd_problem block(int dim, int degree, double y0) { return block_of(dim, degree, y0, 0); }

/* the plane's normal: +x in 1D, +y otherwise */
static void normal_of(int dim, double *nu) {
  nu[0] = dim == 1 ? 1 : 0;
  nu[1] = dim == 1 ? 0 : 1;
  nu[2] = 0;
}

static double *get(nd_problem p, int field, int dim) {
  const int64_t n = nodes(p);
  double *f = malloc(sizeof(double) * (size_t)(n * dim));
  ND_OK_OR_FAIL(nd_get_field(p, field, n, f));
  return f;
}

static const nd_test_scheme *const schemes = nd_test_schemes;
enum { N_SCHEMES = ND_TEST_N_SCHEMES };

/* Partition of unity: sum_i sum_q w_q lambda_q a_q(i) = sum_q w_q lambda_q n
   = ND_CONTACT_FORCE nu_o, over all nodes, clamped ones included (the
   bottom meets the clamped side at x = 0). Round-off of a sum of
   ~n_q terms of the force's size: 1e-13 relative. */
START_TEST(contact_force_sums_to_the_resultant) {
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree) {
      nd_problem p = block(dim, degree, 0.0);
      const double g[3] = {dim == 1 ? -2 : 0, dim == 1 ? 0 : -2, 0}, nm[2] = {0.25, 0.5}, o[3] = {0, 0, 0};
      double nu[3];
      normal_of(dim, nu);
      if (dim > 1) ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, nu));
      ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm));
      ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.01));
      int checked = 0, clamped_loaded = 0;
      for (int k = 0; k < 40; ++k) {
        ND_OK_OR_FAIL(nd_step(p));
        const double res = scalar(p, ND_CONTACT_FORCE);
        if (res == 0) continue;
        double *C = get(p, ND_FIELD_CONTACT_FORCE, dim), *R = get(p, ND_FIELD_REACTION, dim);
        double sum[3] = {0, 0, 0}, mag = 0;
        for (int64_t i = 0; i < nodes(p) * dim; ++i) {
          sum[i % dim] += C[i];
          mag += fabs(C[i]);
          clamped_loaded += R[i] != 0 && C[i] != 0;
        }
        for (int c = 0; c < dim; ++c)
          ck_assert_msg(fabs(sum[c] - res * nu[c]) <= 1e-13 * mag, "%dD P%d: sum %.17g, resultant %.17g", dim, degree,
                        sum[c], res * nu[c]);
        ++checked;
        free(C);
        free(R);
      }
      ck_assert_int_gt(checked, 10);
      if (dim > 1) ck_assert_int_gt(clamped_loaded, 0); /* a clamped node carries contact force */
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

/* a plane oscillating along its normal */
static double plane_at(double t) { return 0.02 * sin(2 * t); }

static void set_plane_1d(nd_problem p, double x) {
  const double up = 1;
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &x, &up));
}

/* Setting a region's plane twice is setting it once (it used to add a second
   plane: twice the contact force); the same point again changes nothing. */
START_TEST(a_plane_is_replaced_not_added) {
  nd_problem a = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 1.0 / 80);
  nd_problem b = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 1.0 / 80);
  nd_problem c = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 1.0 / 80);
  set_plane_1d(b, 0.0);
  set_plane_1d(c, 0.3); /* before setup: the initial plane, replaced again below */
  set_plane_1d(c, 0.0);
  int64_t qa = 0, qb = 0;
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(a, &qa));
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(b, &qb));
  ck_assert_int_eq(qa, qb);
  for (int k = 0; k < 160; ++k) {
    set_plane_1d(b, 0.0); /* every step: no motion */
    ND_OK_OR_FAIL(nd_step(a));
    ND_OK_OR_FAIL(nd_step(b));
    ND_OK_OR_FAIL(nd_step(c));
  }
  double *ua = get(a, ND_FIELD_DISPLACEMENT, 1), *ub = get(b, ND_FIELD_DISPLACEMENT, 1),
         *uc = get(c, ND_FIELD_DISPLACEMENT, 1);
  ck_assert(memcmp(ua, ub, sizeof(double) * (size_t)nodes(a)) == 0);
  ck_assert(memcmp(ua, uc, sizeof(double) * (size_t)nodes(a)) == 0);
  ck_assert(scalar(b, ND_WORK_OBSTACLE) == 0);
  free(ua);
  free(ub);
  free(uc);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
  ND_OK_OR_FAIL(nd_problem_destroy(&c));
}
END_TEST

/* The loop a host writes: f(0) and the plane's x(0) in force with the initial
   state, then per step f(t^{n+1}), x(t^{n+1}) and nd_step, with no other call.
   Before the first step the first value of each load and position is t^0's
   and a second one t^1's, so that loop, whatever the order of the initial
   state and the loads, is the trajectory of the explicit one (nd_problem_setup
   fixing t^0's values): bitwise, for every scheme. A run given f(t^1) alone
   before its first step differs (F^0 enters A^0 and the work W). */
static double load_at(double t) { return 0.3 * cos(3 * t); }

static void set_time_data(nd_problem p, double t) {
  const int64_t n = nodes(p);
  double *f = calloc((size_t)n, sizeof(double));
  f[n / 3] = load_at(t);
  ND_OK_OR_FAIL(nd_problem_set_nodal_forces(p, n, f));
  free(f);
  set_plane_1d(p, plane_at(t));
}

enum { LOOP_SETUP, LOOP_NATURAL, LOOP_STATE_FIRST, LOOP_RESTARTED, LOOP_NO_F0 };

static double *run_loop(const nd_test_scheme *sc, int how, double *work) {
  const double tau = nd_test_is_explicit(sc) ? 1.0 / 200 : 1.0 / 40;
  nd_problem p = nd_test_bar(20, 1, sc->scheme, sc->params, 1.0, 0.2, tau);
  if (nd_test_is_explicit(sc)) ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  const int64_t n = nodes(p);
  double *x = malloc(sizeof(double) * (size_t)n), *u0 = malloc(sizeof(double) * (size_t)n);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, x));
  for (int64_t i = 0; i < n; ++i) u0[i] = 0.5 * (1 - x[i]);
  if (how == LOOP_STATE_FIRST) ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, NULL));
  if (how == LOOP_RESTARTED) { /* a first run with other loads, then a new start */
    for (int k = 0; k < 5; ++k) {
      set_time_data(p, 1 + k * tau);
      ND_OK_OR_FAIL(nd_step(p));
    }
    ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, u0, NULL));
  }
  if (how != LOOP_NO_F0) set_time_data(p, 0);
  if (how == LOOP_SETUP) ND_OK_OR_FAIL(nd_problem_setup(p));
  for (int k = 0; k < 40; ++k) {
    set_time_data(p, (k + 1) * tau);
    ND_OK_OR_FAIL(nd_step(p));
  }
  *work = scalar(p, ND_WORK) + scalar(p, ND_WORK_OBSTACLE);
  double *u = get(p, ND_FIELD_DISPLACEMENT, 1);
  free(x);
  free(u0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  return u;
}

START_TEST(the_natural_loop_starts_from_f0) {
  const nd_test_scheme *sc = &schemes[_i];
  const size_t bytes = sizeof(double) * 21;
  double w_ref = 0, w = 0;
  double *ref = run_loop(sc, LOOP_SETUP, &w_ref);
  for (int how = LOOP_NATURAL; how <= LOOP_RESTARTED; ++how) {
    double *u = run_loop(sc, how, &w);
    ck_assert_msg(memcmp(u, ref, bytes) == 0 && w == w_ref, "scheme %d (%g, %g), loop %d", sc->scheme,
                  sc->params[0], sc->params[1], how);
    free(u);
  }
  double *u = run_loop(sc, LOOP_NO_F0, &w);
  ck_assert_msg(memcmp(u, ref, bytes) != 0 || w != w_ref, "F^0 = f(t^1) left the trajectory and the work unchanged");
  free(u);
  free(ref);
}
END_TEST

/* Hybrid, Theta = 1 (derived in src/problem/integrator.cpp, advance()): per step
     E_Theta^{n+1} - E_Theta^n = (W^{n+1} - W^n) + (Wo^{n+1} - Wo^n) - D,
   D = sum_q (w/gamma)(Phi_q dP_q - ([P^{n+1}]_+^2 - [P^n]_+^2)/2) >= 0,
   and D = 0 when no point changed sides (persistent contact or flight).
   The plane moves; round-off relative to the energies involved. */
START_TEST(hybrid_energy_identity_with_a_moving_plane) {
  for (int dim = 1; dim <= 2; ++dim) {
    nd_problem p = NULL;
    int steps = 320;
    if (dim == 1) {
      p = nd_test_bar(40, 2, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, 1.0 / 80);
      ND_OK_OR_FAIL(nd_problem_set_newton(p, 0, 0, 50));
    } else {
      const double g[2] = {0, -1}, up[2] = {0, 1}, o[2] = {0, 0};
      p = block(2, 2, 0.02);
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, up));
      ND_OK_OR_FAIL(nd_problem_set_body_force(p, g));
      ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
      ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.01));
    }
    const double tau = scalar(p, ND_TIMESTEP);
    int64_t nq = 0;
    ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &nq));
    double *l0 = malloc(sizeof(double) * (size_t)nq), *l1 = malloc(sizeof(double) * (size_t)nq);
    ND_OK_OR_FAIL(nd_problem_setup(p));
    ND_OK_OR_FAIL(nd_get_contact_pressure(p, nq, l0));
    double E0 = scalar(p, ND_ENERGY_AUGMENTED), W0 = scalar(p, ND_WORK), O0 = scalar(p, ND_WORK_OBSTACLE);
    int exact = 0, pushed = 0;
    double worst = 0;
    for (int k = 0; k < steps; ++k) {
      double o[3] = {0, 0, 0}, nu[3];
      normal_of(dim, nu);
      o[dim - 1] = plane_at((k + 1) * tau); /* where the plane is at t^{n+1} */
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, o, nu));
      ND_OK_OR_FAIL(nd_step(p));
      ND_OK_OR_FAIL(nd_get_contact_pressure(p, nq, l1));
      const double E1 = scalar(p, ND_ENERGY_AUGMENTED), W1 = scalar(p, ND_WORK), O1 = scalar(p, ND_WORK_OBSTACLE);
      const double gap = (E1 - E0) - (W1 - W0) - (O1 - O0);
      const double tol = 2e-12 * (fabs(E1) + fabs(W1) + fabs(O1));
      int same_sides = 1;
      for (int64_t q = 0; q < nq; ++q) same_sides &= (l0[q] < 0) == (l1[q] < 0);
      if (same_sides) {
        ck_assert_msg(fabs(gap) <= tol, "%dD step %d: E_Theta changed by %.17g, W by %.17g, W_obstacle by %.17g", dim,
                      k, E1 - E0, W1 - W0, O1 - O0);
        worst = fmax(worst, fabs(gap) / (fabs(E1) + fabs(W1) + fabs(O1)));
        ++exact;
        pushed += O1 != O0;
      } else {
        ck_assert_msg(gap <= tol, "%dD step %d: E_Theta - W - W_obstacle grew by %.17g", dim, k, gap);
      }
      E0 = E1, W0 = W1, O0 = O1;
      double *sw = l0;
      l0 = l1, l1 = sw;
    }
    ck_assert_msg(pushed > 10, "%dD: only %d steps with the moving plane doing work", dim, pushed);
    printf("hybrid %dD: %d steps exact (%d with obstacle work), worst %.3g, W_obstacle = %.6g\n", dim, exact, pushed,
           worst, O0);
    free(l0);
    free(l1);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* A free body (no clamped region, no load) hitting a plane moving at
   constant velocity w is the fixed-plane problem with v0 - w plus the
   translation w t: every scheme integrates a uniform translation exactly (K,
   s_q and the gaps are blind to it), so the two runs differ by round-off only:
   of the translation (|w| t eps per operation) carried through the
   contact solve's conditioning. On simplices (_i = 0) and Q cells (_i = 1:
   1D is the same run again, skipped). */
START_TEST(galilean_invariance) {
  const double w_all[3] = {0.3, 0.5, -0.2}, v0_all[3] = {0.2, -1, 0.1};
  double worst = 0;
  for (int dim = 1 + _i; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (int s = 0; s < N_SCHEMES; ++s) {
        const int expl = nd_test_is_explicit(&schemes[s]);
        const double tau = expl ? 5e-4 : 0.005;
        const int steps = expl ? 600 : 60;
        double nu[3], w[3] = {0, 0, 0}, v0[3] = {0, 0, 0};
        normal_of(dim, nu);
        for (int c = 0; c < dim; ++c) w[c] = dim == 1 ? 0.5 : w_all[c], v0[c] = dim == 1 ? -1 : v0_all[c];
        nd_problem mov = block_of(dim, degree, 0.02, _i), fix = block_of(dim, degree, 0.02, _i);
        const int64_t n = nodes(mov);
        double *vm = malloc(sizeof(double) * (size_t)(n * dim)), *vf = malloc(sizeof(double) * (size_t)(n * dim));
        for (int64_t i = 0; i < n * dim; ++i) vm[i] = v0[i % dim], vf[i] = v0[i % dim] - w[i % dim];
        nd_problem both[2] = {mov, fix};
        const double o[3] = {0, 0, 0};
        for (int k = 0; k < 2; ++k) {
          ND_OK_OR_FAIL(nd_problem_set_contact_plane(both[k], 1, o, nu));
          ND_OK_OR_FAIL(nd_problem_set_scheme(both[k], schemes[s].scheme, schemes[s].params));
          ND_OK_OR_FAIL(nd_problem_set_timestep(both[k], tau));
          ND_OK_OR_FAIL(nd_problem_set_mass_lumping(both[k], expl));
          ND_OK_OR_FAIL(nd_problem_set_initial_state(both[k], n, NULL, k == 0 ? vm : vf));
        }
        double maxd = 0, scale = 0, active = 0;
        for (int k = 1; k <= steps; ++k) {
          const double t = k * tau;
          double om[3];
          for (int c = 0; c < 3; ++c) om[c] = w[c] * t;
          ND_OK_OR_FAIL(nd_problem_set_contact_plane(mov, 1, om, nu));
          ND_OK_OR_FAIL(nd_step(mov));
          ND_OK_OR_FAIL(nd_step(fix));
          active = fmax(active, scalar(fix, ND_ACTIVE_POINTS));
          double *um = get(mov, ND_FIELD_DISPLACEMENT, dim), *uf = get(fix, ND_FIELD_DISPLACEMENT, dim);
          double *Vm = get(mov, ND_FIELD_VELOCITY, dim), *Vf = get(fix, ND_FIELD_VELOCITY, dim);
          for (int64_t i = 0; i < n * dim; ++i) {
            maxd = fmax(maxd, fabs(um[i] - w[i % dim] * t - uf[i]));
            maxd = fmax(maxd, tau * fabs(Vm[i] - w[i % dim] - Vf[i]));
            scale = fmax(scale, fmax(fabs(um[i]), fabs(uf[i])));
          }
          free(um), free(uf), free(Vm), free(Vf);
        }
        ck_assert_msg(active > 0, "%dD P%d scheme %d: the body never touched the plane", dim, degree, s);
        ck_assert_msg(maxd <= 1e-11 * scale, "%dD P%d scheme %d: moving frame differs by %.3g (scale %.3g)", dim,
                      degree, s, maxd, scale);
        worst = fmax(worst, maxd / scale);
        free(vm), free(vf);
        ND_OK_OR_FAIL(nd_problem_destroy(&mov));
        ND_OK_OR_FAIL(nd_problem_destroy(&fix));
      }
  printf("galilean (%s): worst relative difference %.3g\n", _i ? "Q cells" : "simplices", worst);
}
END_TEST

/* A body at rest on a plane that then lifts it: E^0 = 0 and no load, so
   only the obstacle's work lets the energy guard accept the energy the
   push puts in. */
START_TEST(energy_guard_counts_the_obstacle_work) {
  nd_problem p = block(1, 1, 0.0);
  const double up = 1, tau = 0.01;
  double x0 = 0;
  ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &x0, &up));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, tau));
  ND_OK_OR_FAIL(nd_problem_setup(p)); /* from now on a point is the next step's */
  for (int k = 1; k <= 100; ++k) {
    x0 = 0.5 * tau * (k < 20 ? k : 20); /* up at speed 0.5, then still */
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &x0, &up));
    ND_OK_OR_FAIL(nd_step(p));
  }
  const double E = scalar(p, ND_ENERGY_MECHANICAL), Wo = scalar(p, ND_WORK_OBSTACLE);
  ck_assert_msg(E > 0 && Wo > 0 && E <= 2 * Wo, "E = %g, W_obstacle = %g", E, Wo);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("forces");
  TCase *tc = tcase_create("forces");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, contact_force_sums_to_the_resultant);
  tcase_add_test(tc, a_plane_is_replaced_not_added);
  tcase_add_loop_test(tc, the_natural_loop_starts_from_f0, 0, ND_TEST_N_SCHEMES);
  tcase_add_test(tc, hybrid_energy_identity_with_a_moving_plane);
  tcase_add_loop_test(tc, galilean_invariance, 0, 2);
  tcase_add_test(tc, energy_guard_counts_the_obstacle_work);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
