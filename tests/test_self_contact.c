/* One body touching itself (docs/design.md §10.3): a U-shaped body whose two
 * arms, thrown towards each other, close the slot between them. The slot's
 * two faces are two regions of the one connected body, paired as slave and
 * master (nd_problem_set_contact_pair): no rigid obstacle, no load, so the
 * body's momentum stays what it was to round-off (the contact forces on the
 * two faces equal and opposite; Theta = 1 and 0), and the hybrid scheme with
 * Theta = 1 keeps E_Theta - W - W_geometry from rising (by more than one
 * rounding of its terms), while the arms meet and part (2D, P1 and P2). */
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
   two arms 1.5 high on a base 0.5 thick; the slot's left face region 1, its
   right face region 2 */
enum { NX = 21, NY = 20, SLOT_I = 10, SLOT_J = 5 };

static nd_problem u_body(int degree, double theta) {
  double x[2 * (NX + 1) * (NY + 1)];
  int64_t cells[6 * NX * NY], nc = 0;
  for (int j = 0; j <= NY; ++j)
    for (int i = 0; i <= NX; ++i) x[2 * (j * (NX + 1) + i)] = 0.1 * i, x[2 * (j * (NX + 1) + i) + 1] = 0.1 * j;
  for (int j = 0; j < NY; ++j)
    for (int i = 0; i < NX; ++i) {
      if (i == SLOT_I && j >= SLOT_J) continue;
      const int64_t a = j * (NX + 1) + i, b = a + 1, c = a + NX + 2, d = a + NX + 1;
      const int64_t t[6] = {a, b, c, a, c, d};
      for (int k = 0; k < 6; ++k) cells[nc * 3 + k] = t[k];
      nc += 2;
    }
  nd_mesh m = NULL;
  ND_OK_OR_FAIL(nd_mesh_create(2, (NX + 1) * (NY + 1), x, nc, cells, &m));
  const double lo1[2] = {0.99, 0.55}, hi1[2] = {1.01, 2.01}, lo2[2] = {1.09, 0.55}, hi2[2] = {1.11, 2.01};
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, lo1, hi1));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, lo2, hi2));
  nd_problem p = NULL;
  ND_OK_OR_FAIL(nd_problem_create(m, degree, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 100.0, 0.3, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_contact_pair(p, 1, 2));
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, 0.0));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, NULL));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, 0.005));
  /* the arms towards each other, faster towards their tips (a bending
     swing: its tip amplitude, about v/omega = 0.5/4.5, exceeds the slot's
     half width 0.05) */
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *y = malloc(sizeof(double) * (size_t)(2 * n)), *v = calloc((size_t)(2 * n), sizeof(double));
  ck_assert(y && v);
  ND_OK_OR_FAIL(nd_problem_get_node_coordinates(p, n, y));
  for (int64_t k = 0; k < n; ++k)
    if (y[2 * k + 1] > 0.5) v[2 * k] = (y[2 * k] < 1.05 ? 0.5 : -0.5) * (y[2 * k + 1] - 0.5) / 1.5;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, n, NULL, v));
  free(y), free(v);
  return p;
}

START_TEST(a_body_closing_its_own_slot_keeps_momentum_and_the_ledger) {
  for (int degree = 1; degree <= 2; ++degree)
  for (int theta = 1; theta >= 0; --theta) {
    nd_problem p = u_body(degree, theta);
    double P0[2] = {0, 0}, drift = 0, previous = 0, worst = 0, force = 0;
    int contact_steps = 0, parted = 0;
    nd_test_csr K = nd_test_get_matrix(p, ND_MATRIX_STIFFNESS), M = nd_test_get_matrix(p, ND_MATRIX_MASS);
    double *U = malloc(sizeof(double) * (size_t)K.n), *V = malloc(sizeof(double) * (size_t)K.n);
    ck_assert(U && V);
    for (int k = 0; k <= 300; ++k) {
      if (k) ND_OK_OR_FAIL(nd_step(p));
      const double ledger = scalar(p, ND_ENERGY_AUGMENTED) - scalar(p, ND_WORK) - scalar(p, ND_WORK_GEOMETRY);
      /* (no DOF clamped: the free DOFs are the nodal values in order) */
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_DISPLACEMENT, K.n / 2, U));
      ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_VELOCITY, K.n / 2, V));
      const double scale = nd_test_csr_terms(&K, U, U) + nd_test_csr_terms(&M, V, V);
      if (k) worst = fmax(worst, (ledger - previous) / scale);
      previous = ledger;
      const double P[2] = {scalar(p, ND_MOMENTUM_X), scalar(p, ND_MOMENTUM_Y)};
      if (k == 0) P0[0] = P[0], P0[1] = P[1];
      drift = fmax(drift, fmax(fabs(P[0] - P0[0]), fabs(P[1] - P0[1])));
      const int active = scalar(p, ND_ACTIVE_POINTS) > 0;
      if (active) ++contact_steps, force = fmax(force, scalar(p, ND_CONTACT_FORCE_APPLIED));
      if (contact_steps && !active) parted = 1;
    }
    /* the momentum's scale: the arms' |P| at t = 0 (each arm's alone) */
    const double arm = 0.5 * 0.5 * 1.5 * 1.0 * 1.0; /* mean speed 0.25, arm area 1.5, rho 1 */
    printf("U-shaped body P%d Theta = %d: %d contact steps (parted: %d), largest applied force %.4g, momentum drift %.3g "
           "(of an arm's %.3g), ledger rise %.3g of its terms, W_geometry %.3g, %g points paired anew\n",
           degree, theta, contact_steps, parted, force, drift, arm, worst, scalar(p, ND_WORK_GEOMETRY),
           scalar(p, ND_STAT_NORMAL_REFRESHES));
    ck_assert_int_gt(contact_steps, 0); /* the slot closed */
    ck_assert_int_eq(parted, 1);        /* and opened again */
    ck_assert_double_gt(force, 0);
    /* no external force: the momentum stays to round-off (measured: below
       1e-12 of an arm's; a force on one face that the other did not match
       would move it by about F tau = 1e-2 a step) */
    ck_assert_double_le(drift, 1e-11 * arm);
    /* Theta = 1: a rise below one rounding of the energy's terms */
    if (theta == 1) ck_assert_double_le(worst, DBL_EPSILON);
    nd_test_csr_free(&K), nd_test_csr_free(&M), free(U), free(V);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("self_contact");
  TCase *tc = tcase_create("self_contact");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, a_body_closing_its_own_slot_keeps_momentum_and_the_ledger);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
