#include "monitor/guards.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "assembly/coercivity.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "monitor/energies.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"

namespace nd {
namespace {

constexpr double kInitialPenetration = 1e-10;  // of h_K: round-off
// the deepest point relative to its cell size: (penetration / h, index),
// (0, 0) where no point penetrates (the guards' limits are positive: a
// point off the obstacle costs no division); of a distributed state's
// points, the deepest of the rank's own (the rank that has the deepest
// fails with it, the others with it failing there: guard_step runs inside
// the step's agreement)
std::pair<double, size_t> deepest(const Discretization &d, const State &s) {
  PointValues scratch;
  const PointValues &points = state_points(d, s, scratch, d.counters);
  const std::vector<double> &un = points.un;
  std::pair<double, size_t> worst{0, 0};
  auto visit = [&](size_t q) {
    if (!(un[q] > 0)) return;
    const double r = un[q] / d.contact.h[q];
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

}  // namespace

void guard_initial_state(const Discretization &d, const Guards &g, State &s) {
  if (g.initial_penetration && d.contact.size() > 0) {
    const auto [r, q] = deepest(d, s);
    if (r > kInitialPenetration)
      fail(ND_ERR_PENETRATION, "the initial state penetrates the obstacle by " + num(r * d.contact.h[q]) +
                                   " at contact point " + std::to_string(q) + " " + point(d, q) +
                                   " (cell size " + num(d.contact.h[q]) +
                                   "); move the body or the obstacle, or allow it with the initial-penetration guard");
  }
  s.guard = GuardState{};
  s.guard.E0 = mechanical_energy(d, s);
  s.guard.budget = s.guard.E0;
  if (!std::isfinite(s.guard.E0)) fail(ND_ERR_NONFINITE_STATE, "the initial energy is not finite");
}

void guard_step(const Discretization &d, const Guards &g, const State &old, State &next) {
  GuardState &gs = next.guard;
  gs = old.guard;
  // a moving obstacle puts energy in too, and so do moving supports (prescribed motion)
  double put_in = gs.E0 + next.W + next.W_obstacle;
  if (next.W_prescribed != 0) put_in += next.W_prescribed;
  if (next.W_geometry != 0) put_in += next.W_geometry;  // (curved obstacles' re-linearisations)
  gs.budget = std::max(gs.budget, put_in);
  // (a state whose points the step did not evaluate: first from their
  // reference, without a pass)
  const PointReference *ref = next.products.of == d.id ? next.products.points.ref.get() : nullptr;
  if (g.penetration > 0 && d.contact.size() > 0 &&
      !(ref && penetration_within(d.contact, next.U.data(), next.gap.empty() ? nullptr : next.gap.data(), *ref,
                                  g.penetration))) {
    const auto [r, q] = deepest(d, next);
    if (r > g.penetration)
      fail(ND_ERR_PENETRATION, "the step to t = " + num(next.t) + " sinks contact point " + std::to_string(q) + " " +
                                   point(d, q) + " " + num(r * d.contact.h[q]) + " into the obstacle, more than " +
                                   num(g.penetration) + " of its cell size " + num(d.contact.h[q]) +
                                   ": the penalty is too weak (lower gamma0, or gamma0 = 0 for an automatic one) or "
                                   "the step too large; the step was not taken");
  }
  if (!(g.energy > 0)) return;
  const double E = mechanical_energy(d, next);
  if (!std::isfinite(E))
    fail(ND_ERR_NONFINITE_STATE, "the energy after the step to t = " + num(next.t) +
                                     " is not finite; the step was not taken");
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
