// The contact law as an object (src/contact/law.hpp): the registry's
// frictionless law and its traits, and the fallback a law that declines the
// fast paths gets: a test-only law, the frictionless one's values through
// virtual calls, reporting none of the traits (not rank one, not symmetric,
// not zero where free, not nondecreasing, not [P]_+), gives a 2D drop on a
// plane the trajectory of the fast paths (the condensed Newton, the bounds,
// the predictor, [P]_+ inline) for every implicit scheme, through the
// refactoring tangent and the generic passes alone.
//
// The bound: Newton stops only where its active set held over the last
// iteration (solve/newton.hpp), and G(U) = A U + kappa N(U) - r is linear on
// an active set (N is piecewise linear in U): both paths' solutions are the
// one solution of the same linear system, apart from their solves' round-off
// and Newton's residual tolerance rtol (||r|| + c ||M U||), rtol = 1e-10. So
// each state agrees to rtol relative (as tests/unit_tangent.cpp holds its
// paths), with the same active points and Newton counts at every step.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "contact/friction.hpp"
#include "contact/law.hpp"
#include "time/scheme.hpp"
#include "testutil.h"
#include "unit_drop.hpp"
#include "unit_fixtures.hpp"

namespace {

// the frictionless law's values, every trait declined
class Declining final : public nd::PointLaw {
 public:
  Declining() : PointLaw(declined()) {}
  const char *name() const override { return "declining (test)"; }
  void at(double x, double &value, double &slope) const override { nd::frictionless_law().at(x, value, slope); }

 private:
  static nd::LawTraits declined() {
    nd::LawTraits t;
    t.rank_one = t.symmetric = t.zero_when_free = t.nondecreasing = t.positive_part = false;
    return t;
  }
};

std::vector<double> field(nd_problem p, int which, int64_t nodes, int dim) {
  std::vector<double> f(static_cast<size_t>(nodes * dim));
  ND_OK_OR_FAIL(nd_get_field(p, which, nodes, f.data()));
  return f;
}

double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

}  // namespace

START_TEST(registry_gives_the_frictionless_law) {
  const std::shared_ptr<const nd::PointLaw> law = nd::make_law(nd::kFrictionNone);
  const nd::LawTraits &t = law->traits();
  ck_assert_str_eq(law->name(), "frictionless");
  ck_assert(t.m == 1 && t.rank_one && t.symmetric && t.zero_when_free && t.nondecreasing && t.positive_part &&
            t.max_slope == 1);
  int code = 0;
  try {
    nd::make_law(99);
  } catch (const nd::Error &e) {
    code = e.code();
  }
  ck_assert_int_eq(code, ND_ERR_VALUE);
  // a problem's law is the frictionless one unless it is given another
  nd_problem p = ndtest::drop_scene(2, 1, ndtest::kSchemes[2], 1.0);
  ck_assert(p->problem.definition().friction.empty());
  ck_assert_str_eq(p->problem.discretization().contact_law->name(), "frictionless");
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

// Any law runs under any scheme's time rule: the rule applied to a law's
// at() by the generic over_step (Declining's) is, bit for bit, the
// frictionless law's own inlined form, for every scheme's rule (the values
// below and at the switches: P^n = 0, mid = 0, signed zeros, subnormals).
START_TEST(time_rules_apply_to_any_law) {
  const Declining generic;
  const double tiny = 4.9e-324;
  const double xs[] = {-2, -0.5, -tiny, -0.0, 0.0, tiny, 0.25, 0.5, 3};
  int rules = 0;
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes) {
    const nd::TimeRule rule = nd::make_scheme(sc.scheme, sc.params)->contact_rule();
    rules += rule.kind != nd::TimeRule::AtEnd;
    for (double P : xs)
      for (double Pn : xs) {
        double v, s, gv, gs;
        nd::frictionless_law().over_step(rule, P, Pn, v, s);
        generic.over_step(rule, P, Pn, gv, gs);
        ck_assert_msg(std::memcmp(&v, &gv, sizeof v) == 0 && std::memcmp(&s, &gs, sizeof s) == 0,
                      "%s at P = %g, P^n = %g: (%g, %g) generic (%g, %g)", sc.name, P, Pn, v, s, gv, gs);
      }
  }
  ck_assert_int_eq(rules, 2);  // (the hybrid's and generalized-alpha's rules besides AtEnd)
}
END_TEST

START_TEST(declined_traits_fall_back_to_the_same_trajectory) {
  // (0.2 above the plane: a free flight of some 15 steps first, where the
  // bounds show the fast path's steps free)
  const int dim = 2, steps = 60;
  const double gap = 0.2;
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes) {
    nd_problem fast = ndtest::drop_scene(dim, 1, sc, 1.0, gap), slow = ndtest::drop_scene(dim, 1, sc, 1.0, gap);
    slow->problem.set_contact_law(std::make_shared<Declining>());
    int64_t nodes = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(fast, &nodes));
    double worst = 0;
    int active_steps = 0;
    for (int k = 0; k < steps; ++k) {
      ND_OK_OR_FAIL(nd_step(fast));
      ND_OK_OR_FAIL(nd_step(slow));
      for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY})
        worst = std::max(worst, ndtest::rel_diff(field(slow, which, nodes, dim), field(fast, which, nodes, dim)));
      const double active = scalar(fast, ND_ACTIVE_POINTS);
      ck_assert_msg(scalar(slow, ND_ACTIVE_POINTS) == active, "%s: step %d: active points differ", sc.name, k);
      ck_assert_msg(scalar(slow, ND_NEWTON_ITERATIONS) == scalar(fast, ND_NEWTON_ITERATIONS) ||
                        scalar(fast, ND_NEWTON_ITERATIONS) == 0,  // (a predicted step: no Newton)
                    "%s: step %d: Newton iterations differ", sc.name, k);
      active_steps += active > 0;
    }
    std::printf("unit_contact_law: %s: fallback vs fast paths %.2g relative over %d steps (%d in contact)\n",
                sc.name, worst, steps, active_steps);
    ck_assert_msg(worst <= 1e-10, "%s: trajectories differ by %g relative", sc.name, worst);
    ck_assert_msg(active_steps > 0, "%s: the scene never came into contact", sc.name);
    // the paths taken: the fallback refactored its tangent and showed nothing by a bound
    ck_assert_str_eq(slow->problem.integrator()->tangent->name(), "refactor");
    ck_assert_str_ne(fast->problem.integrator()->tangent->name(), "refactor");
    ck_assert(scalar(slow, ND_STAT_CONTACT_BOUNDS) == 0 && scalar(slow, ND_STAT_PREDICTED_STEPS) == 0);
    ck_assert(scalar(fast, ND_STAT_CONTACT_BOUNDS) > 0);
    ND_OK_OR_FAIL(nd_problem_destroy(&fast));
    ND_OK_OR_FAIL(nd_problem_destroy(&slow));
  }
}
END_TEST

// The frictional laws (contact/friction.hpp): the Jacobian they give is the
// derivative of their values (central differences, away from the kinks:
// |Y_t| = r and P_n = 0, for every rule, m = 2 and 3); the tangential values
// lie in the disk of radius r, equal Y_t inside it, and point along Y_t
// outside (phi_t . (Y_t - phi_t) >= 0: what D_f adds up).
START_TEST(friction_laws_jacobian_and_projection) {
  const nd::TimeRule rules[] = {nd::TimeRule{}, nd::TimeRule{nd::TimeRule::Shifted, 0.3},
                                nd::TimeRule{nd::TimeRule::Hybrid, 0}};
  const double coefficient = 0.4, gamma = 0.7;
  unsigned seed = 12345;
  auto uniform = [&seed]() {
    seed = seed * 1103515245u + 12345u;
    return ((seed >> 8) & 0xffff) / 65535.0 * 2 - 1;
  };
  int checked = 0;
  for (int law : {ND_FRICTION_TRESCA, ND_FRICTION_COULOMB})
    for (int m = 2; m <= 3; ++m) {
      const auto f = nd::make_law(law, &coefficient, m);
      ck_assert_int_eq(f->traits().m, m);
      ck_assert(!f->traits().rank_one);
      for (const nd::TimeRule &rule : rules)
        for (int trial = 0; trial < 200; ++trial) {
          double P[3], Pn[3], v[3], J[9];
          for (int k = 0; k < m; ++k) P[k] = 2 * uniform(), Pn[k] = 2 * uniform();
          f->over_step_m(rule, 0, gamma, m, P, Pn, v, J);
          // the disk: r from the normal value the rule applies
          const double r = law == ND_FRICTION_COULOMB ? coefficient * v[0] : gamma * coefficient;
          const double c = rule.kind == nd::TimeRule::Shifted ? 1 - rule.af : 1.0;
          double Y[2], y2 = 0, t2 = 0, dot = 0;
          for (int k = 1; k < m; ++k) {
            Y[k - 1] = c * P[k] + (c == 1 ? 0.0 : (1 - c) * Pn[k]);
            y2 += Y[k - 1] * Y[k - 1];
            t2 += v[k] * v[k];
            dot += v[k] * (Y[k - 1] - v[k]);
          }
          ck_assert_double_le(std::sqrt(t2), r * (1 + 1e-15) + 1e-300);
          ck_assert_double_ge(dot, -1e-15 * (y2 + 1));
          const double kink = std::min(std::fabs(std::sqrt(y2) - r), std::fabs(P[0]));
          if (kink < 1e-3 || (rule.kind == nd::TimeRule::Hybrid && std::fabs(Pn[0]) < 1e-3) ||
              (rule.kind != nd::TimeRule::AtEnd && std::fabs(0.5 * (P[0] + Pn[0])) < 1e-3) ||
              (rule.kind == nd::TimeRule::Shifted && std::fabs(c * P[0] + (1 - c) * Pn[0]) < 1e-3))
            continue;
          const double h = 1e-7;
          for (int l = 0; l < m; ++l) {
            double Pp[3], Pm[3], vp[3], vm[3], Jx[9];
            std::copy(P, P + 3, Pp), std::copy(P, P + 3, Pm);
            Pp[l] += h, Pm[l] -= h;
            f->over_step_m(rule, 0, gamma, m, Pp, Pn, vp, Jx);
            f->over_step_m(rule, 0, gamma, m, Pm, Pn, vm, Jx);
            for (int k = 0; k < m; ++k)
              ck_assert_msg(std::fabs((vp[k] - vm[k]) / (2 * h) - J[k * m + l]) <= 1e-6,
                            "law %d m %d rule %d: dphi_%d/dP_%d = %g, J = %g", law, m, int(rule.kind), k, l,
                            (vp[k] - vm[k]) / (2 * h), J[k * m + l]);
          }
          ++checked;
        }
    }
  std::printf("friction laws: %d points checked against central differences\n", checked);
  ck_assert_int_gt(checked, 1000);
}
END_TEST

// The fast tangents of friction against the refactoring one: in 2D the
// block tangent (fast/tangent_blocks.cpp: Woodbury over the active points'
// m values, A's factor reused), in 3D GMRES preconditioned by the sticking
// tangent's factor (fast/tangent_sticking.cpp). A block dropped, turning,
// with a tangential velocity onto the plane, Coulomb F = 0.3 (sliding, then
// sticking) and Tresca, every implicit scheme, Theta = 1 and 0: the same
// trajectories to 1e-10 relative (the Newton tolerance and the solves'
// round-off), and the paths are those named.
START_TEST(friction_fast_tangents_are_the_refactored_one) {
  const double F = 0.3, s_T = 0.05;
  const int dim = _i + 2;
  int compared = 0;
  double farthest = 0;
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes)
    for (double theta : {1.0, 0.0})
      for (int law : {ND_FRICTION_COULOMB, ND_FRICTION_TRESCA}) {
        nd_problem runs[2];
        for (int k = 0; k < 2; ++k) {
          runs[k] = ndtest::drop_scene(dim, 1, sc, theta);
          // (Theta <= 0 with the automatic gamma0 gains energy at impacts (the method's own (Theta - 1) term, docs/design.md §3b): the energy-balance guard refuses it (test_guards_scale); this test compares tangents)
          if (theta <= 0) ND_OK_OR_FAIL(nd_problem_set_guard(runs[k], ND_GUARD_ENERGY_BALANCE, 0));
          ND_OK_OR_FAIL(nd_problem_set_friction(runs[k], 1, law, law == ND_FRICTION_COULOMB ? &F : &s_T));
          int64_t nodes = 0;
          ND_OK_OR_FAIL(nd_problem_get_node_count(runs[k], &nodes));
          std::vector<double> v(static_cast<size_t>(dim * nodes), 0.0);
          for (int64_t i = 0; i < nodes; ++i) v[dim * i] = 0.2, v[dim * i + dim - 1] = -0.1;
          ND_OK_OR_FAIL(nd_problem_set_initial_state(runs[k], nodes, nullptr, v.data()));
          if (k == 0) runs[k]->problem.set_tangent(nd::TangentChoice::Refactor);
        }
        int64_t nodes = 0;
        ND_OK_OR_FAIL(nd_problem_get_node_count(runs[0], &nodes));
        std::vector<double> a(static_cast<size_t>(dim * nodes)), b(a.size());
        double worst = 0;
        for (int step = 0; step < 40; ++step) {
          ND_OK_OR_FAIL(nd_step(runs[0]));
          ND_OK_OR_FAIL(nd_step(runs[1]));
          for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY}) {
            ND_OK_OR_FAIL(nd_get_field(runs[0], which, nodes, a.data()));
            ND_OK_OR_FAIL(nd_get_field(runs[1], which, nodes, b.data()));
            worst = std::max(worst, ndtest::rel_diff(b, a));
          }
        }
        const nd::TangentStats &st = runs[1]->problem.integrator()->tangent->stats;
        ck_assert_str_eq(runs[0]->problem.integrator()->tangent->name(), "refactor");
        ck_assert_str_eq(runs[1]->problem.integrator()->tangent->name(), dim == 2 ? "blocks" : "sticking");
        // (the sticking tangent's refactorizations are its preconditioner's and its fallback's)
        ck_assert_msg(worst <= 1e-10 && st.lowrank > 0 && (dim == 3 || st.refactorizations == 0),
                      "%s Theta %g law %d: %g apart, %lld low-rank solves, %lld refactorizations", sc.name, theta,
                      law, worst, static_cast<long long>(st.lowrank), static_cast<long long>(st.refactorizations));
        double D = 0;
        ND_OK_OR_FAIL(nd_get_scalar(runs[1], ND_DISSIPATION_FRICTION, &D));
        ck_assert_double_gt(D, 0);
        ++compared;
        farthest = std::max(farthest, worst);
        for (nd_problem &p : runs) ND_OK_OR_FAIL(nd_problem_destroy(&p));
      }
  std::printf("friction %dD: %s tangent = refactored tangent over %d runs, at most %.2g apart\n", dim,
              dim == 2 ? "block" : "sticking", compared, farthest);
}
END_TEST

int main(void) {
  Suite *s = suite_create("contact_law");
  TCase *tc = tcase_create("law");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, registry_gives_the_frictionless_law);
  tcase_add_test(tc, time_rules_apply_to_any_law);
  tcase_add_test(tc, friction_laws_jacobian_and_projection);
  tcase_add_loop_test(tc, friction_fast_tangents_are_the_refactored_one, 0, 2);
  tcase_add_test(tc, declined_traits_fall_back_to_the_same_trajectory);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
