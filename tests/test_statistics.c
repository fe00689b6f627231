/* The work counters (ND_STAT_*) and the "leave out what a scene does not
 * need" table of docs/design.md §4, asserted with exact counts derived from the
 * algorithm. On the 1D bar of docs/design.md §7 (P1, 20 cells), where the work of a
 * step is:
 *  - set-up: M and K (2 matrix assemblies), K_Theta (1), for an implicit
 *    scheme A = c M + K_Theta (1), its symbolic analysis and factorization;
 *    a scheme that carries A^n (not the hybrid one) factors M once for A^0
 *    (Remark 3.2) and solves with it once; then the products of the state
 *    (M U, M V, M A, K U in one fused pass over M and K, counted as one
 *    SpMV, and P_q with u_n - g0: one contact evaluation), from which the
 *    initial-penetration guard and the energy guard's E^0 are read;
 *  - an implicit step: the right-hand side from the products of the state
 *    at t^n (no SpMV), with a contact region the predictor check: no point
 *    active at the predictor, so one solve and one check of the result; far
 *    from the obstacle each check is settled by the bound from the last
 *    evaluated P_q (P^n, or an earlier state's: below)
 *    (ND_STAT_CONTACT_BOUNDS, no contact evaluation), else it evaluates the
 *    points (one contact evaluation each); then the products of the new
 *    state (one SpMV), whose sums give the energy guard its E, and, unless
 *    the bound settled the check of the solution, its P_q (one contact
 *    evaluation): the step's contact term phi_q (the applied pressure, the
 *    obstacle's work and the reactions come from it), the next step's P^n,
 *    and u_n - g0 (the same pass) for the penetration guard. Settled by the
 *    bound, every phi_q is 0 and the points are left unevaluated: the next
 *    step's bound, and the penetration guard's, are made from the last state
 *    whose points were evaluated (a query evaluates them: one pass);
 *  - an explicit step with lumped mass: M A = F - K_Theta U - N(U) (one SpMV,
 *    one contact evaluation, a division by the lumped diagonal), the products
 *    (one SpMV; P_q and u_n - g0 from N(U)'s pass, at the same U).
 * The counters count since nd_problem_create, failed steps included, and are
 * not part of a checkpoint. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

enum { N_STEPS = 40 };

typedef struct {
  double fact, symb, solves, mat, load, tangent, contact, spmv, iters, bounds;
} stats;

static double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

static stats get(nd_problem p) {
  stats s;
  s.fact = scalar(p, ND_STAT_FACTORIZATIONS);
  s.symb = scalar(p, ND_STAT_SYMBOLIC_ANALYSES);
  s.solves = scalar(p, ND_STAT_SOLVES);
  s.mat = scalar(p, ND_STAT_MATRIX_ASSEMBLIES);
  s.load = scalar(p, ND_STAT_LOAD_ASSEMBLIES);
  s.tangent = scalar(p, ND_STAT_TANGENT_UPDATES);
  s.contact = scalar(p, ND_STAT_CONTACT_EVALUATIONS);
  s.spmv = scalar(p, ND_STAT_SPMV);
  s.iters = scalar(p, ND_NEWTON_ITERATIONS_TOTAL);
  s.bounds = scalar(p, ND_STAT_CONTACT_BOUNDS);
  return s;
}

/* b - a, field by field */
static stats since(stats a, stats b) {
  stats d = {b.fact - a.fact,       b.symb - a.symb,       b.solves - a.solves,
             b.mat - a.mat,         b.load - a.load,       b.tangent - a.tangent,
             b.contact - a.contact, b.spmv - a.spmv,       b.iters - a.iters,
             b.bounds - a.bounds};
  return d;
}

#define EXPECT(s, f, fa, sy, so, ma, lo, ta, co, sp)                                                   \
  do {                                                                                                \
    ck_assert_msg((s).fact == (fa) && (s).symb == (sy) && (s).solves == (so) && (s).mat == (ma) &&    \
                      (s).load == (lo) && (s).tangent == (ta) && (s).contact == (co) && (s).spmv == (sp), \
                  "%s: got fact %g symb %g solves %g mat %g load %g tangent %g contact %g spmv %g, "    \
                  "expected %d %d %d %d %d %d %d %d",                                                   \
                  f, (s).fact, (s).symb, (s).solves, (s).mat, (s).load, (s).tangent, (s).contact,       \
                  (s).spmv, (fa), (sy), (so), (ma), (lo), (ta), (co), (sp));                             \
  } while (0)

static const double kTau = 1.0 / 80;
static const double kFar = -10; /* an obstacle the bar never reaches */

/* the bar without an obstacle: region 1 (x = 0) free or loaded, region 2 clamped */
static nd_problem free_bar(int scheme, const double *params) {
  nd_mesh m = NULL;
  nd_problem p = NULL;
  const double lo0 = -0.5, hi0 = 0.5, lo1 = 0.5, hi1 = 1.5;
  ND_OK_OR_FAIL(nd_mesh_create_interval(20, 0.0, 1.0, &m));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 1, &lo0, &hi0));
  ND_OK_OR_FAIL(nd_mesh_mark_boundary_box(m, 2, &lo1, &hi1));
  ND_OK_OR_FAIL(nd_problem_create(m, 1, &p));
  ND_OK_OR_FAIL(nd_mesh_destroy(&m));
  ND_OK_OR_FAIL(nd_problem_set_material(p, 1.0, 0.0, 1.0));
  ND_OK_OR_FAIL(nd_problem_set_dirichlet(p, 2));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, scheme, params));
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, kTau));
  return p;
}

static void steps(nd_problem p, int n, int iterations_each) {
  for (int k = 0; k < n; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    if (iterations_each >= 0) ck_assert_int_eq((int)scalar(p, ND_NEWTON_ITERATIONS), iterations_each);
  }
}

START_TEST(free_flight_implicit) {
  /* hybrid: one factorization at set-up, then one solve per step and one
     Newton iteration, no Newton SpMV */
  nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  stats s0 = get(p);
  EXPECT(s0, "hybrid set-up", 1, 1, 0, 4, 0, 0, 1, 1); /* the products (and P_q) of the state */
  steps(p, N_STEPS, 1);
  stats d = since(s0, get(p));
  /* per step one pass over M and K: the products of the new state, which
     give its energy (the guard) and the next right-hand side; the
     predictor and the linear step, 10 below the bar, checked by the bound
     from the set-up's P_q (the last evaluated), which also shows the new
     state free and within the penetration guard: no contact evaluation
     (the hybrid's law reads of P^n only that it is <= 0) */
  EXPECT(d, "hybrid free flight", 0, 0, N_STEPS, 0, 0, 0, 0, N_STEPS);
  ck_assert_double_eq(d.bounds, 2 * N_STEPS);
  ck_assert_double_eq(d.iters, N_STEPS);
  /* a query evaluates them (not counted: the counters count the steps' work) */
  ck_assert_double_eq(scalar(p, ND_ACTIVE_POINTS), 0);
  ck_assert_double_eq(scalar(p, ND_CONTACT_FORCE), 0);
  /* the bar's one contact point, evaluated by this process (all of them):
     the set-up's pass only */
  int64_t nq = 0;
  ND_OK_OR_FAIL(nd_problem_get_contact_point_count(p, &nq));
  ck_assert_int_eq(nq, 1);
  const double points = scalar(p, ND_STAT_POINT_EVALUATIONS);
  ck_assert_double_eq(points, nq);
  ck_assert_double_eq(points - scalar(p, ND_STAT_POINT_EVALUATIONS_OWN), 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));

  /* Newmark carries A^n: M is factored once more at set-up, for A^0 */
  const double nm[2] = {0.25, 0.5};
  p = nd_test_bar_at(20, 1, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, kTau, kFar, NULL);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  s0 = get(p);
  EXPECT(s0, "Newmark set-up", 2, 2, 1, 4, 0, 0, 1 + 1, 1 + 1); /* + N(U^0), K_Theta U^0 for A^0 */
  steps(p, N_STEPS, 1);
  d = since(s0, get(p));
  /* the bar's acceleration changes: every step solves. Its predictor is
     tried at the first step and at every 16th (nd_step(3)): each try makes
     the new state's pass once more, its points shown free by the bound
     (one more check settled) and left unevaluated, as the solved steps' */
  const int tries = 1 + (N_STEPS - 1) / 16;
  EXPECT(d, "Newmark free flight", 0, 0, N_STEPS, 0, 0, 0, 0, N_STEPS + tries);
  ck_assert_double_eq(d.bounds, 2 * N_STEPS + tries);
  ck_assert_double_eq(scalar(p, ND_STAT_PREDICTED_STEPS), 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(no_contact_region) {
  /* no Newton at all: one solve per step, no contact evaluation; the bar
     is set in motion by a constant traction at x = 0, assembled once */
  nd_problem p = free_bar(ND_SCHEME_HYBRID, NULL);
  const double g = -0.1;
  ND_OK_OR_FAIL(nd_problem_set_neumann(p, 1, &g));
  ND_OK_OR_FAIL(nd_problem_setup(p));
  const stats s0 = get(p);
  EXPECT(s0, "set-up", 1, 1, 0, 4, 1, 0, 0, 1);
  steps(p, N_STEPS, 1);
  const stats d = since(s0, get(p));
  EXPECT(d, "steps", 0, 0, N_STEPS, 0, 0, 0, 0, N_STEPS);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(explicit_lumped_mass) {
  /* central difference with lumped mass, through the impact: nothing is
     factored or solved, ever (the critical-step estimate at set-up does SpMVs) */
  const double cd[2] = {0.0, 0.5};
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_NEWMARK, cd, 1.0, 0.2, 1.0 / 160);
  ND_OK_OR_FAIL(nd_problem_set_mass_lumping(p, 1));
  ND_OK_OR_FAIL(nd_problem_setup(p));
  const stats s0 = get(p);
  ck_assert_double_eq(s0.fact, 0);
  ck_assert_double_eq(s0.symb, 0);
  ck_assert_double_eq(s0.solves, 0);
  ck_assert_double_eq(s0.mat, 3); /* M (lumped on K's pattern), K, K_Theta: no A */
  double max_active = 0;
  for (int k = 0; k < 6 * N_STEPS; ++k) {
    ND_OK_OR_FAIL(nd_step(p));
    max_active = fmax(max_active, scalar(p, ND_ACTIVE_POINTS));
  }
  ck_assert(max_active > 0); /* the run went through contact */
  const stats d = since(s0, get(p));
  /* per step: M A = F - K_Theta U - N(U) (1 SpMV, 1 contact evaluation, at U^{n+1}), the products
     of the new state (1, 0: P_q and u_n - g0 from N(U)'s pass): their sums for the energy guard,
     P_q for phi_q, u_n - g0 for the penetration guard */
  EXPECT(d, "explicit steps", 0, 0, 0, 0, 0, 0, 6 * N_STEPS, 2 * 6 * N_STEPS);
  ck_assert_double_eq(d.bounds, 0); /* (no check to settle: U is the prediction) */
  ck_assert_double_eq(d.iters, 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(persistent_contact_lowrank) {
  /* the bar of docs/design.md §7 through its contact phase: the factor of A is
     reused through contact (no factorization after set-up); a step is one
     solve with A's factor (y0 = A^{-1} r) whatever its Newton iterations,
     which run on the contact points alone (the condensed Newton), plus one
     solve, once, for the column A^{-1} b_q of the contact point when it
     first becomes active; in contact, the full residual at the end is
     checked from the new state's products (M U, K U: their one pass over M
     and K) */
  nd_problem p = nd_test_bar(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  const stats s0 = get(p);
  int contact_steps = 0, persistent = 0, was_active = 0, steps = 0, shown_free = 0, evaluated_free = 0;
  stats before = s0;
  for (int k = 0; k < 240; ++k, ++steps) {
    ND_OK_OR_FAIL(nd_step(p));
    const stats now = get(p), d = since(before, now);
    const int active = scalar(p, ND_ACTIVE_POINTS) > 0;
    ck_assert_double_eq(d.fact, 0);
    ck_assert_double_eq(d.mat, 0);
    if (active && was_active) {
      /* in persistent contact: one solve and one SpMV (the products of the
         new state, from which the residual is checked), at most one Jacobian
         LU per iteration (in fact at most one per step: it is kept while the
         set and the slopes stay) */
      ck_assert_double_eq(d.solves, 1);
      ck_assert_double_eq(d.spmv, 1);
      ck_assert(d.tangent <= 1);
      ++persistent;
    }
    /* the bound settles a check only where no point is active: never with
       P^n active (the predictor), never the linear step of a step that ends
       in contact; free flight: both checks settled (the new state's points
       then unevaluated), or the points evaluated */
    ck_assert(d.bounds >= 0 && d.bounds <= 2);
    if (was_active) ck_assert_double_eq(d.bounds, 0);
    if (active) ck_assert(d.bounds <= 1);
    if (!active && !was_active) {
      shown_free += d.bounds == 2;
      evaluated_free += d.bounds < 2;
      /* each check not settled, and then the new state's pass */
      ck_assert_double_eq(d.contact, d.bounds == 2 ? 0 : 1 + (2 - d.bounds));
    }
    contact_steps += active;
    was_active = active;
    before = now;
  }
  ck_assert(persistent >= 10);
  printf("free flight: %d steps settled by the bound, %d evaluated\n", shown_free, evaluated_free);
  ck_assert(shown_free > 0 && evaluated_free > 0);
  const stats d = since(s0, get(p));
  ck_assert_double_eq(d.fact, 0);
  ck_assert_double_eq(d.symb, 0);
  ck_assert_double_eq(d.solves, steps + 1); /* one contact point: one column */
  printf("persistent contact: %d contact steps, %g Newton iterations, %g solves, %g Jacobian LUs\n",
         contact_steps, d.iters, d.solves, d.tangent);
  /* one LU per distinct (set, slopes): the hybrid's Phi has slope 1/2 on
     both of its branches through the contact phase (one), and at the release
     the point, still in the set from the predictor, has slope 0 (one more) */
  ck_assert_double_eq(d.tangent, 2);
  /* the low-rank tangent leaves A's factor as it is: no rank-one modification */
  ck_assert_double_eq(scalar(p, ND_STAT_FACTOR_MODIFICATIONS), 0);
  ck_assert_double_eq(scalar(p, ND_STAT_FACTOR_MODIFIED_ENTRIES), 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(time_dependent_loads) {
  /* a load set every step is assembled once per change, nothing else: no
     factorization, no matrix assembly */
  nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  int64_t n = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &n));
  double *f = calloc((size_t)n, sizeof(double));
  stats s0 = get(p);
  for (int k = 0; k < N_STEPS; ++k) {
    const double g = -0.1 * sin(0.3 * k);
    ND_OK_OR_FAIL(nd_problem_set_body_force(p, &g));
    ND_OK_OR_FAIL(nd_step(p));
  }
  stats d = since(s0, get(p));
  EXPECT(d, "body force", 0, 0, N_STEPS, 0, N_STEPS, 0, 0, N_STEPS); /* far from the obstacle: no contact pass */
  /* a constant load is not assembled again */
  s0 = get(p);
  steps(p, N_STEPS, 1);
  d = since(s0, get(p));
  ck_assert_double_eq(d.load, 0);
  /* nodal forces: the body-force vector is kept, the sum built per change */
  s0 = get(p);
  for (int k = 0; k < N_STEPS; ++k) {
    f[0] = 0.01 * cos(0.2 * k);
    ND_OK_OR_FAIL(nd_problem_set_nodal_forces(p, n, f));
    ND_OK_OR_FAIL(nd_step(p));
  }
  d = since(s0, get(p));
  EXPECT(d, "nodal forces", 0, 0, N_STEPS, 0, N_STEPS, 0, 0, N_STEPS);
  free(f);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));

  /* a traction on region 1, replaced every step */
  p = free_bar(ND_SCHEME_HYBRID, NULL);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  s0 = get(p);
  ck_assert_double_eq(s0.load, 0); /* no Neumann region, no body force: no load vector */
  for (int k = 0; k < N_STEPS; ++k) {
    const double g = 0.05 * sin(0.25 * k);
    ND_OK_OR_FAIL(nd_problem_set_neumann(p, 1, &g));
    ND_OK_OR_FAIL(nd_step(p));
  }
  d = since(s0, get(p));
  EXPECT(d, "traction", 0, 0, N_STEPS, 0, N_STEPS, 0, 0, N_STEPS);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

/* The obstacle's point replaced every step (issue 13): only the gaps change;
   nothing is assembled, analysed or factored, and each free-flight step is
   one solve. */
START_TEST(moving_plane) {
  nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  ND_OK_OR_FAIL(nd_problem_setup(p));
  const stats s0 = get(p);
  const double up = 1;
  for (int k = 0; k < N_STEPS; ++k) {
    const double x0 = kFar + 0.01 * k;
    ND_OK_OR_FAIL(nd_problem_set_contact_plane(p, 1, &x0, &up));
    ND_OK_OR_FAIL(nd_step(p));
  }
  const stats d = since(s0, get(p));
  ck_assert_double_eq(d.fact, 0);
  ck_assert_double_eq(d.symb, 0);
  ck_assert_double_eq(d.mat, 0);
  ck_assert_double_eq(d.solves, N_STEPS);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(change_of_tau) {
  /* a new tau: A is assembled and factored again, on the pattern already
     analysed (no new symbolic analysis); nothing else is rebuilt */
  const double nm[2] = {0.25, 0.5};
  nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_NEWMARK, nm, 1.0, 0.2, kTau, kFar, NULL);
  steps(p, 5, 1);
  const stats s0 = get(p);
  ND_OK_OR_FAIL(nd_problem_set_timestep(p, kTau / 2));
  steps(p, 1, 1);
  const stats d = since(s0, get(p));
  EXPECT(d, "new tau", 1, 0, 1, 1, 0, 0, 0, 1); /* the products do not depend on tau */
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

START_TEST(guards_cost_no_pass) {
  /* the energy guard reads the sums of the pass that gives the next
     right-hand side; the penetration guard the u_n - g0 of the pass that
     gives the new state's P_q, or for a state whose points the bound left
     unevaluated, a bound from the last evaluated state: with the guards
     on or off, the same counts */
  for (int on = 0; on <= 1; ++on) {
    nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
    if (!on) {
      ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY, 0));
      ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_PENETRATION, 0));
    }
    ND_OK_OR_FAIL(nd_problem_setup(p));
    const stats s0 = get(p);
    steps(p, N_STEPS, 1);
    const stats d = since(s0, get(p));
    EXPECT(d, on ? "guards" : "no guards", 0, 0, N_STEPS, 0, 0, 0, 0, N_STEPS);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

/* the two problems' displacements and velocities, bitwise */
static void same_fields(nd_problem p, nd_problem q) {
  const int which[2] = {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY};
  for (int f = 0; f < 2; ++f) {
    double a[21], b[21];
    ND_OK_OR_FAIL(nd_get_field(p, which[f], 21, a));
    ND_OK_OR_FAIL(nd_get_field(q, which[f], 21, b));
    ck_assert(memcmp(a, b, sizeof a) == 0);
  }
}

START_TEST(acceleration_query_keeps_products) {
  /* the hybrid scheme's state has no acceleration: a query makes it
     (Remark 3.2) and keeps the products the step before left, which the next
     step's right-hand side is made of (it reads no M A): the step after a
     query costs what one without costs, and gives the same bits */
  nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  nd_problem q = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  double a[21];
  ND_OK_OR_FAIL(nd_step(p)); /* (the set-up's work in the first step) */
  ND_OK_OR_FAIL(nd_step(q));
  for (int k = 0; k < 5; ++k) {
    const stats p0 = get(p);
    ND_OK_OR_FAIL(nd_step(p));
    const stats dp = since(p0, get(p));
    ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_ACCELERATION, 21, a));
    const stats q0 = get(q);
    ND_OK_OR_FAIL(nd_step(q));
    const stats dq = since(q0, get(q));
    EXPECT(dp, "hybrid step", 0, 0, 1, 0, 0, 0, 0, 1);
    EXPECT(dq, "hybrid step after a query", 0, 0, 1, 0, 0, 0, 0, 1);
    same_fields(p, q);
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

START_TEST(scheme_reading_acceleration_after_a_query) {
  /* after a query of the hybrid scheme's acceleration the products hold no
     M A; a change to Newmark, whose right-hand side reads it, has them made
     again. Against the same change on a state restored from its checkpoint
     (products are not checkpointed: all made anew), the same bits; a
     right-hand side without its M A term differs (the bar is strained:
     A != 0) */
  const double nm[2] = {0.25, 0.5};
  nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  nd_problem q = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  double a[21], b[21];
  steps(p, 3, 1);
  steps(q, 3, 1);
  ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_ACCELERATION, 21, a));
  ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_NEWMARK, nm));
  ND_OK_OR_FAIL(nd_problem_set_scheme(q, ND_SCHEME_NEWMARK, nm));
  int64_t size = 0;
  unsigned char *saved = nd_test_checkpoint(p, &size);
  ND_OK_OR_FAIL(nd_problem_load_state(p, size, saved));
  free(saved);
  steps(p, 3, 1);
  steps(q, 3, 1);
  same_fields(p, q);
  ND_OK_OR_FAIL(nd_get_field(p, ND_FIELD_ACCELERATION, 21, a));
  ND_OK_OR_FAIL(nd_get_field(q, ND_FIELD_ACCELERATION, 21, b));
  ck_assert(memcmp(a, b, sizeof a) == 0);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
  ND_OK_OR_FAIL(nd_problem_destroy(&q));
}
END_TEST

START_TEST(counters_are_not_state) {
  /* a checkpoint restores the state, not the counters: they go on counting */
  nd_problem p = nd_test_bar_at(20, 1, ND_SCHEME_HYBRID, NULL, 1.0, 0.2, kTau, kFar, NULL);
  steps(p, 3, 1);
  int64_t nbytes = 0;
  ND_OK_OR_FAIL(nd_problem_get_state_size(p, &nbytes));
  void *buf = malloc((size_t)nbytes);
  ND_OK_OR_FAIL(nd_problem_save_state(p, nbytes, buf));
  steps(p, 2, 1);
  const stats s0 = get(p);
  ND_OK_OR_FAIL(nd_problem_load_state(p, nbytes, buf));
  const stats d = since(s0, get(p));
  ck_assert_double_eq(d.solves, 0);
  ck_assert_double_eq(d.fact, 0);
  ck_assert_double_eq(scalar(p, ND_STAT_SOLVES), s0.solves);
  free(buf);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

int main(void) {
  Suite *s = suite_create("statistics");
  TCase *tc = tcase_create("counts");
  tcase_set_timeout(tc, 60);
  tcase_add_test(tc, free_flight_implicit);
  tcase_add_test(tc, no_contact_region);
  tcase_add_test(tc, explicit_lumped_mass);
  tcase_add_test(tc, persistent_contact_lowrank);
  tcase_add_test(tc, time_dependent_loads);
  tcase_add_test(tc, moving_plane);
  tcase_add_test(tc, change_of_tau);
  tcase_add_test(tc, guards_cost_no_pass);
  tcase_add_test(tc, counters_are_not_state);
  tcase_add_test(tc, acceleration_query_keeps_products);
  tcase_add_test(tc, scheme_reading_acceleration_after_a_query);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
