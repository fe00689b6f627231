#include "monitor/guards.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <limits>

#include "assembly/coercivity.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "monitor/energies.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"

namespace nd {
namespace {

constexpr double kInitialPenetration = 1e-10;  // of h_K: round-off

// What a moving obstacle closed of each point's gap over the step, (g^n_q -
// g^{n+1}_q)_+, read from the two states' gaps (before null: it did not
// move; a pair's gaps change only where it re-pairs: none either). A scheme
// that applies the law before the step's end (generalized-alpha at its
// shifted point) answers that approach in the steps after: a resting block
// that a plane reaches sank by it before any force acted, with no energy put
// in yet, where the guard's limit is 0 (stability suite, steel block,
// generalized-alpha: a false alarm).
struct Approach {
  const double *before = nullptr, *after = nullptr;
  double at(size_t q) const { return before ? std::max(0.0, before[q] - after[q]) : 0.0; }
};
Approach obstacle_approach(const Discretization &d, const State &old, const State &next) {
  const std::vector<double> &before = old.gap.empty() ? d.contact.gap : old.gap,
                            &after = next.gap.empty() ? d.contact.gap : next.gap;
  if (&before == &after || !next.pairing.empty() || before.size() != after.size()) return {};
  return {before.data(), after.data()};
}

// the deepest point relative to its cell size: (penetration / h, index),
// (0, 0) where no point penetrates (the guards' limits are positive: a
// point off the obstacle costs no division); of a distributed state's
// points, the deepest of the rank's own (the rank that has the deepest
// fails with it, the others with it failing there: guard_step runs inside
// the step's agreement)
// (length: the lengths the penetration is measured in, h_K by default;
// allowed: a depth each point may have beyond them)
std::pair<double, size_t> deepest(const Discretization &d, const State &s, const Products &p,
                                  const std::vector<double> *length = nullptr, const Approach &allowed = {}) {
  const std::vector<double> &len = length && !length->empty() ? *length : d.contact.h;
  PointValues scratch;
  const PointValues &points = state_points(d, s, p, scratch, d.counters);
  const std::vector<double> &un = points.un;
  std::pair<double, size_t> worst{0, 0};
  auto visit = [&](size_t q) {
    const double depth = un[q] - allowed.at(q);
    if (!(depth > 0)) return;
    const double r = depth / len[q];
    if (r > worst.first) worst = {r, q};
  };
  if (points.partial) {
    const Share &own = *d.contact.share;
    for (const int64_t *q = own.own_begin(); q != own.own_end(); ++q) visit(static_cast<size_t>(*q));
  } else {
    for (size_t q = 0; q < un.size(); ++q) visit(q);
  }
  return worst;
}

std::string point(const Discretization &d, size_t q) {
  const int dim = static_cast<int>(d.contact.x.size() / d.contact.size());
  std::string at = "(";
  for (int k = 0; k < dim; ++k) at += (k ? ", " : "") + num(d.contact.x[q * dim + k]);
  return at + ")";
}

// An energy less what loads, obstacle, supports and re-linearisations put
// in, plus what damping and friction took out: the balance's form
double ledger(const State &s, double energy) {
  return energy - s.W - s.W_obstacle - s.W_prescribed - s.W_geometry + s.D_damping + s.D_friction;
}

// The balance of Theorem 2.8 at a state: E_Theta less what loads, obstacle,
// supports and re-linearisations put in, plus what damping and friction
// took out. R from the step's sums, else by a pass over the points' s_q
// (their P_q the step's); NaN for a distributed state's points, and, unless
// `settle`, for a state its step left unevaluated (shown contact-free: no
// pass over the points for it)
double balance_of(const Discretization &d, const State &s, const Products &p, double E, bool settle = false) {
  double R = 0;
  if (d.theta != 0 && d.contact.size() > 0) {
    const PointValues &v = p.points;
    if (p.of == d.id && v.summed) R = v.sums.nitsche;
    else if (s.partial || v.partial || (v.ref && !settle)) return std::numeric_limits<double>::quiet_NaN();
    else R = nitsche_energy(d, s, p);
  }
  return ledger(s, E - d.theta * R);
}
// The guard's balance: balance_of with min(E, E_Theta) for E_Theta when
// Theta < 0 (-Theta R >= 0 there: the Nitsche term, no energy of the body;
// docs/design.md §3b), balance_of itself otherwise (out of contact, where
// R >= 0, that is min(E, E_Theta) too). NaN where balance_of is.
double guard_balance_of(const Discretization &d, const State &s, const Products &p, double E) {
  const double whole = balance_of(d, s, p, E, true);
  if (!(d.theta < 0) || std::isnan(whole)) return whole;
  return std::min(whole, ledger(s, E));
}
// (Theta/2) sum_q w_q gamma_q ((s_q.U)^2 + sum_k (ts_qk.U)^2 at frictional
// points): U'KU/2 less this is U'K_Theta U/2 (one pass over the points' s rows)
double theta_term(const Discretization &d, const State &s) {
  const ContactPoints &cp = d.contact;
  if (d.theta == 0) return 0;
  double sum = 0;
  const size_t mt = static_cast<size_t>(cp.m - 1);
  for (size_t q = 0; q < cp.size(); ++q) {
    const double sn = cp.s[q].dot(s.U.data());
    double e = sn * sn;
    if (mt > 0 && cp.friction[q])
      for (size_t k = 0; k < mt; ++k) {
        const double st = cp.ts[q * mt + k].dot(s.U.data());
        e += st * st;
      }
    sum += cp.w[q] * cp.gamma[q] * e;
  }
  return 0.5 * d.theta * sum;
}

// no point in contact at s: shown contact-free, or evaluated with none active
bool contact_free(const Discretization &d, const Products &p) {
  if (d.contact.size() == 0) return true;
  const PointValues &v = p.points;
  return p.of == d.id && (v.ref || (v.summed && v.sums.active == 0));
}

// The step's contact term of Theorem 2.8, (Theta - 1) sum_q (w_q/gamma_q)
// phi_q a_q.(U^{n+1} - U^n), phi_q the contact terms the steps applied; NaN
// where the state's points are not all at hand (a distributed state's)
double step_exchange(const Discretization &d, const State &old, const State &next) {
  if (d.theta == 1 || next.phi.empty()) return 0;
  if (old.partial || next.partial || next.phi.size() != d.contact.size()) return std::numeric_limits<double>::quiet_NaN();
  const ContactPoints &cp = d.contact;
  double sum = 0;
  // the trapezoid of the two steps' applied terms (the new one alone where
  // old has none): a measure of the contact work, for the message only
  const bool mean = old.phi.size() != cp.size();
  for (size_t q = 0; q < cp.size(); ++q) {
    const double phi = mean ? next.phi[q] : 0.5 * (next.phi[q] + old.phi[q]);
    if (phi != 0) sum += cp.w[q] / cp.gamma[q] * phi * (cp.a[q].dot(next.U.data()) - cp.a[q].dot(old.U.data()));
  }
  return (d.theta - 1) * sum;
}

const char *scheme_advice(const Discretization &d) {
  return d.theta < 0 ? "Theta = 1 (the hybrid scheme with Theta = 1 never gains), a smaller gamma0 or a smaller step"
                     : "a smaller step, a smaller gamma0, or the hybrid scheme with Theta = 1, which never gains";
}

}  // namespace

double penetration_limit(const Discretization &d, const Guards &g, const GuardState &s) {
  if (!(g.penetration > 0) || !(s.budget > 0) || !(d.stiffness_volume > 0)) return 0;
  return g.penetration * std::sqrt(2 * s.budget / d.stiffness_volume);
}

void guard_initial_state(const Discretization &d, const Guards &g, State &s, const Products &p) {
  if (g.initial_penetration && d.contact.size() > 0) {
    const auto [r, q] = deepest(d, s, p);
    if (r > kInitialPenetration)
      fail(ND_ERR_PENETRATION, "the initial state penetrates the obstacle by " + num(r * d.contact.h[q]) +
                                   " at contact point " + std::to_string(q) + " " + point(d, q) +
                                   " (cell size " + num(d.contact.h[q]) +
                                   "); move the body or the obstacle, or allow it with the initial-penetration guard");
  }
  s.guard = GuardState{};
  s.guard.E0 = mechanical_energy(d, s, p);
  s.guard.budget = s.guard.E0;
  s.guard.E_top = s.guard.E0;
  // the balance at t^0 (R by a pass over the points unless the state's own
  // made it; a distributed state's: the first evaluated step starts it)
  s.guard.balance = s.guard.balance_low = guard_balance_of(d, s, p, s.guard.E0);
  if (!std::isfinite(s.guard.E0)) fail(ND_ERR_NONFINITE_STATE, "the initial energy is not finite");
}

namespace {
// The energy-balance guard (docs/design.md §3b): L at next against its
// lowest value so far, relative to the energy in motion; updates next.guard
void guard_balance(const Discretization &d, const Guards &g, const State &old, State &next, const Products &p,
                   double E) {
  GuardState &gs = next.guard;
  const double scale = std::max(gs.budget, gs.E_top);
  gs.E_top = std::max(gs.E_top, E);
  const double dX = step_exchange(d, old, next);
  if (std::isnan(dX)) {  // (a distributed state: not checked)
    gs.balance = gs.balance_low = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  gs.exchange += dX;
  const bool free = contact_free(d, p);
  double L;
  if (free) {
    // out of contact: the whole balance, at the first state out of contact
    // (R from a pass over the points where the step left them unevaluated).
    // Not after it: a step out of contact is linear, and the set-up's checks
    // (coercive K_Theta, theta >= 1/2, tau below tau_c) keep the scheme from
    // gaining there; its own energy need not be E_Theta (generalized-alpha's
    // high modes: E oscillates while they decay)
    if (!gs.in_contact && !std::isnan(gs.balance_low)) return;
    L = guard_balance_of(d, next, p, E);
    if (std::isnan(L)) return;
  } else {
    // in contact: E_Theta = E - Theta R, R = 1/2 sum_q w_q (gamma_q (s_q U)^2
    // - [P_q]_+^2/gamma_q), its contact terms counted only where they lower
    // the balance below the one with E. For Theta > 0 without the energy the
    // penalty holds, (Theta/2) sum_q (w_q/gamma_q) [P_q]_+^2: 1/2 V'MV +
    // 1/2 U'K_Theta U, below both. Dropping a term >= 0 keeps the hybrid
    // scheme's (Theta = 1) below its non-increasing balance, and a scheme
    // applying the law elsewhere (generalized-alpha at Y) does not hold that
    // energy at U^{n+1}. For Theta <= 0, min(E, E_Theta), in and out of
    // contact (guard_balance_of): -Theta R >= 0 is no energy of the body (in
    // contact the Nitsche term -(Theta/2) sum_q w_q gamma_q (s_q U)^2
    // outgrows the penalty's), and counting it made the guard refuse sound
    // runs: with gamma0 E = 1e4 it rose to 268 times the energy in motion in
    // 3 steps while E stayed at E^0 + W (the disk, tau = 10), and at tau =
    // 1.25e-4 (the bar, Theta = -1, 10^4 steps in contact) it lifted a gain
    // of E of 4.7 % past the 5 %; counted in L_low out of contact, it hid
    // gains of E in contact (the bar, Theta = -1, gamma0 E = 1e4, tau = 10:
    // E up 12 % at step 2, refused at step 15 by the factor guard at 1.9
    // times E^0). Where the penalty holds more than that term, E_Theta < E:
    // the balance dips.
    if (next.partial) return;
    if (d.theta > 0) {
      L = ledger(next, E - theta_term(d, next));
    } else {
      L = guard_balance_of(d, next, p, E);
    }
    if (std::isnan(L)) return;
  }
  gs.in_contact = !free;
  if (std::isnan(gs.balance_low)) {
    if (free) gs.balance = gs.balance_low = L, gs.exchange = 0;
    return;
  }
  const double gain = L - gs.balance_low;
  if (gain > g.balance * scale) {
    // the cause: with Theta != 1, the contact term of the impact (since the
    // last contact-free state), if it put in most of the gain
    const bool method = d.theta != 1 && gs.exchange > 0.5 * gain;
    fail(ND_ERR_ENERGY_GROWTH,
         "the step to t = " + num(next.t) +
             " raises the energy balance E_Theta - W - W_obstacle - W_prescribed - W_geometry + D_damping + "
             "D_friction (Theorem 2.8) by " + num(gain) + " above its lowest value out of contact, more than " +
             num(g.balance) + " times the energy in motion " + num(scale) + ": " +
             (method ? "Theta = " + num(d.theta) + " gains energy at impacts (the contact term (Theta - 1) sum_q "
                       "(w_q/gamma_q) [P_q]_+ a_q.V put in " + num(gs.exchange) + " since the impact began)"
                     : d.theta < 0 ? "Theta = " + num(d.theta) + " gains energy at impacts"
                                   : std::string("the time scheme gains energy in contact")) +
             "; use " + scheme_advice(d) + "; the step was not taken");
  }
  gs.balance = L;
  // the reference: the lowest balance where no energy is held by the contact
  // (with Theta != 1 the balance dips while the penalty holds energy)
  if (free) gs.balance_low = std::min(gs.balance_low, L), gs.exchange = 0;
}
}  // namespace

void guard_step(const Discretization &d, const Guards &g, const State &old, State &next, const Products &p,
                bool balance) {
  GuardState &gs = next.guard;
  gs = old.guard;
  // a moving obstacle puts energy in too, and so do moving supports
  // (prescribed motion). Not W_geometry (curved obstacles' and pairs'
  // re-linearisations): it is no work from outside but the geometric
  // approximation's, small in a sound run (1 % of W on the rotating circle),
  // and in a blow-up it grows with the energy, so that a budget counting it
  // let a pair of disks reach 1.9e17 times its energy unrefused
  double put_in = gs.E0 + next.W + next.W_obstacle;
  if (next.W_prescribed != 0) put_in += next.W_prescribed;
  gs.budget = std::max(gs.budget, put_in);
  // (a state whose points the step did not evaluate: first from their
  // reference, without a pass)
  const PointReference *ref = p.of == d.id ? p.points.ref.get() : nullptr;
  if (g.penetration > 0 && d.contact.size() > 0) {
    // (of the points' lengths min(h_K, L/8); 0: no energy put in, no point may sink beyond the
    // obstacle's approach)
    const double limit = penetration_limit(d, g, gs);
    const std::vector<double> &length = d.penetration_length;
    if (!(ref && limit > 0 &&
          penetration_within(d.contact, next.U.data(), next.gap.empty() ? nullptr : next.gap.data(), *ref, limit,
                             &length))) {
      auto [r, q] = deepest(d, next, p, &length);
      // (a point may sink by what the obstacle's own approach closed over the
      // step besides: looked at only past the limit, no second pass else)
      const Approach approach = r > limit ? obstacle_approach(d, old, next) : Approach{};
      if (approach.before) std::tie(r, q) = deepest(d, next, p, &length, approach);
      if (r > limit) {
        const double strain = limit / g.penetration;
        const std::string scale =
            length[q] < d.contact.h[q]
                ? "1/" + num(kPenetrationBodyDivisor) + " of the body's length " +
                      num(length[q] * kPenetrationBodyDivisor) + " across its contact region"
                : "the cell size " + num(d.contact.h[q]);
        fail(ND_ERR_PENETRATION,
             "the step to t = " + num(next.t) + " sinks contact point " + std::to_string(q) + " " + point(d, q) + " " +
                 num(r * length[q]) + " into the obstacle" +
                 (approach.at(q) > 0 ? " beyond the obstacle's approach over the step, " + num(approach.at(q)) + ","
                                     : std::string(",")) +
                 " more than " + num(g.penetration) + " times " + num(strain * length[q]) + " (the strain " +
                 num(strain) + " that the energy put in, " + num(gs.budget) + ", gives the body, times " + scale +
                 "): the penalty is too weak (lower gamma0, or gamma0 = 0 for an automatic one) or "
                 "the step too large; the step was not taken");
      }
    }
  }
  const bool balanced = balance && g.balance > 0;
  if (!(g.energy > 0) && !balanced) return;
  const double E = mechanical_energy(d, next, p);
  if (!std::isfinite(E))
    fail(ND_ERR_NONFINITE_STATE, "the energy after the step to t = " + num(next.t) +
                                     " is not finite; the step was not taken");
  if (balanced) guard_balance(d, g, old, next, p, E);
  if (!(g.energy > 0)) return;
  // with damping the energy it dissipated counts with E: E + D <= f (E^0 + W + W_obstacle)
  if (E + next.D_damping > g.energy * gs.budget) {
    // a gamma0 above the bound makes K_Theta indefinite (the free motion
    // grows): then the message says which gamma0 is safe
    const bool above_bound = d.theta > 0 && d.theta * d.gamma0 > d.gamma0_limit;
    const std::string safe = above_bound ? safe_gamma0(d.theta, d.gamma0_limit) : std::string();
    fail(ND_ERR_ENERGY_GROWTH,
         "the step to t = " + num(next.t) + " raises the mechanical energy to " + num(E) +
             (next.D_damping != 0 ? " (plus " + num(next.D_damping) + " dissipated by the damping)" : std::string()) +
             ", more than " +
             num(g.energy) + " times the energy put in (E^0 + W + W_obstacle + W_prescribed = " + num(gs.budget) +
             "): the scheme is unstable here. Lower the time step (explicit schemes: below the critical step), "
             "lower gamma0 (gamma0 = 0 chooses a safe one), or use a dissipative or the hybrid scheme" +
             (safe.empty() ? std::string()
                           : ". With Theta = " + num(d.theta) + " and gamma0 = " + num(d.gamma0) + ", " + safe) +
             "; the step was not taken");
  }
}

}  // namespace nd
