#include "monitor/energies.hpp"

#include <algorithm>

#include "common/error.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"
#include "solve/contact_law.hpp"

namespace nd {

double mechanical_energy(const Discretization &d, const State &s, const Products &p) {
  if (p.of == d.id) return 0.5 * p.kinetic + 0.5 * p.strain;
  // a rank holds its rows only: the other rows' sums come in a collective
  // pass, which a query on one rank cannot make (set-up makes it)
  if (d.rows_split)
    fail(ND_ERR_STATE, "the energy of a state that was not set up: with the operators split over the ranks it is "
                       "computed by nd_problem_setup, collective (call it on every rank first)");
  const Products sums = product_sums(d, s);
  return 0.5 * sums.kinetic + 0.5 * sums.strain;
}

namespace {
// a pass that needs every point's value: a distributed state's are completed first
const std::vector<double> &whole(const std::vector<double> &v, const PointValues &of) {
  if (of.partial) fail(ND_ERR_INTERNAL, "the contact points of a distributed state read before they were gathered");
  return v;
}
// point q's terms added to t, from its P_q, u_n - g0 and applied phi_q;
// with `nitsche` also the Nitsche energy's, which reads s_q.U. The law at the
// state (phi(P_q), the force w_q phi/gamma_q; active where its slope is not
// 0); the energy's contact part -phi^2/(2 gamma_q) is the frictionless law's
// potential ([P]_+^2/2: a law with another one brings its own term here)
// (PP: the law's positive_part, asked once per pass: a loop apiece; phi
// null: the state has applied none, phi(P_q) stands for it)
// With friction (cp.m > 1, P holding the tangential values after the
// normal ones) a frictional point's tangential part joins the Nitsche
// energy: (gamma_q |ts_q.U|^2 - |P_t|^2/gamma_q)/2, P_t at the state's slip
// reference, inside the disk there (docs/design.md §10.2).
template <bool PP>
inline __attribute__((always_inline)) void add_point(const ContactPoints &cp, const PointLaw &law, size_t q,
                                                     const std::vector<double> &Pv, double un, const double *phi,
                                                     const double *U, bool nitsche, PointSums &t) {
  const double P = Pv[q];
  double Pp, slope;
  law_at(law, PP, P, Pp, slope);
  if (nitsche) {
    const double sn = cp.s[q].dot(U);
    t.nitsche += 0.5 * cp.w[q] * (cp.gamma[q] * sn * sn - Pp * Pp / cp.gamma[q]);
    if (cp.m > 1 && cp.friction[q]) {
      const size_t mt = static_cast<size_t>(cp.m - 1);
      double e = 0;
      for (size_t k = 0; k < mt; ++k) {
        const double st = cp.ts[q * mt + k].dot(U), pt = Pv[cp.size() + q * mt + k];
        e += cp.gamma[q] * st * st - pt * pt / cp.gamma[q];
      }
      t.nitsche += 0.5 * cp.w[q] * e;
    }
  }
  if (Pp != 0) t.force += cp.w[q] * Pp / cp.gamma[q];
  t.active += slope != 0;  // (+0 or 1: the count's bits either way)
  t.force_applied += cp.w[q] * (phi ? phi[q] : Pp) / cp.gamma[q];
  t.penetration = std::max(t.penetration, un);
}
// the sums of a state: the step's when it left them, else over every point
// in order (phi_q = phi(P_q) before a step: the applied force is the force)
PointSums state_sums(const Discretization &d, const State &s, const Products &p, bool nitsche) {
  if (p.of == d.id && p.points.summed) return p.points.sums;
  // the sums an earlier query made at these products (the same pass, the same bits)
  const bool kept = p.of == d.id && p.pass != 0;
  if (kept && p.queried_pass == p.pass && (p.queried_nitsche || !nitsche)) return p.queried;
  PointValues scratch;
  const PointValues &v = state_points(d, s, p, scratch);
  const std::vector<double> &P = whole(v.P, v), &un = whole(v.un, v);
  PointSums t;
  const PointLaw &law = *d.contact_law;
  const double *phi = s.phi.empty() ? nullptr : s.phi.data();
  auto pass = [&](auto pp) {
    for (size_t q = 0; q < d.contact.size(); ++q)
      add_point<decltype(pp)::value>(d.contact, law, q, P, un[q], phi, s.U.data(), nitsche, t);
  };
  if (law.traits().positive_part) pass(std::true_type{});
  else pass(std::false_type{});
  if (kept) p.queried = t, p.queried_pass = p.pass, p.queried_nitsche = nitsche;
  return t;
}
}  // namespace

void sum_points(const Discretization &d, State &s, Products &p, const std::vector<double> &dW) {
  const ContactPoints &cp = d.contact;
  PointValues &v = p.points;
  PointSums t;
  double W = 0;
  const Share *share = cp.share.get();
  const RowSet own = own_rows(share);  // each rank its own points, added rank after rank
  for (int64_t k = 0, m = own.size(static_cast<int64_t>(cp.size())); k < m; ++k) {
    const int64_t q = own[k];
    add_point<false>(cp, *d.contact_law, static_cast<size_t>(q), v.P, v.un[q], s.phi.data(), s.U.data(), true, t);
    W += dW[q];
  }
  if (share) {
    double sums[6] = {t.nitsche, t.force, t.force_applied, t.active, W, t.penetration};
    gather(*share, {}, sums, 6, 1);
    t = PointSums{sums[0], sums[1], sums[2], sums[3], sums[5]};
    W = sums[4];
  }
  v.sums = t;
  v.summed = true;
  s.W_obstacle += W;
}

double nitsche_energy(const Discretization &d, const State &s, const Products &p) {
  return state_sums(d, s, p, true).nitsche;
}

PointSums region_sums(const Discretization &d, const State &s, const Products &p, int region) {
  PointValues scratch;
  const PointValues &v = state_points(d, s, p, scratch);
  const std::vector<double> &P = whole(v.P, v), &un = whole(v.un, v);
  PointSums t;
  const double *phi = s.phi.empty() ? nullptr : s.phi.data();
  for (size_t q = 0; q < d.contact.size(); ++q)
    if (d.contact.region[q] == region) add_point<false>(d.contact, *d.contact_law, q, P, un[q], phi, s.U.data(), true, t);
  return t;
}

std::vector<double> contact_pressure(const Discretization &d, const State &s, const Products &p) {
  PointValues scratch;
  const PointValues &points = state_points(d, s, p, scratch);
  const std::vector<double> &Pq = whole(points.P, points);
  std::vector<double> lam(d.contact.size());
  for (size_t q = 0; q < lam.size(); ++q) {
    double phi, slope;
    law_at(*d.contact_law, Pq[q], phi, slope);
    lam[q] = phi != 0 ? -phi / d.contact.gamma[q] : 0.0;  // (+0 where free)
  }
  return lam;
}

namespace {
// a state whose points its step left unevaluated (the bound's reference),
// shown to have every P_q <= 0 by the bound from that reference: its
// contact forces and active points are zero (+0, the evaluated sums' bits:
// no term is added), so a query evaluates no point: evaluating them all
// would cost a large part of a predicted step per query
bool shown_free(const Discretization &d, const State &s, const Products &p) {
  const PointValues &v = p.points;
  return p.of == d.id && v.ref && d.contact_law->traits().zero_when_free &&
         nonpositive_within(d.contact, s.U.data(), s.gap.empty() ? nullptr : s.gap.data(), *v.ref);
}
}  // namespace

double contact_force(const Discretization &d, const State &s, const Products &p) {
  return shown_free(d, s, p) ? 0.0 : state_sums(d, s, p, false).force;
}

double contact_force_applied(const Discretization &d, const State &s, const Products &p) {
  return shown_free(d, s, p) ? 0.0 : state_sums(d, s, p, false).force_applied;
}

int64_t active_points(const Discretization &d, const State &s, const Products &p) {
  return shown_free(d, s, p) ? 0 : static_cast<int64_t>(state_sums(d, s, p, false).active);
}

double max_penetration(const Discretization &d, const State &s, const Products &p) {
  return state_sums(d, s, p, false).penetration;
}

}  // namespace nd
