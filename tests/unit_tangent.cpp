// The low-rank Newton tangent (Woodbury over the active points, the factor
// of A = c M + K_Theta reused) and the condensed Newton (on the contact
// points alone, fast/newton_condensed.hpp) against the reference that
// refactors the tangent: the same trajectories to 1e-10 relative and the
// same Newton iteration counts, for every implicit scheme, Theta = 1, 0, -1, P1/P2, in
// 1D (the bar), 2D (a rectangle dropped on a plane) and 3D (a box dropped on
// a plane), and on quadrilaterals and hexahedra (Q1, Q2, mixed meshes, the
// disk in a bowl). Each run also shows that the path it names was taken.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "common/simd.hpp"
#include "linalg/backends.hpp"
#include "monitor/energies.hpp"
#include "fast/contact_columns.hpp"
#include "solve/contact_law.hpp"
#include "testutil.h"
#include "unit_drop.hpp"
#include "unit_fixtures.hpp"

namespace {
using ndtest::rel_diff;

using ndtest::kSchemes;
using ndtest::SchemeCase;
const double kThetas[] = {1.0, 0.0, -1.0};

// Reproducible numbers in [-1, 1) (a linear congruential generator)
struct Uniform {
  explicit Uniform(unsigned s) : seed(s) {}
  double operator()() {
    seed = seed * 1103515245u + 12345u;
    return static_cast<double>((seed >> 8) & 0xffff) / 32768.0 - 1.0;
  }
  unsigned seed;
};

// refine > 1: the rectangle's finer mesh, on CHOLMOD (whose factor is then
// supernodal), the contact columns held at the points' DOFs alone (Auto
// chooses that only on larger meshes)
nd_problem scene(int dim, int degree, const SchemeCase &sc, double theta, int refine = 1,
                 const ndtest::Body &body = {}) {
  nd_problem p = ndtest::drop_scene(dim, degree, sc, theta, 0.02, 0.1, refine, body);
  // (Theta <= 0 may gain energy at impacts (the method's own (Theta - 1) term, docs/design.md §3b): the energy-balance guard refuses it (test_guards_scale); this test compares tangents)
  if (theta <= 0) ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0));
  if (refine > 1) {
    ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, ND_SOLVER_CHOLMOD));
    p->problem.set_column_rows(nd::ColumnRows::Points);
  }
  return p;
}

std::vector<double> field(nd_problem p, int which, int64_t nodes, int dim) {
  std::vector<double> f(static_cast<size_t>(nodes * dim));
  ND_OK_OR_FAIL(nd_get_field(p, which, nodes, f.data()));
  return f;
}

// The bodies of a dimension's runs: simplices, and quadrilaterals (the
// rectangle, the mixed mesh) or hexahedra
std::vector<ndtest::Body> bodies(int dim) {
  if (dim == 2) return {ndtest::Body{}, ndtest::kQuads, ndtest::kMixed};
  if (dim == 3) return {ndtest::Body{}, ndtest::kHexahedra};
  return {ndtest::Body{}};
}

// Runs the scene with the reference and with choice `other`.
void compare(int dim, int degree, const SchemeCase &sc, double theta, nd::TangentChoice other, int steps,
             int refine = 1, const ndtest::Body &body = {}) {
  nd_problem ref = scene(dim, degree, sc, theta, refine, body), fast = scene(dim, degree, sc, theta, refine, body);
  ref->problem.set_tangent(nd::TangentChoice::Refactor);
  fast->problem.set_tangent(other);
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(ref, &nodes));
  double worst = 0;
  int iteration_mismatch = 0, one_earlier = 0;  // steps; of them, the fast path one iteration fewer
  int lagged = 0;  // the updated factor's steps whose first iteration kept the last tangent: their own counts
  for (int k = 0; k < steps; ++k) {
    double lags_before = 0, lags_after = 0;
    ND_OK_OR_FAIL(nd_get_scalar(fast, ND_STAT_LAGGED_STEPS, &lags_before));
    ND_OK_OR_FAIL(nd_step(ref));
    ND_OK_OR_FAIL(nd_step(fast));
    ND_OK_OR_FAIL(nd_get_scalar(fast, ND_STAT_LAGGED_STEPS, &lags_after));
    for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY}) {
      const double r = rel_diff(field(fast, which, nodes, dim), field(ref, which, nodes, dim));
      worst = std::max(worst, r);
    }
    double it_ref = 0, it_fast = 0;
    ND_OK_OR_FAIL(nd_get_scalar(ref, ND_NEWTON_ITERATIONS, &it_ref));
    ND_OK_OR_FAIL(nd_get_scalar(fast, ND_NEWTON_ITERATIONS, &it_fast));
    if (lags_after > lags_before) {
      ++lagged;
      continue;
    }
    if (it_ref != it_fast) ++iteration_mismatch;
    if (it_fast == it_ref - 1) ++one_earlier;
  }
  const nd::TangentStats &sr = ref->problem.integrator()->tangent->stats,
                         &sf = fast->problem.integrator()->tangent->stats;
  if (std::getenv("ND_TANGENT_TEST_VERBOSE"))
    std::fprintf(stderr, "%dD P%d %s Theta=%g: %.2e, %lld contact solves, %lld columns, rank <= %lld\n", dim, degree,
                 sc.name, theta, worst, static_cast<long long>(sr.refactorizations),
                 static_cast<long long>(sf.columns), static_cast<long long>(sf.max_rank));
  const std::string what = std::to_string(dim) + "D P" + std::to_string(degree) + " " + sc.name +
                           " Theta=" + std::to_string(theta) + " " + body.name;
  ck_assert_msg(worst <= 1e-10, "%s: trajectories differ by %g relative", what.c_str(), worst);
  // (refine > 1: the condensed Newton, which stops when the active set holds,
  // may end one iteration before the reference, which stops when the
  // residual is below the tolerance: at 1-2 steps of 30 on the finer
  // rectangle with Newmark, with whole columns as with columns at the
  // points' DOFs (compare_columns below holds those two to the same
  // counts). Only that: never more iterations, never two fewer.)
  const bool each_one_earlier =
      refine > 1 && other == nd::TangentChoice::Condensed && one_earlier == iteration_mismatch;
  ck_assert_msg(iteration_mismatch == 0 || each_one_earlier,
                "%s: Newton iteration counts differ at %d steps (%d of them one fewer)", what.c_str(),
                iteration_mismatch, one_earlier);
  ck_assert_msg(sr.refactorizations > 0, "%s: the scene never came into contact", what.c_str());
  const bool updown = other == nd::TangentChoice::Updown;
  ck_assert_msg(std::string(fast->problem.integrator()->tangent->name()) == (updown ? "updown" : "lowrank"), "%s",
                what.c_str());
  if (updown) {  // started (factored, or from A's factor) far less often than the reference factors
    // (where the reference factors once, the active set settled at once, as
    // the disk in a bowl under the theta-scheme (1): one start, from A's factor)
    const int64_t starts = sf.refactorizations + sf.restarts;
    const bool once = sr.refactorizations == 1 && sf.restarts == 1 && sf.refactorizations == 0;
    ck_assert_msg(starts > 0 && (starts < sr.refactorizations || once),
                  "%s: updated factor: %lld factorizations and %lld restarts from A's, reference %lld factorizations",
                  what.c_str(), static_cast<long long>(sf.refactorizations), static_cast<long long>(sf.restarts),
                  static_cast<long long>(sr.refactorizations));
    if (std::getenv("ND_TANGENT_TEST_VERBOSE"))
      std::fprintf(stderr, "  updated factor: %lld factorizations, %lld restarts from A's, %d lagged steps\n",
                   static_cast<long long>(sf.refactorizations), static_cast<long long>(sf.restarts), lagged);
  }
  if (other == nd::TangentChoice::Condensed) {  // no full Newton at all, each point's column once
    const nd::CondensedCache *cols = fast->problem.integrator()->condensed.get();
    int64_t points = 0;
    ND_OK_OR_FAIL(nd_problem_get_contact_point_count(ref, &points));
    ck_assert_msg(cols && sf.calls == 0 && cols->columns.computed() > 0 && cols->columns.computed() <= points,
                  "%s: condensed: %lld tangent calls, %lld columns for %lld points", what.c_str(),
                  static_cast<long long>(sf.calls), static_cast<long long>(cols ? cols->columns.computed() : -1),
                  static_cast<long long>(points));
  }
  if (other == nd::TangentChoice::LowRank) {
    ck_assert_msg(sf.refactorizations == 0 && sf.lowrank == sr.refactorizations,
                  "%s: low-rank %lld calls, %lld refactorizations; reference %lld", what.c_str(),
                  static_cast<long long>(sf.lowrank), static_cast<long long>(sf.refactorizations),
                  static_cast<long long>(sr.refactorizations));
    // each point's column once, whatever the number of iterations
    int64_t points = 0;
    ND_OK_OR_FAIL(nd_problem_get_contact_point_count(ref, &points));
    ck_assert_msg(sf.columns <= points, "%s: %lld columns for %lld points", what.c_str(),
                  static_cast<long long>(sf.columns), static_cast<long long>(points));
  }
  // the columns at the points' DOFs alone, as asked
  const nd::Integrator *in = fast->problem.integrator();
  if (refine > 1 && !updown)
    ck_assert_msg(in->columns && !in->columns->sums_whole(), "%s: the columns are not held at the points' DOFs alone",
                  what.c_str());
  nd_problem_destroy(&ref);
  nd_problem_destroy(&fast);
}

// The same fast path with the columns at the points' DOFs alone and with
// whole columns: the same G and P (the kept values are the whole columns'
// bits), so the same Newton iterations at every step; the displacement a
// solve instead of a sum of columns, so trajectories equal to round-off.
void compare_columns(const SchemeCase &sc, double theta, nd::TangentChoice other, int steps, int refine,
                     const ndtest::Body &body = {}) {
  nd_problem whole = scene(2, 2, sc, theta, refine, body), at_points = scene(2, 2, sc, theta, refine, body);
  whole->problem.set_tangent(other);
  at_points->problem.set_tangent(other);
  whole->problem.set_column_rows(nd::ColumnRows::Whole);
  at_points->problem.set_column_rows(nd::ColumnRows::Points);
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(whole, &nodes));
  double worst = 0, total = 0;
  const std::string what = std::string(sc.name) + " Theta=" + std::to_string(theta) +
                           (other == nd::TangentChoice::Condensed ? " condensed " : " low-rank ") + body.name;
  for (int k = 0; k < steps; ++k) {
    ND_OK_OR_FAIL(nd_step(whole));
    ND_OK_OR_FAIL(nd_step(at_points));
    for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY})
      worst = std::max(worst, rel_diff(field(at_points, which, nodes, 2), field(whole, which, nodes, 2)));
    double it_whole = 0, it_points = 0;
    ND_OK_OR_FAIL(nd_get_scalar(whole, ND_NEWTON_ITERATIONS, &it_whole));
    ND_OK_OR_FAIL(nd_get_scalar(at_points, ND_NEWTON_ITERATIONS, &it_points));
    ck_assert_msg(it_whole == it_points, "%s step %d: %g Newton iterations with whole columns, %g at the points",
                  what.c_str(), k, it_whole, it_points);
    total += it_points;
  }
  ck_assert_msg(worst <= 1e-10, "%s: trajectories differ by %g relative", what.c_str(), worst);
  ck_assert_msg(total > steps, "%s: no step needed Newton", what.c_str());
  ck_assert(whole->problem.integrator()->columns->sums_whole());
  ck_assert(!at_points->problem.integrator()->columns->sums_whole());
  if (std::getenv("ND_TANGENT_TEST_VERBOSE"))
    std::fprintf(stderr, "%s: columns at the points against whole: %.2e\n", what.c_str(), worst);
  nd_problem_destroy(&whole);
  nd_problem_destroy(&at_points);
}

void all_cases(int dim, int degree, int steps, const ndtest::Body &body = {}) {
  for (const SchemeCase &sc : kSchemes)
    for (double theta : kThetas)
      for (nd::TangentChoice other :
           {nd::TangentChoice::LowRank, nd::TangentChoice::Condensed, nd::TangentChoice::Updown})
        if (other != nd::TangentChoice::Updown || theta == 1)  // (symmetric T only)
          compare(dim, degree, sc, theta, other, steps, 1, body);
}

}  // namespace

START_TEST(bar_p1) { all_cases(1, 1, 60); }
END_TEST
START_TEST(bar_p2) { all_cases(1, 2, 60); }
END_TEST
START_TEST(rectangle_p1) { all_cases(2, 1, 30); }
END_TEST
START_TEST(rectangle_p2) { all_cases(2, 2, 30); }
END_TEST
// CHOLMOD's supernodal factor (1,722 unknowns): the columns held at the
// points' DOFs alone, solved only there, and the final displacement a solve;
// and the updated factor in its supernodal form (our updates), Theta = 1
START_TEST(rectangle_p2_supernodal) {
  for (const SchemeCase &sc : kSchemes)
    for (double theta : kThetas) {
      for (nd::TangentChoice other : {nd::TangentChoice::LowRank, nd::TangentChoice::Condensed}) {
        if (sc.scheme == ND_SCHEME_NEWMARK) compare(2, 2, sc, theta, other, 30, 5);
        compare_columns(sc, theta, other, 20, 5);
      }
      if (theta == 1) compare(2, 2, sc, theta, nd::TangentChoice::Updown, 30, 5);
    }
}
END_TEST
// Quadrilaterals and hexahedra (docs/performance.md, "Quadrilaterals and
// hexahedra"): every tangent path against the reference on Q1 and Q2
// rectangles of quadrilaterals, the mixed mesh (P1/Q1, P2/Q2), the
// quadrilateral disk in a bowl (a curved obstacle) and a box of Q1
// hexahedra; on the refined Q2 rectangle (CHOLMOD's supernodal factor) the
// columns at the points' DOFs against whole columns, and the updated factor
// in its supernodal form.
START_TEST(quadrilaterals) {
  all_cases(2, 1, 30, ndtest::kQuads);
  all_cases(2, 2, 30, ndtest::kQuads);
}
END_TEST
START_TEST(mixed_and_disk) {
  all_cases(2, 1, 30, ndtest::kMixed);
  all_cases(2, 2, 30, ndtest::kMixed);
  all_cases(2, 1, 30, ndtest::kDiskInBowl);
}
END_TEST
START_TEST(hexahedra) { all_cases(3, 1, 30, ndtest::kHexahedra); }
END_TEST
START_TEST(quadrilaterals_supernodal) {
  for (double theta : {1.0, -1.0})
    for (nd::TangentChoice other : {nd::TangentChoice::LowRank, nd::TangentChoice::Condensed}) {
      compare(2, 2, kSchemes[2], theta, other, 30, 5, ndtest::kQuads);
      compare_columns(kSchemes[2], theta, other, 20, 5, ndtest::kQuads);
    }
  compare(2, 2, kSchemes[2], 1.0, nd::TangentChoice::Updown, 30, 5, ndtest::kQuads);
}
END_TEST
START_TEST(box_p1) { all_cases(3, 1, 30); }
END_TEST
START_TEST(box_p2) { all_cases(3, 2, 30); }
END_TEST

// The solvers alone, on random states whose active sets grow, shrink and
// jump (the cached G of the last set reused in part), Theta = 1 and -1,
// with the scheme's contact law: x = T^{-1} r to 1e-12 relative; and with a
// rank limit, above which the solver refactors and past which it drops
// columns; and with the second solve in place of Z w.
START_TEST(random_active_sets) {
  for (double theta : {1.0, -1.0}) {
    nd_problem p = scene(3, 2, kSchemes[3], theta);
    if (theta <= 0) {  // Theta = 1's automatic gamma0, half the bound: its random sets cross the rank limit both ways
      double half = 0;
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 0.0));
      ND_OK_OR_FAIL(nd_get_scalar(p, ND_GAMMA0, &half));
      ND_OK_OR_FAIL(nd_problem_set_nitsche(p, theta, half));
    }
    ND_OK_OR_FAIL(nd_step(p));
    nd::Problem &pb = p->problem;
    const nd::Integrator &in = *pb.integrator();
    const nd::Discretization &d = pb.discretization();
    const int64_t n = in.A.n;
    const size_t Q = d.contact.size();
    std::vector<double> Pn(Q, 0.0);
    nd::ContactLaw law{&d.contact, d.theta, in.scheme.get(), &Pn};
    auto ref = nd::make_refactoring_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO,
                                            theta == 1 ? nd::Structure::SymmetricPositiveDefinite
                                                       : nd::Structure::General);
    auto fast = nd::make_lowrank_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO,
                                         theta == 1 ? nd::Structure::SymmetricPositiveDefinite
                                                    : nd::Structure::General, -1);
    // a rank limit of 12: larger sets refactor, and at most 24 columns are kept
    auto limited = nd::make_lowrank_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO,
                                            theta == 1 ? nd::Structure::SymmetricPositiveDefinite
                                                       : nd::Structure::General, 12);
    // the second-solve variant above rank 5
    auto two = nd::make_lowrank_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO,
                                        theta == 1 ? nd::Structure::SymmetricPositiveDefinite
                                                   : nd::Structure::General, -1, 5);
    // the updated factor (Theta = 1), from set to set by rank updates
    auto updated = nd::make_updown_tangent(in.A, *in.A_factor);
    // and with the cost model's price of a factorization scaled to either
    // end: factored at every change, or started from A's factor and only updated
    auto factoring = nd::make_updown_tangent(in.A, *in.A_factor, nullptr, 1e-9);
    auto updating = nd::make_updown_tangent(in.A, *in.A_factor, nullptr, 1e9);
    Uniform rnd(12345);
    std::vector<double> U(static_cast<size_t>(n)), r(U.size()), x1, x2;
    int64_t last_k = -1, changes = 0, above_five = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const double shift = 0.05 * rnd();  // moves the body up or down: fewer or more active points
      for (auto &u : U) u = 0.01 * rnd() - shift;
      for (auto &v : r) v = rnd();
      int64_t k = 0;
      for (size_t q = 0; q < Q; ++q) {
        double value, slope;
        law.law(q, law.P(q, U.data()), value, slope);
        k += slope != 0;
      }
      if (k != last_k) ++changes;
      last_k = k;
      x1 = r;
      x2 = r;
      ref->solve(law, in.coef.kappa, U.data(), k > 0, x1.data());
      fast->solve(law, in.coef.kappa, U.data(), k > 0, x2.data());
      ck_assert_msg(rel_diff(x2, x1) <= 1e-12, "Theta = %g, trial %d, k = %lld: %g", theta, trial,
                    static_cast<long long>(k), rel_diff(x2, x1));
      x2 = r;
      limited->solve(law, in.coef.kappa, U.data(), k > 0, x2.data());
      ck_assert_msg(rel_diff(x2, x1) <= 1e-12, "limited, Theta = %g, trial %d, k = %lld: %g", theta, trial,
                    static_cast<long long>(k), rel_diff(x2, x1));
      x2 = r;
      two->solve(law, in.coef.kappa, U.data(), k > 0, x2.data());
      ck_assert_msg(rel_diff(x2, x1) <= 1e-12, "two solves, Theta = %g, trial %d, k = %lld: %g", theta, trial,
                    static_cast<long long>(k), rel_diff(x2, x1));
      if (theta == 1) {
        x2 = r;
        updated->solve(law, in.coef.kappa, U.data(), k > 0, x2.data());
        ck_assert_msg(rel_diff(x2, x1) <= 1e-12, "updated factor, trial %d, k = %lld: %g", trial,
                      static_cast<long long>(k), rel_diff(x2, x1));
        for (auto *t : {factoring.get(), updating.get()}) {
          x2 = r;
          t->solve(law, in.coef.kappa, U.data(), k > 0, x2.data());
          ck_assert_msg(rel_diff(x2, x1) <= 1e-12, "updated factor (%s), trial %d, k = %lld: %g",
                        t == factoring.get() ? "factoring" : "updating", trial, static_cast<long long>(k),
                        rel_diff(x2, x1));
        }
      }
      if (k > 5) ++above_five;
    }
    if (theta == 1) {  // mostly updated, not started anew (factored, or from A's factor)
      const int64_t starts = updated->stats.refactorizations + updated->stats.restarts;
      ck_assert_msg(starts > 0 && 4 * starts < updated->stats.lowrank,
                    "updated factor: %lld factorizations and %lld restarts in %lld solves",
                    static_cast<long long>(updated->stats.refactorizations),
                    static_cast<long long>(updated->stats.restarts), static_cast<long long>(updated->stats.lowrank));
      ck_assert_msg(factoring->stats.restarts == 0 && factoring->stats.refactorizations > 1,
                    "factoring: %lld restarts, %lld factorizations", static_cast<long long>(factoring->stats.restarts),
                    static_cast<long long>(factoring->stats.refactorizations));
      ck_assert_msg(updating->stats.restarts == 1 && updating->stats.refactorizations == 0,
                    "updating: %lld restarts, %lld factorizations", static_cast<long long>(updating->stats.restarts),
                    static_cast<long long>(updating->stats.refactorizations));
      if (std::getenv("ND_TANGENT_TEST_VERBOSE"))
        std::fprintf(stderr, "random sets, updated factor: %lld factorizations, %lld restarts, %lld solves\n",
                     static_cast<long long>(updated->stats.refactorizations),
                     static_cast<long long>(updated->stats.restarts), static_cast<long long>(updated->stats.lowrank));
    }
    ck_assert_int_gt(changes, 10);
    ck_assert_int_gt(above_five, 5);
    ck_assert_int_eq(fast->stats.refactorizations, 0);
    ck_assert_int_le(fast->stats.columns, static_cast<int64_t>(Q));
    ck_assert_int_gt(limited->stats.refactorizations + limited->stats.restarts, 0);  // past its rank limit
    ck_assert_int_gt(limited->stats.lowrank, 0);
    nd_problem_destroy(&p);
  }
}
END_TEST

// A tangent solve given the points' values P_q(U) that Newton's residual at
// U evaluated (ContactLaw::add_force) makes the bits it makes evaluating them
// itself, and evaluates nothing: each solver twice, one always given P and
// one never, on the same random states (the solvers keep state from solve
// to solve: the two see the same sequence), 2D P1 and 3D P2, Theta = 1 and -1.
START_TEST(tangent_given_the_residuals_points) {
  for (int dim : {2, 3})
    for (double theta : {1.0, -1.0}) {
      nd_problem p = scene(dim, dim == 2 ? 1 : 2, kSchemes[3], theta);
      ND_OK_OR_FAIL(nd_step(p));
      const nd::Integrator &in = *p->problem.integrator();
      const nd::Discretization &d = p->problem.discretization();
      const int64_t n = in.A.n;
      const size_t Q = d.contact.size();
      const nd::Structure s = theta == 1 ? nd::Structure::SymmetricPositiveDefinite : nd::Structure::General;
      std::vector<double> Pn(Q, 0.0);
      nd::Counters given_count, evaluated_count;
      nd::ContactLaw given{&d.contact, d.theta, in.scheme.get(), &Pn}, evaluated = given;
      given.counters = &given_count, evaluated.counters = &evaluated_count;
      auto make = [&](int which) -> std::unique_ptr<nd::TangentSolver> {
        if (which == 0) return nd::make_refactoring_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO, s);
        if (which == 1) return nd::make_lowrank_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO, s, -1);
        if (which == 2) return nd::make_lowrank_tangent(in.A, *in.A_factor, ND_SOLVER_AUTO, s, 4);  // past 4: inside
        return nd::make_updown_tangent(in.A, *in.A_factor);
      };
      for (int which = 0; which < (theta == 1 ? 4 : 3); ++which) {
        auto with_P = make(which), without = make(which);
        Uniform rnd(777);
        std::vector<double> U(static_cast<size_t>(n)), r(U.size()), x1, x2, P;
        int active_solves = 0;
        for (int trial = 0; trial < 12; ++trial) {
          const double shift = 0.05 * rnd();
          for (auto &u : U) u = 0.01 * rnd() - shift;
          for (auto &v : r) v = rnd();
          given.P_all(U.data(), P);  // (what the residual's add_force leaves in one process)
          bool any = false;
          for (size_t q = 0; q < Q; ++q) {
            double value, slope;
            given.law(q, P[q], value, slope);
            any |= slope != 0;
          }
          active_solves += any;
          x1 = r, x2 = r;
          const int64_t before_given = given_count.contact_evaluations;
          const int64_t before_evaluated = evaluated_count.contact_evaluations;
          with_P->solve(given, in.coef.kappa, U.data(), any, x1.data(), nullptr, &P);
          without->solve(evaluated, in.coef.kappa, U.data(), any, x2.data());
          ck_assert_msg(std::memcmp(x1.data(), x2.data(), x1.size() * sizeof(double)) == 0,
                        "%dD Theta = %g, solver %s, trial %d: the bits differ", dim, theta, with_P->name(), trial);
          ck_assert_int_eq(given_count.contact_evaluations, before_given);
          // (evaluated once, also past the rank limit: the solver inside is given them)
          ck_assert_int_eq(evaluated_count.contact_evaluations, before_evaluated + (any ? 1 : 0));
        }
        ck_assert_int_gt(active_solves, 3);
      }
      nd_problem_destroy(&p);
    }
}
END_TEST

// The dots a column keeps (ContactColumns::keeps_dots: P^T Z_j, made with
// the column) are the bits of p_q . Z_j evaluated on that column, made here
// by a solve of b_j alone, for every point q: columns that keep them,
// columns that evaluate them, and the automatic choice, which keeps them
// exactly where the points are no more than a whole column's rows; 1D, 2D
// and 3D, P1 and P2.
START_TEST(columns_keep_their_dots_bitwise) {
  for (int dim : {1, 2, 3})
    for (int degree : {1, 2}) {
      nd_problem p = scene(dim, degree, kSchemes[3], 1.0);
      ND_OK_OR_FAIL(nd_step(p));
      const nd::Integrator &in = *p->problem.integrator();
      const nd::ContactPoints &cp = p->problem.discretization().contact;
      const int64_t n = in.A.n, nq = static_cast<int64_t>(cp.size());
      std::vector<int64_t> S;
      for (int64_t q = nq > 1 ? 1 : 0; q < nq; q += 3) S.push_back(q);
      for (nd::ColumnDots dots : {nd::ColumnDots::Keep, nd::ColumnDots::Evaluate, nd::ColumnDots::Auto}) {
        nd::ContactColumns columns(*in.A_factor, n, nq, nullptr, nullptr, nd::ColumnRows::Whole, dots);
        columns.bind(cp, 1.0);
        ck_assert(columns.keeps_dots() == (dots == nd::ColumnDots::Keep || (dots == nd::ColumnDots::Auto && nq <= n)));
        columns.require(S);
        std::vector<double> z(static_cast<size_t>(n));
        for (int64_t j : S) {
          std::fill(z.begin(), z.end(), 0.0);
          nd::add_b(cp, 1.0, static_cast<size_t>(j), 1.0, z.data());
          in.A_factor->solve_many(z.data(), n, 1);
          for (int64_t q = 0; q < nq; ++q) {
            const double read = columns.dot(static_cast<size_t>(q), j),
                         evaluated = nd::p_dot(cp, static_cast<size_t>(q), z.data());
            ck_assert_msg(std::memcmp(&read, &evaluated, sizeof(double)) == 0,
                          "%dD P%d, dots %d: p_%lld . Z_%lld = %.17g read, %.17g evaluated", dim, degree,
                          static_cast<int>(dots), static_cast<long long>(q), static_cast<long long>(j), read,
                          evaluated);
          }
        }
      }
      nd_problem_destroy(&p);
    }
}
END_TEST

// The full residual from a state's products (newton_residual_from_products,
// the condensed Newton's check: c M U + K_Theta U + kappa N(U) - r from M U,
// K U and P_q(U)) is newton_residual's to round-off, at states with points
// active and off the solution (the residual of the order of A U), 1D-3D,
// P1/P2, Theta = 1, 0, -1, Newmark and the hybrid scheme (whose contact
// term reads P^n); and the contact term counts there (left out, it is seen).
START_TEST(residual_from_products_is_newton_residual) {
  for (int dim : {1, 2, 3})
    for (int degree : {1, 2})
      for (double theta : kThetas)
        for (const SchemeCase &sc : {kSchemes[2], kSchemes[3]}) {
          nd_problem p = scene(dim, degree, sc, theta);
          ND_OK_OR_FAIL(nd_step(p));
          const nd::Integrator &in = *p->problem.integrator();
          const nd::Discretization &d = p->problem.discretization();
          nd::State st = p->problem.current_state();
          nd::PointValues at_n;  // (the step may have left them unevaluated: PointValues::ref)
          const std::vector<double> Pn = nd::state_points(d, st, nd::Products{}, at_n).P;
          nd::ContactLaw law{&d.contact, d.theta, in.scheme.get(), &Pn};
          nd::NewtonSystem sys{&in.A, in.tangent.get(), &d.M, in.coef.c, in.coef.kappa, &law};
          Uniform rnd(4242);
          const size_t n = st.U.size();
          const std::vector<double> U0 = st.U;
          int checked = 0;
          for (int trial = 0; trial < 6; ++trial) {
            // towards the obstacle by up to about a cell (the blocks' gap
            // 0.02; the bar's end 0.5 away from it, its plane on the left)
            const double shift = (dim == 1 ? 0.6 : 0.05) * (1 + rnd());
            for (size_t i = 0; i < n; ++i) st.U[i] = U0[i] + 0.01 * rnd() - shift;
            std::vector<double> r(n), G(n), MU(n), active_P;
            for (auto &v : r) v = rnd();
            std::vector<char> active;
            const double full = nd::newton_residual(sys, r, st.U, G, &active, MU);
            int any = 0;
            for (char a : active) any += a != 0;
            nd::Products products;
            nd::compute_products(d, st, products);
            const double from = nd::newton_residual_from_products(sys, products, st.U, r, G);
            ck_assert_msg(std::fabs(from - full) <= 1e-12 * full, "%dD P%d %s Theta = %g: %.17g from the products, %.17g",
                          dim, degree, sc.name, theta, from, full);
            // with the contact term left out it is another residual
            if (any) {
              nd::Products no_contact = products;
              for (auto &P : no_contact.points.P) P = -1;
              ck_assert(std::fabs(nd::newton_residual_from_products(sys, no_contact, st.U, r, G) - full) > 1e-10 * full);
              ++checked;
            }
          }
          ck_assert_msg(checked > 0, "%dD P%d: no point active", dim, degree);
          nd_problem_destroy(&p);
        }
}
END_TEST

// K_Theta U (StepInputs::k_theta_u: the hybrid and generalized-alpha
// right-hand sides, the predictor's check, Newton's check from the products)
// run by run (s_q.U once per run that shares s_q; each entry of a run's index
// list read and written once) against the point-by-point sum (the runs
// cleared), 1D-3D, P1/P2 (and Q1/Q2: quadrilaterals, the mixed mesh,
// hexahedra), Theta = 1, -1: bitwise where a run's points have
// their own s_q (the points' terms subtracted in their order); where they
// share it (P1), the coefficients are summed first: the same sum rounded
// otherwise, within 32 eps of the sum of the terms' magnitudes at every entry
// (|KU_i| + theta sum_q w_q gamma_q (|s_q|.|U|) |s_qi|: the same call with
// |s| and |U|, no KU).
START_TEST(k_theta_u_by_runs) {
  int compared = 0, rounded = 0, expected = 0;
  for (int dim : {1, 2, 3})
    for (int degree : {1, 2})
      for (const ndtest::Body &body : bodies(dim)) {
      expected += 2;
      nd_problem p = scene(dim, degree, kSchemes[2], 1.0, 1, body);
      const nd::ContactPoints &cp = p->problem.discretization().contact;
      nd::ContactPoints alone = cp, magnitudes = cp;
      alone.runs.clear(), alone.run_shares_s.clear();
      magnitudes.runs.clear(), magnitudes.run_shares_s.clear();
      for (auto &row : magnitudes.s)
        for (auto &v : row.val) v = std::fabs(v);
      bool shares = false;
      for (char c : cp.run_shares_s) shares |= c != 0;
      const size_t n = static_cast<size_t>(p->problem.discretization().dofs.n_free);
      nd::Products old, zero;
      old.n = zero.n = static_cast<int64_t>(n);
      old.KU.resize(n), zero.KU.assign(n, 0.0);
      std::vector<double> U(n), absU(n);
      Uniform rnd(5);
      for (size_t i = 0; i < n; ++i) U[i] = rnd(), old.KU[i] = rnd(), absU[i] = std::fabs(U[i]);
      const std::vector<double> none;
      for (double theta : {1.0, -1.0}) {
        std::vector<double> by_runs, by_points, scale;
        nd::StepInputs{old, cp, theta, none, none}.k_theta_u(U, by_runs);
        nd::StepInputs{old, alone, theta, none, none}.k_theta_u(U, by_points);
        nd::StepInputs{zero, magnitudes, std::fabs(theta), none, none}.k_theta_u(absU, scale);
        ck_assert(by_runs.size() == n && by_points.size() == n && scale.size() == n);
        if (!shares) {
          ck_assert_msg(std::memcmp(by_runs.data(), by_points.data(), n * sizeof(double)) == 0, "%dD P%d Theta %g",
                        dim, degree, theta);
        } else {
          bool differs = false;
          for (size_t i = 0; i < n; ++i) {
            const double bound = 32 * DBL_EPSILON * (std::fabs(old.KU[i]) + std::fabs(scale[i]));
            ck_assert_msg(std::fabs(by_runs[i] - by_points[i]) <= bound, "%dD P%d Theta %g: entry %zu differs by %g",
                          dim, degree, theta, i, std::fabs(by_runs[i] - by_points[i]));
            differs |= by_runs[i] != by_points[i];
          }
          rounded += differs;
        }
        ck_assert(!(by_runs == old.KU));  // the contact term is there
        ++compared;
      }
      nd_problem_destroy(&p);
    }
  ck_assert_msg(rounded > 0, "no run shares s_q: the rounded form was not tried");
  ck_assert_int_eq(compared, expected);
}
END_TEST

// The pass over the points run by run (ContactLaw::P_by_runs: U read once
// per facet, a shared s_q.U once) gives every point the bits of P(q, U) and
// of a_q.U - g_q, 1D-3D, P1/P2; the runs are the facets' points, sharing
// s_q on P1 cells (constant stress) and not on P2 in 2D and 3D, nor on
// quadrilaterals and hexahedra (Q1, Q2; on the mixed mesh the triangles'
// runs share it); and a run whose s_q differ in one point is found so and
// still right. Both forms: scalar, and four points per load
// (ContactPoints::run_rows) with AVX2.
START_TEST(points_by_runs_bitwise) {
  for (int dim : {1, 2, 3})
    for (int degree : {1, 2})
      for (const ndtest::Body &body : bodies(dim)) {
      nd_problem p = scene(dim, degree, kSchemes[2], 1.0, 1, body);
      nd::ContactPoints cp = p->problem.discretization().contact;  // a copy: one s_q changed below
      ck_assert(cp.runs.size() >= 2 && cp.runs.back() == static_cast<int64_t>(cp.size()));
      ck_assert_uint_eq(cp.run_shares_s.size() + 1, cp.runs.size());
      size_t sharing = 0;
      for (char c : cp.run_shares_s) sharing += c != 0;
      const bool simplices = body.cell_type == ND_CELL_SIMPLEX && !body.file;
      if (std::getenv("ND_TANGENT_TEST_VERBOSE"))
        std::fprintf(stderr, "%dD P%d %s: %zu of %zu runs share s_q\n", dim, degree, body.name, sharing,
                     cp.run_shares_s.size());
      if (degree == 1 && simplices) ck_assert_uint_eq(sharing, cp.run_shares_s.size());
      // (a Q1 cell's stress varies along its facets: no run of theirs shares
      // s_q; the mixed mesh's triangles' runs do)
      if (!simplices && !body.file) ck_assert_uint_eq(sharing, 0);
      if (degree == 1 && body.file) ck_assert(sharing > 0 && sharing < cp.run_shares_s.size());
      if (degree == 2 && dim > 1) ck_assert_uint_eq(sharing, 0);
      for (int changed = 0; changed <= (degree == 1 && dim > 1 ? 1 : 0); ++changed) {
        if (changed) {  // the second point of the first run with two or more
          size_t r = 0;
          while (cp.runs[r + 1] - cp.runs[r] < 2) ++r;
          cp.s[cp.runs[r] + 1].val[0] *= 1.5;
          nd::set_bounds(cp);
          ck_assert(!cp.run_shares_s[r]);
        }
        nd::ContactLaw law{&cp, 1.0};
        Uniform rnd(99);
        std::vector<double> U(static_cast<size_t>(p->problem.discretization().dofs.n_free)), P, un;
        for (auto &u : U) u = rnd();
        for (int simd = 0; simd <= 1; ++simd) {  // the scalar form, and the wide one where the CPU has AVX2
          nd::set_simd(simd == 1);
          law.P_all(U.data(), P, &un);
          for (size_t q = 0; q < cp.size(); ++q) {
            const double Pq = law.P(q, U.data()), unq = cp.a[q].dot(U.data()) - cp.gap[q];
            ck_assert_msg(std::memcmp(&P[q], &Pq, sizeof(double)) == 0 &&
                              std::memcmp(&un[q], &unq, sizeof(double)) == 0,
                          "%dD P%d simd %d point %zu: %.17g, %.17g by runs; %.17g, %.17g alone", dim, degree, simd, q,
                          P[q], un[q], Pq, unq);
          }
        }
      }
      nd_problem_destroy(&p);
    }
}
END_TEST

double scalar(nd_problem p, int key) {
  double v = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &v));
  return v;
}

// The new state's points (P_q and u_n - g0) come from Newton's last
// residual, at the solution: the bits of a pass over the points on the
// state's U and gaps, on every tangent path, 2D P2 and 3D P1, Theta = 1
// and 0. And a step of the full Newton that starts in contact evaluates the
// points its + 1 times (the check of the predictor, whose pass the residual
// there reads, and the residual after each iteration): none for a tangent
// solve, none for the new state.
START_TEST(new_state_points_from_newton) {
  const nd::TangentChoice choices[] = {nd::TangentChoice::Refactor, nd::TangentChoice::LowRank,
                                       nd::TangentChoice::Condensed, nd::TangentChoice::Updown};
  for (int dim : {2, 3})
    for (double theta : {1.0, 0.0})
      for (nd::TangentChoice choice : choices) {
        if (choice == nd::TangentChoice::Updown && theta != 1) continue;
        nd_problem p = scene(dim, dim == 2 ? 2 : 1, kSchemes[3], theta);
        p->problem.set_tangent(choice);
        const nd::Discretization &d = p->problem.discretization();
        int contact_steps = 0, counted = 0, was_active = 0;
        double before = scalar(p, ND_STAT_CONTACT_EVALUATIONS);
        for (int k = 0; k < 40; ++k) {
          ND_OK_OR_FAIL(nd_step(p));
          const nd::State &s = p->problem.current_state();
          nd::ContactLaw law = nd::state_contact_law(d, s);
          law.local = true;
          std::vector<double> P, un;
          law.P_all(s.U.data(), P, &un);
          const nd::PointValues &kept = p->problem.current_products().points;
          if (kept.ref) {  // left unevaluated, shown off the obstacle: no point active, none evaluated
            ck_assert(kept.P.empty() && kept.un.empty());
            for (double Pq : P) ck_assert_msg(Pq <= 0, "%dD step %d: P_q = %g in a state shown free", dim, k + 1, Pq);
          } else {
            ck_assert(kept.P.size() == P.size() && kept.un.size() == un.size());
            ck_assert_msg(std::memcmp(kept.P.data(), P.data(), P.size() * sizeof(double)) == 0 &&
                              std::memcmp(kept.un.data(), un.data(), un.size() * sizeof(double)) == 0,
                          "%dD Theta = %g, tangent %d, step %d: the state's points differ", dim, theta,
                          static_cast<int>(choice), k + 1);
          }
          const double evaluations = scalar(p, ND_STAT_CONTACT_EVALUATIONS) - before;
          before += evaluations;
          const int active = scalar(p, ND_ACTIVE_POINTS) > 0;
          contact_steps += active;
          const bool full = choice != nd::TangentChoice::Condensed;
          if (full && active && was_active) {
            ck_assert_msg(evaluations == scalar(p, ND_NEWTON_ITERATIONS) + 1, "%dD, tangent %d, step %d: %g passes",
                          dim, static_cast<int>(choice), k + 1, evaluations);
            ++counted;
          }
          was_active = active;
        }
        ck_assert_int_gt(contact_steps, 5);
        if (choice != nd::TangentChoice::Condensed) ck_assert_int_gt(counted, 3);
        nd_problem_destroy(&p);
      }
}
END_TEST

// The automatic choice is the low-rank solver; with a rank limit of 0 it
// hands every contact solve to the refactoring inside and still agrees.
START_TEST(automatic_choice) {
  compare(2, 2, kSchemes[3], 1.0, nd::TangentChoice::Auto, 30);
  nd_problem p = scene(2, 1, kSchemes[3], 1.0);
  ND_OK_OR_FAIL(nd_step(p));
  ck_assert_str_eq(p->problem.integrator()->tangent->name(), "lowrank");
  nd_problem_destroy(&p);
}
END_TEST

// The updated factor's bits depend on its history (the state's TangentLog):
// a run resumed from a checkpoint taken in contact, with updates in its
// history, and a run that retries steps after failing them (Newton limited
// to one iteration: the failed step changed the factor), are bitwise the
// uninterrupted run. The 3D default (Theta = 1) is the updated factor, on
// the box a simplicial LDL^T (CHOLMOD's updates); on the refined rectangle
// (asked for) a supernodal LL^T (ours, linalg/supernodal.hpp).
void updated_factor_history(int dim, int refine, bool supernodal) {
  const SchemeCase &sc = kSchemes[0];  // theta 0.5: steps of two Newton iterations in this scene
  const int first = 30, then = 30;
  auto bits = [](nd_problem p) {
    const nd::State &st = p->problem.current_state();
    std::vector<double> b(st.U);
    b.insert(b.end(), st.V.begin(), st.V.end());
    return b;
  };
  auto make = [&] {
    nd_problem p = scene(dim, 2, sc, 1.0, refine);
    if (dim == 2) p->problem.set_tangent(nd::TangentChoice::Updown);
    return p;
  };
  nd_problem a = make(), retry = make();
  int64_t size1 = 0, size2 = 0;
  ND_OK_OR_FAIL(nd_problem_get_state_size(a, &size1));
  // the checkpoint at step `first`, or at the first step after it with updates in the history
  int taken = 0;
  auto updated = [&] {
    const nd::TangentLog &h = a->problem.current_state().tangent_log;
    return !h.i.empty() && static_cast<int64_t>(h.i.size()) > 1 + h.i[0];
  };
  for (; taken < first || (!updated() && taken < 3 * first); ++taken) ND_OK_OR_FAIL(nd_step(a));
  ND_OK_OR_FAIL(nd_problem_get_state_size(a, &size2));
  ck_assert_int_eq(size1, size2);  // the history takes its longest form's room: no change as it grows
  ck_assert_str_eq(a->problem.integrator()->tangent->name(), "updown");
  // (the updated factor's form is that of CHOLMOD's analysis of A's pattern)
  ck_assert(nd::cholmod_is_supernodal(a->problem.integrator()->A) == supernodal);
  const nd::TangentLog &log = a->problem.current_state().tangent_log;
  ck_assert_msg(!log.i.empty() && static_cast<int64_t>(log.i.size()) > 1 + log.i[0],
                "no update in the history at the checkpoint (%zu entries)", log.i.size());
  ck_assert(nd::tangent_log_well_formed(log, static_cast<int64_t>(a->problem.discretization().contact.size())));
  // every update the history holds was a rank-one modification of the
  // factor, counted, with its work (at least its diagonal)
  int64_t logged = 0;
  for (size_t at = 1 + static_cast<size_t>(log.i[0]); at < log.i.size();) {  // [+-m, q_1 .. q_m] per update
    const int64_t m = std::abs(log.i[at]);
    logged += m, at += 1 + static_cast<size_t>(m);
  }
  double modifications = 0, entries = 0;
  ND_OK_OR_FAIL(nd_get_scalar(a, ND_STAT_FACTOR_MODIFICATIONS, &modifications));
  ND_OK_OR_FAIL(nd_get_scalar(a, ND_STAT_FACTOR_MODIFIED_ENTRIES, &entries));
  ck_assert_msg(logged > 0 && modifications >= logged && entries > modifications,
                "%lld updates in the history, %g modifications counted, %g entries", static_cast<long long>(logged),
                modifications, entries);
  const std::vector<unsigned char> saved = a->problem.save_state();
  for (int k = 0; k < then; ++k) ND_OK_OR_FAIL(nd_step(a));
  nd_problem b = make();
  ND_OK_OR_FAIL(nd_problem_load_state(b, static_cast<int64_t>(saved.size()), saved.data()));
  for (int k = 0; k < then; ++k) ND_OK_OR_FAIL(nd_step(b));
  ck_assert_msg(bits(a) == bits(b), "the resumed run differs");
  // (in 3D the resumed steps include ones whose first iteration kept the
  // last tangent, fast/tangent_updown.cpp: the choice is made alike; on the
  // 2D rectangle no step's changes cost three solves)
  double lagged_a = 0, lagged_b = 0;
  ND_OK_OR_FAIL(nd_get_scalar(a, ND_STAT_LAGGED_STEPS, &lagged_a));
  ND_OK_OR_FAIL(nd_get_scalar(b, ND_STAT_LAGGED_STEPS, &lagged_b));
  if (dim == 3)
    ck_assert_msg(lagged_b > 0 && lagged_b <= lagged_a, "%g lagged steps resumed, %g in the whole run", lagged_b,
                  lagged_a);

  const nd::NewtonOptions defaults;
  int failed = 0, diverged = 0;
  for (int k = 0; k < taken + then; ++k) {
    ND_OK_OR_FAIL(nd_problem_set_newton(retry, defaults.rtol, defaults.atol, 1));
    const int status = nd_step(retry);
    if (status != ND_OK) {
      ck_assert_int_eq(status, ND_ERR_NEWTON);
      ++failed;
      const nd::TangentSolver &t = *retry->problem.integrator()->tangent;
      diverged += t.log() && *t.log() != retry->problem.current_state().tangent_log;
      ND_OK_OR_FAIL(nd_problem_set_newton(retry, defaults.rtol, defaults.atol, defaults.max_iter));
      ND_OK_OR_FAIL(nd_step(retry));
    }
  }
  ck_assert_msg(failed > 0 && diverged > 0, "%d failed steps, %d of them changed the factor", failed, diverged);
  ck_assert_msg(bits(a) == bits(retry), "the run with failed and retried steps differs");
  nd_problem_destroy(&a);
  nd_problem_destroy(&b);
  nd_problem_destroy(&retry);
}
START_TEST(updated_factor_history_simplicial) { updated_factor_history(3, 1, false); }
END_TEST
START_TEST(updated_factor_history_supernodal) { updated_factor_history(2, 5, true); }
END_TEST

// A whole run has the same bits with and without the wide (AVX2) forms
// (common/simd.hpp): the condensed Newton with whole columns (their sums in
// subtract_blocked), 2D P1 and P2, and the updated factor in its supernodal
// form (its rotations), on the refined rectangle; besides the passes every
// step makes. U and V at every step, bit for bit.
START_TEST(runs_have_the_bits_without_the_wide_forms) {
  struct Case {
    int degree, refine;
    nd::TangentChoice tangent;
    ndtest::Body body;
  };
  const bool before = nd::simd_on();
  // (and on quadrilaterals: Q1, Q2, and the updated factor on the refined Q2 rectangle)
  for (const Case &c : {Case{1, 1, nd::TangentChoice::Condensed, {}}, Case{2, 1, nd::TangentChoice::Condensed, {}},
                        Case{2, 5, nd::TangentChoice::Updown, {}},
                        Case{1, 1, nd::TangentChoice::Condensed, ndtest::kQuads},
                        Case{2, 1, nd::TangentChoice::Condensed, ndtest::kMixed},
                        Case{2, 5, nd::TangentChoice::Updown, ndtest::kQuads}}) {
    nd_problem run[2];
    for (nd_problem &p : run) {
      p = scene(2, c.degree, kSchemes[2], 1.0, c.refine, c.body);
      p->problem.set_tangent(c.tangent);
      if (c.tangent == nd::TangentChoice::Condensed) p->problem.set_column_rows(nd::ColumnRows::Whole);
    }
    int contact = 0;
    for (int k = 0; k < 40; ++k) {
      for (int wide = 0; wide < 2; ++wide) {
        nd::set_simd(wide == 1 && before);
        ND_OK_OR_FAIL(nd_step(run[wide]));
      }
      const nd::State &a = run[0]->problem.current_state(), &b = run[1]->problem.current_state();
      auto same = [](const std::vector<double> &x, const std::vector<double> &y) {
        return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
      };
      ck_assert_msg(same(a.U, b.U) && same(a.V, b.V), "P%d refine %d %s, step %d: the wide forms' run differs",
                    c.degree, c.refine, c.body.name, k + 1);
      contact += scalar(run[0], ND_ACTIVE_POINTS) > 0;
    }
    ck_assert_msg(contact > 5, "P%d refine %d %s: %d steps in contact", c.degree, c.refine, c.body.name, contact);
    for (nd_problem &p : run) nd_problem_destroy(&p);
  }
  nd::set_simd(before);
}
END_TEST

// What a checkpoint's history must look like before it is replayed.
START_TEST(malformed_histories) {
  const int64_t points = 10;
  nd::TangentLog ok;
  ok.i = {2, 1, 4, 3, 0, 5, 7, -1, 4};
  ok.x = {1.5, 2.0, 0.5, 0.25, 1.0, 2.0};
  ck_assert(nd::tangent_log_well_formed(ok, points));
  ck_assert(nd::tangent_log_well_formed(nd::TangentLog{}, points));
  std::vector<nd::TangentLog> bad(9, ok);
  bad[0].i[0] = 11;                  // more base points than points
  bad[1].i[2] = 1;                   // base not increasing
  bad[2].i[3] = 4;                   // an update longer than what follows
  bad[3].i[4] = 10;                  // a point out of range
  bad[4].x[3] = -0.25;               // a negative coefficient
  bad[5].x[5] = NAN;                 // a NaN
  bad[6].x.pop_back();               // coefficients missing
  bad[7].i[7] = INT64_MIN;           // a count that cannot be negated
  bad[8].i.push_back(0);             // an empty update
  for (size_t k = 0; k < bad.size(); ++k)
    ck_assert_msg(!nd::tangent_log_well_formed(bad[k], points), "malformed history %zu accepted", k);
}
END_TEST

int main(void) {
  Suite *s = suite_create("tangent");
  TCase *tc = tcase_create("lowrank_vs_refactor");
  tcase_set_timeout(tc, 600);
  tcase_add_test(tc, bar_p1);
  tcase_add_test(tc, bar_p2);
  tcase_add_test(tc, rectangle_p1);
  tcase_add_test(tc, rectangle_p2);
  tcase_add_test(tc, rectangle_p2_supernodal);
  tcase_add_test(tc, box_p1);
  tcase_add_test(tc, quadrilaterals);
  tcase_add_test(tc, mixed_and_disk);
  tcase_add_test(tc, hexahedra);
  tcase_add_test(tc, quadrilaterals_supernodal);
  tcase_add_test(tc, box_p2);
  tcase_add_test(tc, random_active_sets);
  tcase_add_test(tc, tangent_given_the_residuals_points);
  tcase_add_test(tc, new_state_points_from_newton);
  tcase_add_test(tc, columns_keep_their_dots_bitwise);
  tcase_add_test(tc, residual_from_products_is_newton_residual);
  tcase_add_test(tc, points_by_runs_bitwise);
  tcase_add_test(tc, k_theta_u_by_runs);
  tcase_add_test(tc, automatic_choice);
  tcase_add_test(tc, updated_factor_history_simplicial);
  tcase_add_test(tc, updated_factor_history_supernodal);
  tcase_add_test(tc, malformed_histories);
  tcase_add_test(tc, runs_have_the_bits_without_the_wide_forms);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
