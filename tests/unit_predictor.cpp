// A step that is its predictor (fast/predictor_check.hpp): Newmark,
// generalized-alpha and the theta-scheme take U^{n+1} = U^n + tau V^n +
// w tau^2 A^n (w = 1/2, or theta), with no solve, when it solves the step to
// round-off.
//  - A rigid fall (uniform velocity, uniform body force; 2D and 3D, P1 and
//    P2, with and without a contact region): every step predicted, no solve
//    after the set-up, U the scheme's exact discrete fall at every node, and
//    the identities E = m |v0 + g t|^2/2 and W = m g.(U - U^0).
//  - The same fall onto a plane: the predicted flight, then the impact
//    solved; the trajectories within 1e-10 of the run that solves every step
//    (Theta = 1 and -1), which predicts nothing.
//  - Deformed bodies, where the acceleration changes (a turning drop, a
//    clamped block starting from rest under gravity): nothing predicted, U
//    and V bitwise those of the run that never tries.
//  - A run resumed from a checkpoint within the predicted flight is bitwise
//    the uninterrupted run.
//  - The fall onto a plane and the turning drop on quadrilaterals and
//    hexahedra (Q1, Q2, mixed meshes, the disk in a bowl).
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "testutil.h"
#include "unit_drop.hpp"
#include "unit_fixtures.hpp"

namespace {

using ndtest::rel_diff;
using ndtest::SchemeCase;

const SchemeCase kPredicting[] = {
    {ND_SCHEME_NEWMARK, {0.25, 0.5}, "newmark"},
    {ND_SCHEME_GENERALIZED_ALPHA, {0.8}, "generalized-alpha 0.8"},
    {ND_SCHEME_THETA, {0.5}, "theta 0.5"},
    {ND_SCHEME_THETA, {1.0}, "theta 1"},
};
// the weight w of tau^2 A^n in the scheme's step at constant acceleration:
// 1/2 in the Newmark family, theta in the theta-scheme
double acceleration_weight(const SchemeCase &sc) { return sc.scheme == ND_SCHEME_THETA ? sc.params[0] : 0.5; }

double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

std::vector<double> field(nd_problem p, int which) {
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  std::vector<double> f(static_cast<size_t>(nodes * p->problem.space().dim));
  ND_OK_OR_FAIL(nd_get_field(p, which, nodes, f.data()));
  return f;
}

// ndtest::block_scene (mass 2) moving at v0 under the body force g; its
// bottom `gap` above a plane (no contact region when gap <= 0). clamped: the
// face x = 0 clamped, from rest.
const double kV2[2] = {0.3, -0.5}, kV3[3] = {0.3, 0.2, -0.5}, kG2[3] = {0, -1, 0}, kG3[3] = {0, 0, -1};
nd_problem rigid_fall(int dim, int degree, const SchemeCase &sc, double gap, double theta = 1, bool clamped = false,
                      const ndtest::Body &body = {}) {
  nd_problem p = ndtest::block_scene(dim, degree, sc, theta, gap, clamped, 1, body);
  // (Theta <= 0 with the automatic gamma0 gains energy at impacts (the method's own (Theta - 1) term, docs/design.md §3b): the energy-balance guard refuses it (test_guards_scale); this test compares predicted and solved steps)
  if (theta <= 0) ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0));
  ND_OK_OR_FAIL(nd_problem_set_body_force(p, dim == 2 ? kG2 : kG3));
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  std::vector<double> v0(static_cast<size_t>(nodes * dim));
  const double *v = dim == 2 ? kV2 : kV3;
  for (size_t i = 0; i < v0.size(); ++i) v0[i] = clamped ? 0.0 : v[i % static_cast<size_t>(dim)];
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nodes, nullptr, v0.data()));
  return p;
}

std::string name(int dim, int degree, const SchemeCase &sc, double theta = 1, const ndtest::Body &body = {}) {
  return std::to_string(dim) + "D P" + std::to_string(degree) + " " + sc.name + " Theta=" + std::to_string(theta) +
         " " + body.name;
}

}  // namespace

// The exact fall: with A^n = g the Newmark relations give U^{n+1} = U^n +
// tau V^n + tau^2 g/2 and V^{n+1} = V^n + tau g, so U^n = v0 t + g t^2/2; the
// theta-scheme's U^{n+1} = U^n + tau V^n + theta tau^2 g gives
// U^n = v0 t + g (t^2/2 + (theta - 1/2) tau t). Identities: E = m |v0 + g t|^2/2
// (m = 2) and the loads' work W = m g.(U^n - U^0), for any weight (for
// theta = 1 the fall loses E - E^0 - W = -m |g|^2 tau t/2 to the scheme).
// The bound: A^0 from a direct solve with M (these meshes are below the
// conjugate gradients' size), relative error <= cond(M) eps with cond(M) <= 100
// for these P1/P2 masses; then each step rounds U, V and A's sum once more.
START_TEST(rigid_fall_is_predicted) {
  const int steps = 30;
  for (int dim : {2, 3})
    for (int degree : {1, 2})
      for (const SchemeCase &sc : kPredicting)
        for (double gap : {0.0, 10.0}) {
          const std::string what = name(dim, degree, sc) + (gap > 0 ? " plane far below" : " no contact region");
          nd_problem p = rigid_fall(dim, degree, sc, gap);
          ND_OK_OR_FAIL(nd_problem_setup(p));
          const double solves = scalar(p, ND_STAT_SOLVES), factorizations = scalar(p, ND_STAT_FACTORIZATIONS);
          int64_t nodes = 0;
          ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
          const double *g = dim == 2 ? kG2 : kG3, *v0 = dim == 2 ? kV2 : kV3;
          double worst = 0, worst_E = 0, worst_W = 0;
          for (int k = 1; k <= steps; ++k) {
            ND_OK_OR_FAIL(nd_step(p));
            ck_assert_msg(scalar(p, ND_NEWTON_ITERATIONS) == 0, "%s: step %d solved", what.c_str(), k);
            const double t = scalar(p, ND_TIME), tau = scalar(p, ND_TIMESTEP);
            const std::vector<double> U = field(p, ND_FIELD_DISPLACEMENT);
            double d = 0, m = 0, v2 = 0, gU = 0;
            for (int c = 0; c < dim; ++c) {
              const double exact = v0[c] * t + g[c] * (0.5 * t * t + (acceleration_weight(sc) - 0.5) * tau * t);
              for (int64_t i = 0; i < nodes; ++i) d = std::max(d, std::fabs(U[i * dim + c] - exact));
              m = std::max(m, std::fabs(exact));
              gU += g[c] * exact;
              v2 += (v0[c] + g[c] * t) * (v0[c] + g[c] * t);
            }
            worst = std::max(worst, d / m);
            const double E = scalar(p, ND_ENERGY_MECHANICAL);
            worst_E = std::max(worst_E, std::fabs(E - 0.5 * 2 * v2) / E);
            worst_W = std::max(worst_W, std::fabs(scalar(p, ND_WORK) - 2 * gU) / E);
          }
          const double bound = (100 + 4 * steps) * DBL_EPSILON;
          if (std::getenv("ND_PREDICTOR_TEST_VERBOSE"))
            std::fprintf(stderr, "%s: U %.2e (bound %.2e), E %.2e, W %.2e\n", what.c_str(), worst, bound,
                         worst_E, worst_W);
          ck_assert_msg(worst <= bound, "%s: U off the exact fall by %g relative (bound %g)", what.c_str(), worst,
                        bound);
          ck_assert_msg(worst_E <= 1e-12 && worst_W <= 1e-12, "%s: E off m|v|^2/2 by %g, W off m g.U by %g",
                        what.c_str(), worst_E, worst_W);
          ck_assert_double_eq(scalar(p, ND_STAT_PREDICTED_STEPS), steps);
          ck_assert_double_eq(scalar(p, ND_STAT_SOLVES), solves);
          ck_assert_double_eq(scalar(p, ND_STAT_FACTORIZATIONS), factorizations);
          ck_assert_double_eq(scalar(p, ND_NEWTON_ITERATIONS_TOTAL), 0);
          ND_OK_OR_FAIL(nd_problem_destroy(&p));
        }
}
END_TEST

// The fall onto a plane 0.1 below (the impact near t = 0.18, step 18): the
// predicted flight, then contact, against the run that solves every step.
void fall_onto_a_plane(int dim, int degree, const SchemeCase &sc, double theta, const ndtest::Body &body = {}) {
  const int steps = 60;
  const std::string what = name(dim, degree, sc, theta, body);
  nd_problem on = rigid_fall(dim, degree, sc, 0.1, theta, false, body),
             off = rigid_fall(dim, degree, sc, 0.1, theta, false, body);
  off->problem.set_predicted_steps(false);
  double worst = 0;
  int contact_steps = 0, predicted_in_contact = 0;
  for (int k = 1; k <= steps; ++k) {
    ND_OK_OR_FAIL(nd_step(on));
    ND_OK_OR_FAIL(nd_step(off));
    for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY})
      worst = std::max(worst, rel_diff(field(on, which), field(off, which)));
    const bool contact = scalar(off, ND_ACTIVE_POINTS) > 0;
    contact_steps += contact;
    // (a step whose solved twin applied a contact force is never its
    // predictor; in a bowl, generalized-alpha's step into contact can end
    // with points active and have applied no force: its predictor solves it)
    predicted_in_contact += scalar(off, ND_CONTACT_FORCE_APPLIED) != 0 && scalar(on, ND_NEWTON_ITERATIONS) == 0;
  }
  const double predicted = scalar(on, ND_STAT_PREDICTED_STEPS);
  if (std::getenv("ND_PREDICTOR_TEST_VERBOSE"))
    std::fprintf(stderr, "%s: %.2e, %g predicted, %d contact steps\n", what.c_str(), worst, predicted,
                 contact_steps);
  ck_assert_msg(worst <= 1e-10, "%s: the trajectories differ by %g relative", what.c_str(), worst);
  ck_assert_msg(predicted >= 15 && scalar(off, ND_STAT_PREDICTED_STEPS) == 0,
                "%s: %g steps predicted (the flight is 17 steps)", what.c_str(), predicted);
  ck_assert_msg(contact_steps > 10 && predicted_in_contact == 0, "%s: %d contact steps, %d of them predicted",
                what.c_str(), contact_steps, predicted_in_contact);
  ND_OK_OR_FAIL(nd_problem_destroy(&on));
  ND_OK_OR_FAIL(nd_problem_destroy(&off));
}

START_TEST(fall_onto_a_plane_follows_the_solved_run) {
  for (int dim : {2, 3})
    for (int degree : {1, 2}) {
      if (dim == 3 && degree == 2) continue;  // (3D P1 holds the 3D contact paths)
      for (const SchemeCase &sc : kPredicting)
        for (double theta : {1.0, -1.0}) fall_onto_a_plane(dim, degree, sc, theta);
    }
}
END_TEST

// on and off step together: U and V bitwise equal at every step, nothing predicted
void same_bits_unpredicted(nd_problem on, nd_problem off, int steps, const std::string &what) {
  off->problem.set_predicted_steps(false);
  for (int k = 1; k <= steps; ++k) {
    ND_OK_OR_FAIL(nd_step(on));
    ND_OK_OR_FAIL(nd_step(off));
    for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY}) {
      const std::vector<double> a = field(on, which), b = field(off, which);
      ck_assert_msg(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0, "%s: step %d differs",
                    what.c_str(), k);
    }
  }
  ck_assert_msg(scalar(on, ND_STAT_PREDICTED_STEPS) == 0, "%s: %g steps predicted", what.c_str(),
                scalar(on, ND_STAT_PREDICTED_STEPS));
  ck_assert_double_eq(scalar(on, ND_NEWTON_ITERATIONS_TOTAL), scalar(off, ND_NEWTON_ITERATIONS_TOTAL));
  ND_OK_OR_FAIL(nd_problem_destroy(&on));
  ND_OK_OR_FAIL(nd_problem_destroy(&off));
}

START_TEST(deformed_bodies_are_solved) {
  for (const SchemeCase &sc : kPredicting)
    for (int dim : {2, 3})
      for (int degree : {1, 2}) {
        // a turning drop (ndtest::drop_scene: the velocity grows with x), 80 steps through its impact
        same_bits_unpredicted(ndtest::drop_scene(dim, degree, sc, 1.0, 0.3), ndtest::drop_scene(dim, degree, sc, 1.0, 0.3),
                              80, name(dim, degree, sc) + " turning drop");
        // a block clamped at x = 0, from rest under gravity: it starts to sag
        same_bits_unpredicted(rigid_fall(dim, degree, sc, 0.0, 1, true), rigid_fall(dim, degree, sc, 0.0, 1, true),
                              40, name(dim, degree, sc) + " clamped block");
      }
}
END_TEST

// Quadrilaterals and hexahedra (docs/performance.md, "Quadrilaterals and
// hexahedra"): the fall onto a plane (onto a bowl, the disk) predicted and
// then solved as the run that solves every step, and the turning drop
// solved with the bits of the run that never tries, on Q1 and Q2
// rectangles of quadrilaterals, the mixed mesh (P1/Q1, P2/Q2), the
// quadrilateral disk and a box of Q1 hexahedra.
START_TEST(quadrilaterals_and_hexahedra) {
  struct Case {
    int dim, degree;
    ndtest::Body body;
  };
  for (const Case &c : {Case{2, 1, ndtest::kQuads}, Case{2, 2, ndtest::kQuads}, Case{2, 1, ndtest::kMixed},
                        Case{2, 2, ndtest::kMixed}, Case{2, 1, ndtest::kDiskInBowl}, Case{3, 1, ndtest::kHexahedra}})
    for (const SchemeCase &sc : kPredicting) {
      for (double theta : {1.0, -1.0}) fall_onto_a_plane(c.dim, c.degree, sc, theta, c.body);
      const std::string what = name(c.dim, c.degree, sc, 1, c.body) + " turning drop";
      same_bits_unpredicted(ndtest::drop_scene(c.dim, c.degree, sc, 1.0, 0.3, 0.1, 1, c.body),
                            ndtest::drop_scene(c.dim, c.degree, sc, 1.0, 0.3, 0.1, 1, c.body), 80, what);
    }
}
END_TEST

// A checkpoint within the predicted flight: the resumed run is bitwise the
// uninterrupted one (whether a step tries its predictor is read from the
// state: the last step's iterations, its step index and its contact term).
START_TEST(resumed_within_the_flight) {
  for (const SchemeCase &sc : kPredicting) {
    nd_problem a = rigid_fall(2, 2, sc, 0.1), b = rigid_fall(2, 2, sc, 0.1);
    for (int k = 0; k < 8; ++k) ND_OK_OR_FAIL(nd_step(a));
    int64_t size = 0;
    ND_OK_OR_FAIL(nd_problem_get_state_size(a, &size));
    std::vector<unsigned char> buf(static_cast<size_t>(size));
    ND_OK_OR_FAIL(nd_problem_save_state(a, size, buf.data()));
    ND_OK_OR_FAIL(nd_problem_load_state(b, size, buf.data()));
    int contact_steps = 0;
    for (int k = 0; k < 40; ++k) {
      ND_OK_OR_FAIL(nd_step(a));
      ND_OK_OR_FAIL(nd_step(b));
      contact_steps += scalar(b, ND_ACTIVE_POINTS) > 0;
      for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY, ND_FIELD_ACCELERATION}) {
        const std::vector<double> x = field(a, which), y = field(b, which);
        ck_assert_msg(std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0, "%s: step %d differs",
                      sc.name, k + 9);
      }
    }
    // the resumed run predicted the rest of the flight, then went into contact
    ck_assert(scalar(a, ND_STAT_PREDICTED_STEPS) > 8 && scalar(b, ND_STAT_PREDICTED_STEPS) > 0);
    ck_assert_int_gt(contact_steps, 10);
    ND_OK_OR_FAIL(nd_problem_destroy(&a));
    ND_OK_OR_FAIL(nd_problem_destroy(&b));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("predictor");
  TCase *tc = tcase_create("predictor");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, rigid_fall_is_predicted);
  tcase_add_test(tc, fall_onto_a_plane_follows_the_solved_run);
  tcase_add_test(tc, deformed_bodies_are_solved);
  tcase_add_test(tc, quadrilaterals_and_hexahedra);
  tcase_add_test(tc, resumed_within_the_flight);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
