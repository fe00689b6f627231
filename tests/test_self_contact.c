/* One body touching itself (docs/design.md §10.3): a U-shaped body whose two
 * arms, thrown towards each other, close the slot between them. The slot's
 * two faces are two regions of the one connected body, paired as slave and
 * master (nd_problem_set_contact_pair), or one region paired with itself
 * (both faces, or the whole boundary: the pairing then skips each point's own
 * neighbourhood, the facets not facing it and those through the body): no
 * rigid obstacle, no load, so the body's momentum stays what it was to
 * round-off (the contact forces on the two faces equal and opposite; Theta =
 * 1 and 0), and the hybrid scheme with Theta = 1 keeps E_Theta - W -
 * W_geometry (+ D_f with friction) from rising (by more than one rounding of
 * its terms), while the arms meet and part (2D, P1 and P2). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "testutil.h"

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

/* [0, 2.1] x [0, 2] in cells of 0.1, without the slot [1, 1.1] x [0.5, 2]:
   two arms 1.5 high on a base 0.5 thick (thin: the arms one cell wide, [0.9,
   1] and [1.1, 1.2]); the slot's left face region 1, its right face region 2
   (not its bottom), and region 3 as the scene says */
enum { NX = 21, NY = 20, SLOT_I = 10, SLOT_J = 5 };
enum scene {
  SLOT_PAIR,  /* region 1 the slave of region 2 */
  SLOT_BOTH,  /* and 2 the slave of 1: each face's points against the other face */
  SLOT_SELF,  /* both faces one region 3, its own master: SLOT_BOTH's points and pairings */
  WHOLE_SELF  /* the whole boundary region 3, its own master */
};

/* the arms towards each other, faster towards their tips (a bending swing:
   its tip amplitude, about v/omega = 0.5/4.5, exceeds the slot's half width
   0.05), and along the slot at -+shear likewise (the faces slide) */
static void throw_arms(nd_problem p, double shear) {
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *y = malloc(sizeof(double) * (size_t)(2 * n)), *v = calloc((size_t)(2 * n), sizeof(double));
  ck_assert(y && v);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, y));
  for (int64_t k = 0; k < n; ++k)
    if (y[2 * k + 1] > 0.5) {
      const double side = y[2 * k] < 1.05 ? 1 : -1, rise = (y[2 * k + 1] - 0.5) / 1.5;
      v[2 * k] = side * 0.5 * rise, v[2 * k + 1] = -side * shear * rise;
    }
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v));
  free(y), free(v);
}

static nd_problem u_body(int degree, double theta, enum scene scene, int thin, double gamma0) {
  double x[2 * (NX + 1) * (NY + 1)];
  int64_t cells[6 * NX * NY], nc = 0;
  for (int j = 0; j <= NY; ++j)
    for (int i = 0; i <= NX; ++i) x[2 * (j * (NX + 1) + i)] = 0.1 * i, x[2 * (j * (NX + 1) + i) + 1] = 0.1 * j;
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) {
      if (i == SLOT_I && j >= SLOT_J) continue;
      if (thin && j >= SLOT_J && (i < SLOT_I - 1 || i > SLOT_I + 1)) continue;
      const int64_t a = j * (NX + 1) + i, b = a + 1, c = a + NX + 2, d = a + NX + 1;
      const int64_t t[6] = {a, b, c, a, c, d};
      for (int k = 0; k < 6; ++k) cells[nc * 3 + k] = t[k];
      nc += 2;
    }
  /* (thin: the vertices of no cell left out, the others renumbered in order) */
  int64_t at[(NX + 1) * (NY + 1)], nv = 0;
  for (int64_t v = 0; v < (NX + 1) * (NY + 1); ++v) at[v] = -1;
  for (int64_t k = 0; k < 3 * nc; ++k) at[cells[k]] = 0;
  for (int64_t v = 0; v < (NX + 1) * (NY + 1); ++v)
    if (at[v] == 0) x[2 * nv] = x[2 * v], x[2 * nv + 1] = x[2 * v + 1], at[v] = nv++;
  for (int64_t k = 0; k < 3 * nc; ++k) cells[k] = at[cells[k]];
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create(2, nv, x, nc, cells, &m));
  const double lo1[2] = {0.99, 0.45}, hi1[2] = {1.01, 2.01}, lo2[2] = {1.09, 0.45}, hi2[2] = {1.11, 2.01};
  const double all_lo[2] = {-1, -1}, all_hi[2] = {3, 3};
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, lo1, hi1));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, lo2, hi2));
  if (scene == SLOT_SELF) {
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 3, lo1, hi1));
    ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 3, lo2, hi2));
  }
  if (scene == WHOLE_SELF) ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 3, all_lo, all_hi));
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 100.0, 0.3, 1.0));
  if (scene == SLOT_PAIR || scene == SLOT_BOTH) ND_OK_OR_FAIL(nd_problem_set_contact_pair(p, 1, 2));
  if (scene == SLOT_BOTH) ND_OK_OR_FAIL(nd_problem_set_contact_pair(p, 2, 1));
  if (scene == SLOT_SELF || scene == WHOLE_SELF) ND_OK_OR_FAIL(nd_problem_set_contact_pair(p, 3, 3));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, gamma0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.005));
  throw_arms(p, 0.0);
  return p;
}

/* What a run measured: the largest momentum drift, ledger rise (a fraction
   of the energy's terms, Sum |K_ij U_i U_j| + Sum |M_ij V_i V_j|; with D_f),
   applied force and penetration, the steps in contact, whether the arms
   parted, active points at the first step, D_f at the end and its smallest
   step, and the largest |U - U_ref| over the nodes and steps (ref: a run in
   lockstep, NULL: none) */
typedef struct {
  double drift, worst, force, penetration, differ, dissipation, dissipation_step;
  int contact_steps, parted, first_active, same;
} run_stats;

static run_stats run(nd_problem p, nd_problem ref, int steps) {
  run_stats r = {0, 0, 0, 0, 0, 0, INFINITY, 0, 0, 0, 1};
  double P0[2] = {0, 0}, previous = 0, D_previous = 0;
  nd_test_csr K = nd_test_get_matrix(p, ND_MATRIX_STIFFNESS), M = nd_test_get_matrix(p, ND_MATRIX_MASS);
  double *U = malloc(sizeof(double) * (size_t)K.n), *V = malloc(sizeof(double) * (size_t)K.n),
         *W = malloc(sizeof(double) * (size_t)K.n);
  ck_assert(U && V && W);
  for (int k = 0; k <= steps; ++k) {
    if (k) ND_OK_OR_FAIL(nd_step(p));
    if (k && ref) ND_OK_OR_FAIL(nd_step(ref));
    const double D = scalar(p, ND_DISSIPATION_FRICTION);
    const double ledger = scalar(p, ND_ENERGY_AUGMENTED) + D - scalar(p, ND_WORK) - scalar(p, ND_WORK_GEOMETRY);
    /* (no DOF clamped: the free DOFs are the nodal values in order) */
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, K.n / 2, U));
    ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, K.n / 2, V));
    const double scale = nd_test_csr_terms(&K, U, U) + nd_test_csr_terms(&M, V, V);
    if (k) {
      r.worst = fmax(r.worst, (ledger - previous) / scale);
      r.dissipation_step = fmin(r.dissipation_step, D - D_previous);
    }
    previous = ledger, D_previous = D;
    if (ref) {
      ND_OK_OR_FAIL(nd_get_field(ref, ND_FIELD_DISPLACEMENT, K.n / 2, W));
      for (int64_t i = 0; i < K.n; ++i) {
        r.differ = fmax(r.differ, fabs(U[i] - W[i]));
        r.same = r.same && U[i] == W[i];
      }
    }
    const double P[2] = {scalar(p, ND_MOMENTUM_X), scalar(p, ND_MOMENTUM_Y)};
    if (k == 0) P0[0] = P[0], P0[1] = P[1];
    r.drift = fmax(r.drift, fmax(fabs(P[0] - P0[0]), fabs(P[1] - P0[1])));
    const int active = scalar(p, ND_ACTIVE_POINTS) > 0;
    if (k == 1) r.first_active = (int)scalar(p, ND_ACTIVE_POINTS);
    if (active) ++r.contact_steps, r.force = fmax(r.force, scalar(p, ND_CONTACT_FORCE_APPLIED));
    r.penetration = fmax(r.penetration, scalar(p, ND_MAX_PENETRATION));
    if (r.contact_steps && !active) r.parted = 1;
  }
  r.dissipation = scalar(p, ND_DISSIPATION_FRICTION);
  nd_test_csr_free(&K), nd_test_csr_free(&M), free(U), free(V), free(W);
  return r;
}

/* |U_self - U_ref|, U of order 0.1: with the same points, rows and
   pairings, added in another order, the runs part by roundings alone, a
   few per step over 300 steps: 300 x 2.2e-16 x 0.1 = 6.7e-15 (measured up
   to 9.4e-15), allowed 1e-13. With Theta = 1 the frozen normals of every
   point, active or not, enter K_Theta (its term Theta w_q gamma_q s_q
   s_q^T, s_q the stress along n_q): a point whose new pairing differs in
   its last bits is paired anew in one run and not in the other (measured:
   565 points paired anew against 564, after the arms parted), and the
   runs' free flights then differ by that change of K_Theta (measured 1.3e-6;
   allowed 1e-5, 1e-4 of the arms' swing) */
#define ROUNDING_AGREEMENT 1e-13
#define REPAIRING_AGREEMENT 1e-5

/* the momentum's scale: the arms' |P| at t = 0 (each arm's alone) */
static const double arm = 0.5 * 0.5 * 1.5 * 1.0 * 1.0; /* mean speed 0.25, arm area 1.5, rho 1 */

/* the statements every run keeps: no external force, so the momentum stays
   to round-off (measured: below 1e-12 of an arm's; a force on one face that
   the other did not match would move it by about F tau = 1e-2 a step);
   Theta = 1: a ledger rise below one rounding of the energy's terms */
static void check_statements(const run_stats *r, int theta, double momentum_scale) {
  ck_assert_int_gt(r->contact_steps, 0); /* the slot closed */
  ck_assert_double_gt(r->force, 0);
  ck_assert_double_le(r->drift, 1e-11 * momentum_scale);
  if (theta == 1) ck_assert_double_le(r->worst, DBL_EPSILON);
}

START_TEST(a_body_closing_its_own_slot_keeps_momentum_and_the_ledger) {
  for (int degree = 1; degree <= 2; ++degree)
    for (int theta = 1; theta >= 0; --theta) {
      nd_problem p = u_body(degree, theta, SLOT_PAIR, 0, 0.0);
      const run_stats r = run(p, NULL, 300);
      printf("U-shaped body P%d Theta = %d: %d contact steps (parted: %d), largest applied force %.4g, momentum drift "
             "%.3g (of an arm's %.3g), ledger rise %.3g of its terms, W_geometry %.3g, %g points paired anew\n",
             degree, theta, r.contact_steps, r.parted, r.force, r.drift, arm, r.worst, scalar(p, ND_WORK_GEOMETRY),
             scalar(p, ND_STAT_NORMAL_REFRESHES));
      check_statements(&r, theta, arm);
      ck_assert_int_eq(r.parted, 1); /* and opened again */
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
    }
}
END_TEST

START_TEST(one_region_as_its_own_master_is_the_two_regions_both_ways) {
  /* the slot's two faces as one region paired with itself: each point skips
     its own face (its facets share a vertex with the point's or face the
     same way) and lands on the other face, the pairing of the two regions
     each the other's slave; the same points and rows, in another order (the
     region's facets in mesh order, not one face's, then the other's) */
  for (int degree = 1; degree <= 2; ++degree)
    for (int theta = 1; theta >= 0; --theta) {
      nd_problem p = u_body(degree, theta, SLOT_SELF, 0, 0.0), ref = u_body(degree, theta, SLOT_BOTH, 0, 0.0);
      const run_stats r = run(p, ref, 300);
      printf("slot faces as one self-paired region, P%d Theta = %d: %d contact steps (parted: %d), momentum drift "
             "%.3g, ledger rise %.3g of its terms, %g points paired anew (two regions: %g), largest |U - U_two| "
             "%.3g%s, largest penetration %.3g\n",
             degree, theta, r.contact_steps, r.parted, r.drift, r.worst, scalar(p, ND_STAT_NORMAL_REFRESHES),
             scalar(ref, ND_STAT_NORMAL_REFRESHES), r.differ, r.same ? " (bitwise)" : "", r.penetration);
      check_statements(&r, theta, arm);
      ck_assert_int_eq(r.parted, 1);
      ck_assert_int_eq(r.first_active, 0);
      ck_assert_double_le(r.differ, theta == 1 ? REPAIRING_AGREEMENT : ROUNDING_AGREEMENT);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      ND_OK_OR_FAIL(nd_problem_destroy(&ref));
    }
}
END_TEST

START_TEST(the_whole_boundary_as_its_own_master) {
  /* every boundary facet one region, its own master: a point of an outer
     face must not land on the inner face behind it (thin arms: one cell,
     0.1, behind, within the search's reach, facing it: kept out by the
     depth bound alone, h/2 = 0.071), nor on its own face or a neighbouring
     one at a corner; the arms still close the slot. With Theta = 0 the
     extra points, never active, add nothing: the run is the slot faces'
     (both ways) with the same gamma0 */
  for (int thin = 0; thin <= 1; ++thin)
    for (int theta = 1; theta >= 0; --theta) {
      const int steps = thin ? 120 : 300;
      /* gamma0: the two-region run's automatic one, set on both runs (the
         automatic value depends on the contact regions); thin arms with
         Theta = 1 a tenth of it, a stiffer penalty: the penetration guard's
         length, |Omega| / |Gamma_C| / 8, is small with the whole boundary
         as Gamma_C (0.12 / 8), and the automatic penalty let the arms sink
         1.1e-3 against its limit 8.2e-4 */
      nd_problem probe = u_body(1, theta, SLOT_BOTH, thin, 0.0);
      ND_OK_OR_FAIL(nd_step(probe));
      const double gamma0 = scalar(probe, ND_GAMMA0) / (thin && theta == 1 ? 10 : 1);
      ND_OK_OR_FAIL(nd_problem_destroy(&probe));
      nd_problem p = u_body(1, theta, WHOLE_SELF, thin, gamma0);
      nd_problem ref = theta == 0 ? u_body(1, theta, SLOT_BOTH, thin, gamma0) : NULL;
      const run_stats r = run(p, ref, steps);
      printf("whole boundary self-paired, %s arms, P1 Theta = %d: %d contact steps (parted: %d), %d active at the "
             "first step, momentum drift %.3g, ledger rise %.3g of its terms, %g points paired anew, largest |U - "
             "U_slot| %.3g%s, largest penetration %.3g\n",
             thin ? "thin" : "thick", theta, r.contact_steps, r.parted, r.first_active, r.drift, r.worst,
             scalar(p, ND_STAT_NORMAL_REFRESHES), r.differ, ref ? (r.same ? " (bitwise)" : "") : " (no reference)",
             r.penetration);
      check_statements(&r, theta, thin ? arm / 10 : arm); /* (a thin arm: a tenth of the area) */
      /* the arms start 0.1 apart: a point active at the first step met its own body */
      ck_assert_int_eq(r.first_active, 0);
      /* the penetrations stay far inside the depth bound h/2 */
      ck_assert_double_le(r.penetration, 0.1 * 0.5 * 0.1 * sqrt(2.0));
      if (ref) ck_assert_double_le(r.differ, ROUNDING_AGREEMENT);
      ND_OK_OR_FAIL(nd_problem_destroy(&p));
      if (ref) ND_OK_OR_FAIL(nd_problem_destroy(&ref));
    }
}
END_TEST

START_TEST(friction_on_a_region_touching_itself) {
  /* Coulomb F = 0.3 on the whole boundary paired with itself, the arms
     also thrown along the slot in opposite senses: the faces slide while
     in contact. D_f >= 0 and never decreases, the momentum is kept, and the
     Theta = 1 ledger with D_f does not rise */
  const double F = 0.3;
  nd_problem p = u_body(1, 1, WHOLE_SELF, 0, 0.0);
  ND_OK_OR_FAIL(nd_problem_set_friction(p, 3, ND_FRICTION_COULOMB, &F));
  throw_arms(p, 0.2);
  const run_stats r = run(p, NULL, 300);
  printf("whole boundary self-paired with friction, P1 Theta = 1: %d contact steps, D_f %.4g (smallest step %.3g), "
         "momentum drift %.3g, ledger rise %.3g of its terms\n",
         r.contact_steps, r.dissipation, r.dissipation_step, r.drift, r.worst);
  check_statements(&r, 1, arm);
  ck_assert_double_gt(r.dissipation, 0);     /* the faces slid in contact */
  ck_assert_double_ge(r.dissipation_step, 0); /* D_f never decreases */
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(a_restart_of_a_region_touching_itself_is_bitwise) {
  /* the whole boundary paired with itself, with friction: the checkpoint
     holds the pairings (the outer points' -1: not paired yet), normals and
     slip references; resumed after points were paired anew in contact, the
     run is the uninterrupted one */
  const double F = 0.3;
  nd_problem a = u_body(1, 1, WHOLE_SELF, 0, 0.0), b = u_body(1, 1, WHOLE_SELF, 0, 0.0);
  ND_OK_OR_FAIL(nd_problem_set_friction(a, 3, ND_FRICTION_COULOMB, &F));
  ND_OK_OR_FAIL(nd_problem_set_friction(b, 3, ND_FRICTION_COULOMB, &F));
  throw_arms(a, 0.2), throw_arms(b, 0.2);
  unsigned char *saved = NULL;
  int64_t size = 0;
  int at = 0;
  const int steps = 150;
  for (int k = 1; k <= steps; ++k) {
    ND_OK_OR_FAIL(nd_step(a));
    if (!saved && scalar(a, ND_ACTIVE_POINTS) > 0 && scalar(a, ND_STAT_NORMAL_REFRESHES) > 0)
      saved = nd_test_checkpoint(a, &size), at = k;
  }
  ck_assert_msg(saved != NULL, "no step in contact after a new pairing");
  printf("self-paired restart at step %d of %d\n", at, steps);
  ND_OK_OR_FAIL(nd_problem_load_state(b, size, saved));
  for (int k = at + 1; k <= steps; ++k) ND_OK_OR_FAIL(nd_step(b));
  nd_test_snapshot sa = nd_test_take(a, 2), sb = nd_test_take(b, 2);
  ck_assert(nd_test_same(&sa, &sb));
  ck_assert(scalar(a, ND_WORK_GEOMETRY) == scalar(b, ND_WORK_GEOMETRY));
  ck_assert(scalar(a, ND_DISSIPATION_FRICTION) == scalar(b, ND_DISSIPATION_FRICTION));
  nd_test_snapshot_free(&sa), nd_test_snapshot_free(&sb);
  free(saved);
  ND_OK_OR_FAIL(nd_problem_destroy(&a));
  ND_OK_OR_FAIL(nd_problem_destroy(&b));
}
END_TEST

int main(void) {
  Suite *s = suite_create("self_contact");
  TCase *tc = tcase_create("self_contact");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, a_body_closing_its_own_slot_keeps_momentum_and_the_ledger);
  tcase_add_test(tc, one_region_as_its_own_master_is_the_two_regions_both_ways);
  tcase_add_test(tc, the_whole_boundary_as_its_own_master);
  tcase_add_test(tc, friction_on_a_region_touching_itself);
  tcase_add_test(tc, a_restart_of_a_region_touching_itself_is_bitwise);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
