// The bound that settles a step's contact check without evaluating a point
// (ContactLaw::certainly_free): P_q(U) <= P_q(U^n) + nu_q max_i |U_i - U^n_i|
// + g^n_q - g_q, i over the DOFs of the points' rows, with a margin for
// round-off.
//  - Every scheme's contact law is nondecreasing in P, vanishes with its
//    slope below a point where both vanish, and where P <= 0 and P^n <= 0:
//    the bound relies on it.
//  - Sound: on random states around a step's U^n (the maximum taken over
//    the DOFs the points' rows touch), at every scale of
//    max|U - U^n| and with the obstacle moved, whenever the bound says
//    "free", P_q(U) evaluated puts every point's law and slope at zero. The
//    trials also show the bound saying "free" and, conservatively, not
//    saying it where the points are free, and not saying it where they are
//    not; non-finite states are never shown free.
//  - The same bits: drops with a free flight, the impact and contact, for
//    every implicit scheme, Theta = 1 and -1, 2D P1/P2 and 3D P1, with the
//    condensed, low-rank and updated-factor tangents: U and V bitwise equal
//    with and without the bound at every step, the bound used in one run
//    only, with fewer passes over the points.
//  - The same on quadrilaterals and hexahedra (Q1, Q2, mixed meshes, the
//    disk in a bowl): same_bits_q, bound_is_sound_q.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "common/simd.hpp"
#include "monitor/energies.hpp"
#include "testutil.h"
#include "time/scheme.hpp"
#include "nitschedyn.h"
#include "unit_drop.hpp"

namespace {

double scalar(nd_problem p, int key) {
  double x = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, key, &x));
  return x;
}

// the frictionless law over a step by the scheme's rule: the same bits at
// every P^n <= 0?
bool same_below_zero(const nd::TimeScheme &scheme) {
  return nd::same_for_nonpositive_Pn(scheme.contact_rule(), nd::frictionless_law().traits());
}

START_TEST(laws_are_monotone) {
  std::vector<std::unique_ptr<nd::TimeScheme>> laws;
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes) laws.push_back(nd::make_scheme(sc.scheme, sc.params));
  // every listed scheme, whatever its contact term
#define ND_ADD_SCHEME_(name, value, text) \
  laws.push_back(nd::make_scheme(name, std::vector<double>(nd::scheme_parameter_count(name), 0.5)));
  ND_SCHEME_LIST(ND_ADD_SCHEME_)
#undef ND_ADD_SCHEME_
  laws.push_back(nd::make_scheme(ND_SCHEME_GENERALIZED_ALPHA, {0.0}));
  laws.push_back(nd::make_scheme(ND_SCHEME_GENERALIZED_ALPHA, {1.0}));
  const double Pns[] = {-1, -0.25, -1e-300, 0, 1e-300, 0.25, 1};
  int zero_regions = 0;
  for (const auto &law : laws)
    for (double Pn : Pns) {
      double last = -1, value = 0, slope = 0;
      bool zero_so_far = true;  // the law and its slope vanished at every P so far
      for (int i = -512; i <= 512; ++i) {
        const double P = i / 128.0 + (i % 3 ? 1e-300 * (i % 3) : 0.0);
        nd::frictionless_law().over_step(law->contact_rule(), P, Pn, value, slope);
        ck_assert_msg(value >= last, "contact(%g, %g) = %g < %g: not nondecreasing", P, Pn, value, last);
        last = value;
        const bool zero = value == 0 && slope == 0;
        ck_assert_msg(zero || !zero_so_far || i > -512, "contact(%g, %g) active at the bottom of the range", P, Pn);
        if (zero) ck_assert_msg(zero_so_far, "contact(%g, %g) zero above a P where it was not", P, Pn);
        zero_so_far = zero_so_far && zero;
        zero_regions += zero;
      }
    }
  ck_assert(zero_regions > 0);
  // every law vanishes with its slope where P <= 0 and P^n <= 0
  for (const auto &law : laws)
    for (double Pn : {-1e300, -1.0, -0.25, -1e-300, -0.0, 0.0})
      for (double P : {-1e300, -1.0, -0.25, -1e-300, -0.0, 0.0}) {
        double value = 1, slope = 1;
        nd::frictionless_law().over_step(law->contact_rule(), P, Pn, value, slope);
        ck_assert_msg(value == 0 && slope == 0, "contact(%g, %g) = (%g, %g)", P, Pn, value, slope);
      }
  // a law that says it reads of P^n only that it is <= 0
  // (nd::same_for_nonpositive_Pn: a state whose points were
  // left unevaluated then stands as P^n) gives the same bits at every
  // P^n <= 0, -0 and +0 included; [P]_+ and the hybrid scheme's say so
  int same = 0;
  for (const auto &law : laws) {
    if (!same_below_zero(*law)) continue;
    ++same;
    for (int i = -512; i <= 512; ++i) {
      const double P = i / 128.0 + (i % 3 ? 1e-300 * (i % 3) : 0.0);
      double v0, s0;
      nd::frictionless_law().over_step(law->contact_rule(), P, -1.0, v0, s0);
      for (double Pn : {-1e300, -0.25, -1e-300, -0.0, 0.0}) {
        double v, s;
        nd::frictionless_law().over_step(law->contact_rule(), P, Pn, v, s);
        ck_assert_msg(std::memcmp(&v, &v0, sizeof v) == 0 && std::memcmp(&s, &s0, sizeof s) == 0,
                      "contact(%g, %g) = (%g, %g), at P^n = -1 (%g, %g)", P, Pn, v, s, v0, s0);
      }
    }
  }
  ck_assert(same > 0 && same_below_zero(*nd::make_scheme(ND_SCHEME_HYBRID, {})) &&
            !same_below_zero(*nd::make_scheme(ND_SCHEME_GENERALIZED_ALPHA, {0.8})));
}
END_TEST

// Is every point's law zero with its slope at U, evaluated point by point?
bool free_at(const nd::ContactLaw &law, const std::vector<double> &U) {
  for (size_t q = 0; q < law.cp->size(); ++q) {
    double value, slope;
    law.law(q, law.P(q, U.data()), value, slope);
    if (value != 0 || slope != 0) return false;
  }
  return true;
}

void soundness(int dim, int degree, const ndtest::SchemeCase &sc, double theta, const ndtest::Body &body = {}) {
  nd_problem p = ndtest::drop_scene(dim, degree, sc, theta, 0.3, 1.0, 1, body);
  ND_OK_OR_FAIL(nd_step(p));
  nd::Problem &pb = p->problem;
  const nd::Discretization &d = pb.discretization();
  const nd::Integrator &in = *pb.integrator();
  const nd::ContactPoints &cp = d.contact;
  const size_t n = static_cast<size_t>(in.A.n), Q = cp.size();
  ck_assert(Q > 0 && cp.nu.size() == Q);
  unsigned seed = 2024;
  auto rnd = [&seed] {  // in [-1, 1)
    seed = seed * 1103515245u + 12345u;
    return static_cast<double>((seed >> 8) & 0xffff) / 32768.0 - 1.0;
  };
  int shown = 0, missed = 0, active = 0, within = 0, within_missed = 0, beyond = 0;
  int nonpositive = 0, nonpositive_missed = 0, any_positive = 0, made_free = 0, made_within = 0;
  std::vector<double> Un(n), U(n), Pn, gap_n(cp.gap), gap(Q);
  for (int trial = 0; trial < 400; ++trial) {
    // U^n: the body somewhere between 0.5 above the plane and touching it
    const double lift = 0.25 * (1 + rnd());
    for (auto &u : Un) u = 0.01 * rnd() + lift * (trial % 2 ? 1 : 0.1);
    nd::ContactLaw ref{&cp, d.theta, nullptr, nullptr, gap_n.data()};
    ref.P_all(Un.data(), Pn);
    // the obstacle moved by up to 0.01 in a third of the trials
    const double move = trial % 3 == 0 ? 0.01 * rnd() : 0.0;
    for (size_t q = 0; q < Q; ++q) gap[q] = gap_n[q] + move;
    nd::ContactLaw law{&cp, d.theta, in.scheme.get(), &Pn, gap.data()};
    law.Un = Un.data(), law.gap_n = gap_n.data();
    const double scale = std::pow(10.0, -6 + (trial % 13) * 0.5);  // 1e-6 ... 1
    for (size_t i = 0; i < n; ++i) U[i] = Un[i] + scale * rnd();
    const bool bound = law.certainly_free(U), exact = free_at(law, U);
    ck_assert_msg(!bound || exact, "%dD P%d %s Theta = %g, trial %d: shown free, but a point is active", dim, degree,
                  sc.name, theta, trial);
    shown += bound, missed += exact && !bound, active += !exact;
    // the penetration guard's bound (nd::penetration_within) from the same
    // reference: shown within limit h_q only where u_n - g0 evaluated is
    // (the guard's test, monitor/guards.cpp)
    nd::PointReference at_n{Un, {}, {}, gap_n};  // (constructed: GCC 12 -O3 warns of a null in the assignments)
    ref.P_all(Un.data(), at_n.P, &at_n.un);
    const double limit = trial % 4 == 0 ? 1e-3 : trial % 4 == 1 ? 0.05 : 0.5;
    bool exceeds = false;
    for (size_t q = 0; q < Q; ++q) {
      double sa, ss;
      law.dots(q, U.data(), sa, ss);
      exceeds |= (sa - gap[q]) / cp.h[q] > limit;  // (u_n - g0's bits: ContactLaw::P_all)
    }
    const bool shown_within = nd::penetration_within(cp, U.data(), gap.data(), at_n, limit);
    // a query's bound (nd::nonpositive_within) from the same reference:
    // every P_q <= 0 shown only where every P_q evaluated is (its contact
    // forces are then zero)
    bool positive = false;
    for (size_t q = 0; q < Q; ++q) positive |= law.P(q, U.data()) > 0;
    const bool shown_nonpositive = nd::nonpositive_within(cp, U.data(), gap.data(), at_n);
    ck_assert_msg(!shown_nonpositive || !positive, "%dD P%d %s Theta = %g, trial %d: P <= 0 shown, but a P_q > 0",
                  dim, degree, sc.name, theta, trial);
    nonpositive += shown_nonpositive, nonpositive_missed += !positive && !shown_nonpositive, any_positive += positive;
    // the tests' wide form (AVX2, on by default where the CPU has it) and
    // the scalar one say the same
    nd::set_simd(false);
    ck_assert(law.certainly_free(U, false) == bound &&
              nd::penetration_within(cp, U.data(), gap.data(), at_n, limit) == shown_within &&
              nd::nonpositive_within(cp, U.data(), gap.data(), at_n) == shown_nonpositive);
    nd::set_simd(true);
    ck_assert_msg(!shown_within || !exceeds, "%dD P%d %s Theta = %g, trial %d: shown within %g h, but a point is not",
                  dim, degree, sc.name, theta, trial, limit);
    // the tests made once for the reference (nd::set_reference_reach, what
    // a free flight's checks read): where U's reach is admitted at the
    // reference's gaps they hold, and so do the tests at every point; the
    // checks that read them say what they said without
    nd::PointReference made = at_n;
    nd::set_reference_reach(cp, made, limit);
    const nd::Reach r = nd::reach(cp.dofs, U.data(), Un.data());
    const bool same_gaps = nd::same_gaps(gap.data(), gap_n.data(), Q);
    ck_assert(same_gaps == (move == 0));
    const bool fast_free = same_gaps && nd::reach_admitted(r, made.free_reach),
               fast_within = same_gaps && nd::reach_admitted(r, made.within_reach);
    ck_assert_msg(!fast_free || shown_nonpositive, "%dD P%d %s trial %d: P <= 0 admitted, not shown", dim, degree,
                  sc.name, trial);
    ck_assert_msg(!fast_within || shown_within, "%dD P%d %s trial %d: within %g h admitted, not shown", dim, degree,
                  sc.name, trial, limit);
    made_free += fast_free, made_within += fast_within;
    nd::ContactLaw from_made = law;
    from_made.free_reach_n = made.free_reach;
    ck_assert(from_made.certainly_free(U, false) == bound &&
              nd::penetration_within(cp, U.data(), gap.data(), made, limit) == shown_within &&
              nd::nonpositive_within(cp, U.data(), gap.data(), made) == shown_nonpositive);
    // the reach's wide form gives the scalar loop's values
    nd::set_simd(false);
    const nd::Reach scalar_reach = nd::reach(cp.dofs, U.data(), Un.data());
    nd::set_simd(true);
    ck_assert(scalar_reach.finite && r.finite && scalar_reach.d == r.d && scalar_reach.u_max == r.u_max &&
              scalar_reach.ref_max == r.ref_max);
    within += shown_within, within_missed += !exceeds && !shown_within, beyond += exceeds;
  }
  ck_assert_msg(nonpositive > 0 && nonpositive_missed > 0 && any_positive > 0,
                "%dD P%d %s: P <= 0 %d shown, %d not shown, %d with a P_q > 0", dim, degree, sc.name, nonpositive,
                nonpositive_missed, any_positive);
  ck_assert_msg(within > 0 && within_missed > 0 && beyond > 0,
                "%dD P%d %s: penetration %d shown within, %d within not shown, %d beyond", dim, degree, sc.name, within,
                within_missed, beyond);
  ck_assert_msg(made_free > 0 && made_within > 0, "%dD P%d %s: the reference's tests held in %d, %d trials", dim,
                degree, sc.name, made_free, made_within);
  if (std::getenv("ND_BOUNDS_TEST_VERBOSE"))
    std::fprintf(stderr, "%dD P%d %s Theta=%g: %d shown free, %d free not shown, %d active; made: %d of %d, %d of %d\n",
                 dim, degree, sc.name, theta, shown, missed, active, made_free, nonpositive, made_within, within);
  ck_assert_msg(shown > 0 && missed > 0 && active > 0, "%dD P%d %s: %d shown free, %d free not shown, %d active", dim,
                degree, sc.name, shown, missed, active);
  // a law that reads P^n's value (the hybrid, generalized-alpha): the body
  // translated into the obstacle at U^n (every P_q^n > 0), then the
  // obstacle moved away by 1.5 max P^n: the bound on P_q(U) is <= 0 at
  // every point, but the law at those P^n is not zero where P_q^n > 3/4
  // max P^n: never shown free
  if (in.scheme->contact_rule().kind != nd::TimeRule::AtEnd) {
    for (auto &u : Un) u = -1;  // (down and sideways by 1: into the plane 0.3 below)
    nd::ContactLaw at_n{&cp, d.theta, nullptr, nullptr, gap_n.data()};
    at_n.P_all(Un.data(), Pn);
    const double most = *std::max_element(Pn.begin(), Pn.end());
    ck_assert(*std::min_element(Pn.begin(), Pn.end()) > 0);
    for (size_t q = 0; q < Q; ++q) gap[q] = gap_n[q] + 1.5 * most;
    nd::ContactLaw moved{&cp, d.theta, in.scheme.get(), &Pn, gap.data()};
    moved.Un = Un.data(), moved.gap_n = gap_n.data();
    U = Un;
    ck_assert(!free_at(moved, U));
    for (int simd = 0; simd <= 1; ++simd) {
      nd::set_simd(simd == 1);
      ck_assert_msg(!moved.certainly_free(U, false), "%s: shown free, P^n active", sc.name);
    }
  }
  // never for a non-finite state, nor without U^n
  nd::ContactLaw law{&cp, d.theta, in.scheme.get(), &Pn, nullptr};
  law.Un = Un.data();
  U = Un;
  ck_assert(!law.certainly_free(U) || free_at(law, U));
  nd::PointReference at_n{Un, {}, {}, {}};
  nd::ContactLaw{&cp, d.theta, nullptr, nullptr, nullptr}.P_all(Un.data(), at_n.P, &at_n.un);
  const double huge = std::numeric_limits<double>::max();  // (every finite u_n within it)
  ck_assert(nd::penetration_within(cp, Un.data(), nullptr, at_n, huge));
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    U = Un;
    U[cp.dofs[cp.dofs.size() / 2]] = bad;  // (off the points' DOFs it changes no P_q)
    ck_assert(!law.certainly_free(U));
    ck_assert(!nd::penetration_within(cp, U.data(), nullptr, at_n, huge));
    for (int simd = 0; simd <= 1; ++simd) {
      nd::set_simd(simd == 1);
      ck_assert(!nd::reach(cp.dofs, U.data(), Un.data()).finite && !nd::reach(cp.dofs, Un.data(), U.data()).finite);
    }
  }
  // nor with a non-finite P^n or gap, which [P]_+ would map to 0
  U = Un;
  const bool before = law.certainly_free(U);
  for (double *slot : {&Pn[Q / 2], &gap_n[Q / 2]}) {
    const double keep = *slot;
    *slot = std::numeric_limits<double>::quiet_NaN();
    law.gap_n = gap_n.data();
    ck_assert(!law.certainly_free(U));
    *slot = keep;
  }
  law.gap_n = nullptr;
  ck_assert(law.certainly_free(U) == before);
  law.Un = nullptr;
  ck_assert(!law.certainly_free(Un));
  nd_problem_destroy(&p);
}

START_TEST(bound_is_sound) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes)
    for (double theta : {1.0, -1.0}) {
      soundness(2, 2, sc, theta);
      soundness(3, 1, sc, theta);
    }
}
END_TEST

std::vector<double> field(nd_problem p, int which) {
  int64_t nodes = 0, dim = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  dim = p->problem.space().dim;
  std::vector<double> f(static_cast<size_t>(nodes * dim));
  ND_OK_OR_FAIL(nd_get_field(p, which, nodes, f.data()));
  return f;
}

// moving: the plane moves away from the block for 15 steps, then rises
// towards it three times as fast, then stays (its gaps change every step:
// the bound's, and the points' reference's, must be the gaps of their
// states: a reference's gaps taken from a later or an earlier state show
// points free that are not, and the trajectories part)
void same_bits(int dim, int degree, const ndtest::SchemeCase &sc, double theta, nd::TangentChoice tangent,
               bool moving = false, const ndtest::Body &body = {}) {
  const std::string what = std::to_string(dim) + "D P" + std::to_string(degree) + " " + sc.name +
                           " Theta=" + std::to_string(theta) + (moving ? " moving plane" : "") + " " +
                           body.name;
  nd_problem on = ndtest::drop_scene(dim, degree, sc, theta, 0.3, 0.1, 1, body);
  nd_problem off = ndtest::drop_scene(dim, degree, sc, theta, 0.3, 0.1, 1, body);
  on->problem.set_tangent(tangent);
  off->problem.set_tangent(tangent);
  off->problem.set_contact_bounds(false);
  // (Theta <= 0 with the automatic gamma0 gains energy at impacts (the method's own (Theta - 1) term, docs/design.md §3b): the energy-balance guard refuses it (test_guards_scale); this test compares bits)
  if (theta <= 0)
    for (nd_problem p : {on, off}) ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY_BALANCE, 0));
  if (moving)  // (the rising plane puts in more energy than the guard allows some schemes; the bits are compared)
    for (nd_problem p : {on, off}) ND_OK_OR_FAIL(nd_problem_set_guard(p, ND_GUARD_ENERGY, 0));
  int contact_steps = 0, unevaluated = 0;
  for (int k = 0; k < 80; ++k) {
    const double passes = scalar(on, ND_STAT_CONTACT_EVALUATIONS);
    if (moving) {
      const double y = k < 15 ? -0.3 - 0.01 * (k + 1) : std::min(-0.45 + 0.03 * (k - 14), -0.1);
      const double plane[3] = {0, dim == 2 ? y : 0, dim == 3 ? y : 0}, up[3] = {0, dim == 2 ? 1.0 : 0, dim == 3 ? 1.0 : 0};
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(on, 1, plane, up));
      ND_OK_OR_FAIL(nd_problem_set_contact_plane(off, 1, plane, up));
    }
    ND_OK_OR_FAIL(nd_step(on));
    ND_OK_OR_FAIL(nd_step(off));
    // a step that evaluated no point: its new state's points left unevaluated
    unevaluated += scalar(on, ND_STAT_CONTACT_EVALUATIONS) == passes;
    // (the hybrid's acceleration is not state: a query computes it, and
    // makes the next step's pass: not asked here)
    for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY, ND_FIELD_ACCELERATION, ND_FIELD_CONTACT_FORCE}) {
      if (which == ND_FIELD_ACCELERATION && sc.scheme == ND_SCHEME_HYBRID) continue;
      const std::vector<double> a = field(on, which), b = field(off, which);
      ck_assert_msg(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0, "%s: step %d field %d differs",
                    what.c_str(), k + 1, which);
    }
    // what the monitors read of the points, evaluated where the step left
    // them unevaluated: the bits of the run without the bound
    for (int key : {ND_ENERGY_MECHANICAL, ND_ENERGY_NITSCHE, ND_ENERGY_AUGMENTED, ND_WORK, ND_CONTACT_FORCE,
                    ND_CONTACT_FORCE_APPLIED, ND_ACTIVE_POINTS, ND_MAX_PENETRATION, ND_WORK_OBSTACLE}) {
      const double a = scalar(on, key), b = scalar(off, key);
      ck_assert_msg(std::memcmp(&a, &b, sizeof a) == 0, "%s: step %d scalar %d: %.17g against %.17g", what.c_str(),
                    k + 1, key, a, b);
    }
    int64_t nq = 0;
    ND_OK_OR_FAIL(nd_problem_get_contact_point_count(on, &nq));
    std::vector<double> la(static_cast<size_t>(nq)), lb(la.size());
    ND_OK_OR_FAIL(nd_get_contact_pressure(on, nq, la.data()));
    ND_OK_OR_FAIL(nd_get_contact_pressure(off, nq, lb.data()));
    ck_assert_msg(std::memcmp(la.data(), lb.data(), la.size() * sizeof(double)) == 0, "%s: step %d pressure",
                  what.c_str(), k + 1);
    ck_assert_double_eq(scalar(on, ND_NEWTON_ITERATIONS), scalar(off, ND_NEWTON_ITERATIONS));
    contact_steps += scalar(on, ND_ACTIVE_POINTS) > 0;
  }
  ck_assert_msg(contact_steps > 0, "%s: no contact", what.c_str());
  // the free flight's steps leave their points unevaluated where the
  // scheme's law reads of P^n only that it is <= 0 (not generalized-alpha)
  // (a curved obstacle's step evaluates its points at the step's own gaps,
  // docs/performance.md "Curved obstacles": none left unevaluated there)
  const bool same_below_zero = sc.scheme != ND_SCHEME_GENERALIZED_ALPHA && !body.bowl;
  ck_assert_msg(same_below_zero ? unevaluated > 0 : unevaluated == 0, "%s: %d steps without a pass over the points",
                what.c_str(), unevaluated);
  const double shown = scalar(on, ND_STAT_CONTACT_BOUNDS);
  if (std::getenv("ND_BOUNDS_TEST_VERBOSE"))
    std::fprintf(stderr, "%s tangent %d: %d contact steps, %g checks shown, passes %g against %g\n", what.c_str(),
                 static_cast<int>(tangent), contact_steps, shown, scalar(on, ND_STAT_CONTACT_EVALUATIONS),
                 scalar(off, ND_STAT_CONTACT_EVALUATIONS));
  ck_assert_msg(shown > 0 && scalar(off, ND_STAT_CONTACT_BOUNDS) == 0, "%s: %g checks shown by the bound",
                what.c_str(), shown);
  ck_assert_msg(scalar(on, ND_STAT_CONTACT_EVALUATIONS) < scalar(off, ND_STAT_CONTACT_EVALUATIONS), "%s",
                what.c_str());
  nd_problem_destroy(&on);
  nd_problem_destroy(&off);
}

START_TEST(same_bits_2d) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes)
    for (double theta : {1.0, -1.0})
      for (int degree : {1, 2}) {
        same_bits(2, degree, sc, theta, nd::TangentChoice::Auto);  // condensed
        same_bits(2, degree, sc, theta, nd::TangentChoice::LowRank);
        same_bits(2, degree, sc, theta, nd::TangentChoice::Auto, true);
      }
}
END_TEST

START_TEST(same_bits_3d) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes)
    for (double theta : {1.0, -1.0})
      same_bits(3, 1, sc, theta, nd::TangentChoice::Auto);  // updated factor (Theta = 1), else condensed
}
END_TEST

// Quadrilaterals and hexahedra (docs/performance.md, "Quadrilaterals and
// hexahedra"): the same bits on Q1 and Q2 rectangles of quadrilaterals, the
// mixed triangle/quadrilateral mesh (examples/meshes/mixed.msh, P1/Q1 and
// P2/Q2), the quadrilateral disk (disk_quad_h4) on a plane and in a
// circular bowl (a curved obstacle), and a box of Q1 hexahedra, for every
// implicit scheme, Theta = 1 and -1; and the bound's soundness there.
START_TEST(same_bits_q) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes)
    for (double theta : {1.0, -1.0}) {
      for (int degree : {1, 2}) {
        same_bits(2, degree, sc, theta, nd::TangentChoice::Auto, false, ndtest::kQuads);
        same_bits(2, degree, sc, theta, nd::TangentChoice::Auto, false, ndtest::kMixed);
      }
      same_bits(2, 2, sc, theta, nd::TangentChoice::LowRank, false, ndtest::kQuads);
      same_bits(2, 1, sc, theta, nd::TangentChoice::Auto, true, ndtest::kQuads);
      same_bits(2, 1, sc, theta, nd::TangentChoice::Auto, false, ndtest::kDisk);
      same_bits(2, 1, sc, theta, nd::TangentChoice::Auto, false, ndtest::kDiskInBowl);
      same_bits(3, 1, sc, theta, nd::TangentChoice::Auto, false, ndtest::kHexahedra);  // updated factor at Theta = 1
    }
}
END_TEST

START_TEST(bound_is_sound_q) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes)
    for (double theta : {1.0, -1.0}) {
      soundness(2, 2, sc, theta, ndtest::kQuads);
      soundness(2, 2, sc, theta, ndtest::kMixed);
      soundness(2, 1, sc, theta, ndtest::kDisk);  // (its trials lift U^n off a plane)
      soundness(3, 1, sc, theta, ndtest::kHexahedra);
    }
}
END_TEST

// A state's queries of the sums over its points (contact force, applied
// force, active points, deepest penetration, Nitsche energy): the first
// keeps its sums with the state's products (Products::queried), the next
// ones read them; they are the bits of a twin problem queried in another
// order, and after a step or nd_problem_set_state the kept sums are not
// read: the values are the twin's that was never queried before.
START_TEST(queried_sums_are_kept_with_their_products) {
  const int keys[5] = {ND_CONTACT_FORCE, ND_CONTACT_FORCE_APPLIED, ND_ACTIVE_POINTS, ND_MAX_PENETRATION,
                       ND_ENERGY_NITSCHE};
  for (int dim : {2, 3}) {
    nd_problem a = ndtest::drop_scene(dim, 1, ndtest::kSchemes[2], 1.0, 0.3);
    nd_problem b = ndtest::drop_scene(dim, 1, ndtest::kSchemes[2], 1.0, 0.3);
    int contact = 0;
    for (int k = 0; k < 60 && contact < 3; ++k) {
      ND_OK_OR_FAIL(nd_step(a));
      ND_OK_OR_FAIL(nd_step(b));
      // a is queried at every step, b at every other one: sums kept from an
      // earlier state (a's from the step before, b's from two before) would differ
      double va[5], vb[5], again[5];
      for (int j = 0; j < 5; ++j) va[j] = scalar(a, keys[j]);  // the force first: kept without the Nitsche sum
      if (k % 2) continue;
      for (int j = 4; j >= 0; --j) vb[j] = scalar(b, keys[j]);  // the Nitsche energy first: kept with it
      for (int j = 0; j < 5; ++j) again[j] = scalar(a, keys[j]);  // read from the kept sums
      ck_assert_msg(std::memcmp(va, vb, sizeof va) == 0 && std::memcmp(va, again, sizeof va) == 0,
                    "%dD step %d: the queries differ", dim, k + 1);
      const nd::Products &pa = a->problem.current_products();
      ck_assert(pa.pass != 0 && pa.queried_pass == pa.pass && pa.queried_nitsche);
      contact += va[2] > 0;
    }
    ck_assert_msg(contact == 3, "%dD: no contact", dim);
    // a new state set over the queried one: its own sums, a's (queried before) as b's
    int64_t nodes = 0;
    ND_OK_OR_FAIL(nd_problem_get_node_count(a, &nodes));
    std::vector<double> u(static_cast<size_t>(nodes * dim));
    ND_OK_OR_FAIL(nd_get_field(a, ND_FIELD_DISPLACEMENT, nodes, u.data()));
    for (int64_t i = 0; i < nodes; ++i) u[i * dim + dim - 1] -= 0.01;  // deeper into the plane
    const double before = scalar(a, ND_CONTACT_FORCE);
    for (nd_problem p : {a, b}) ND_OK_OR_FAIL(nd_problem_set_state(p, nodes, u.data(), nullptr));
    for (int j = 0; j < 5; ++j) {
      const double x = scalar(a, keys[j]), y = scalar(b, keys[j]);
      ck_assert_msg(std::memcmp(&x, &y, sizeof x) == 0, "%dD: after set_state, key %d %.17g against %.17g", dim,
                    keys[j], x, y);
    }
    ck_assert(scalar(a, ND_CONTACT_FORCE) > before);
    nd_problem_destroy(&a);
    nd_problem_destroy(&b);
  }
}
END_TEST

// The block of the drops falling without turning, at `speed`, gamma0 small
// (nu_q = sum |a_qk| + gamma_q sum |s_qk| near 1: the bound's reach, where
// the points move together, near the distance they move)
nd_problem translating_block(int dim, const ndtest::SchemeCase &sc, double gap, double speed) {
  nd_problem p = ndtest::block_scene(dim, 1, sc, 1.0, gap);
  ND_OK_OR_FAIL(nd_problem_set_nitsche(p, 1.0, 1e-4));
  int64_t nodes = 0;
  ND_OK_OR_FAIL(nd_problem_get_node_count(p, &nodes));
  std::vector<double> v0(static_cast<size_t>(nodes * dim), 0.0);
  for (int64_t i = 0; i < nodes; ++i) v0[i * dim + dim - 1] = -speed;
  ND_OK_OR_FAIL(nd_problem_set_initial_state(p, nodes, nullptr, v0.data()));
  return p;
}

// A state whose points a Newmark step left unevaluated, then stepped into
// contact by the generalized-alpha scheme, whose contact term reads P^n's
// value (not only its sign): the step evaluates them first, the bits of
// the run without the bound, 2D and 3D. The block falls fast and without
// turning: the last state before the impact is one left unevaluated (the
// bound from an earlier state held there), and the impact is deep enough
// for that P^n to count.
START_TEST(scheme_change_after_unevaluated_points) {
  for (int dim : {2, 3}) {
    const double speed = 4;
    // the first step in contact, for the first gap whose state before it
    // was left unevaluated (where the bound held since the last evaluation)
    int impact = -1;
    bool before_unevaluated = false;
    double gap = 0.3;
    for (; gap < 0.34 && !before_unevaluated; gap += 0.004) {
      nd_problem probe = translating_block(dim, ndtest::kSchemes[2], gap, speed);
      impact = -1;
      for (int k = 0; k < 40 && impact < 0; ++k) {
        before_unevaluated = probe->problem.current_products().points.ref != nullptr;
        ND_OK_OR_FAIL(nd_step(probe));
        if (scalar(probe, ND_ACTIVE_POINTS) > 0) impact = k;
      }
      nd_problem_destroy(&probe);
    }
    gap -= 0.004;
    ck_assert_msg(impact > 0 && before_unevaluated, "%dD: no impact after a state left unevaluated", dim);
    nd_problem on = translating_block(dim, ndtest::kSchemes[2], gap, speed);
    nd_problem off = translating_block(dim, ndtest::kSchemes[2], gap, speed);
    off->problem.set_contact_bounds(false);
    const double rho = 0.8;
    for (int k = 0; k < impact + 10; ++k) {
      if (k == impact)
        for (nd_problem p : {on, off}) ND_OK_OR_FAIL(nd_problem_set_scheme(p, ND_SCHEME_GENERALIZED_ALPHA, &rho));
      ND_OK_OR_FAIL(nd_step(on));
      ND_OK_OR_FAIL(nd_step(off));
      for (int which : {ND_FIELD_DISPLACEMENT, ND_FIELD_VELOCITY}) {
        const std::vector<double> a = field(on, which), b = field(off, which);
        ck_assert_msg(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0, "%dD: step %d differs", dim,
                      k + 1);
      }
      if (k == impact) ck_assert(scalar(on, ND_CONTACT_FORCE_APPLIED) > 0);
    }
    nd_problem_destroy(&on);
    nd_problem_destroy(&off);
  }
}
END_TEST

}  // namespace

int main(void) {
  Suite *s = suite_create("contact_bounds");
  TCase *tc = tcase_create("bounds");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, laws_are_monotone);
  tcase_add_test(tc, bound_is_sound);
  tcase_add_test(tc, same_bits_2d);
  tcase_add_test(tc, same_bits_3d);
  tcase_add_test(tc, same_bits_q);
  tcase_add_test(tc, bound_is_sound_q);
  tcase_add_test(tc, scheme_change_after_unevaluated_points);
  tcase_add_test(tc, queried_sums_are_kept_with_their_products);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
