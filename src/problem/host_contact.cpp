#include "problem/host_contact.hpp"

#include <algorithm>

#include "monitor/energies.hpp"
#include "problem/exports.hpp"
#include "solve/contact_law.hpp"
#include "solve/products.hpp"

namespace nd {

namespace {
// A state that is the problem's at t^n except for U: its gaps (the obstacle
// at t^n) and slip references (friction, docs/design.md §10.2), no products
// (so every monitor evaluates its points at U)
State at_host_U(Problem &p, const Discretization &d, const double *U) {
  const State &s = p.current_state();
  State t;
  t.t = s.t;
  t.U.assign(U, U + d.dofs.n_free);
  t.V.assign(static_cast<size_t>(d.dofs.n_free), 0.0);
  t.gap = s.gap;
  t.slip = s.slip;
  return t;
}
// the law [P]_+ at t's gaps, every point evaluated here (a query, not a step)
ContactLaw query_law(const Discretization &d, const State &t) {
  ContactLaw law = state_contact_law(d, t);
  law.local = true;
  return law;
}
// The law of a host call: query_law's, and with U_old the scheme's time rule
// over the step, P^n = P_q(U_old) at the same gaps (the pieces a step's law
// holds, ContactLaw::scheme and Pn, kept alive here)
struct HostLaw {
  std::unique_ptr<TimeScheme> scheme;
  std::vector<double> Pn;
  ContactLaw law;
  HostLaw(Problem &p, const Discretization &d, const State &t, const double *U_old) : law(query_law(d, t)) {
    if (!U_old) return;
    const Definition &def = p.definition();
    require_complete(def.given & kScheme ? 0u : unsigned(kScheme));
    scheme = make_scheme(def.scheme, def.scheme_params);
    law.P_all(U_old, Pn);
    law.scheme = scheme.get();
    law.Pn = &Pn;
  }
};
}  // namespace

void host_contact_residual(Problem &p, const double *U, const double *U_old, double *r) {
  const Discretization &d = whole_operators(p, "the contact term");
  const State t = at_host_U(p, d, U);
  const HostLaw h(p, d, t, U_old);
  std::fill(r, r + d.dofs.n_free, 0.0);
  h.law.add_force(t.U.data(), 1.0, r, nullptr);
}

Csr host_contact_tangent(Problem &p, const double *U, const double *U_old) {
  const Discretization &d = whole_operators(p, "the contact term");
  const ContactPoints &cp = d.contact;
  // every (i, j) of a point's index list (s_q shares a_q's): all that
  // add_point_tangent writes, at any U
  std::vector<std::vector<int64_t>> rows(static_cast<size_t>(d.dofs.n_free));
  for (size_t q = 0; q < cp.size(); ++q)
    for (int64_t i : cp.a[q].idx) rows[i].insert(rows[i].end(), cp.a[q].idx.begin(), cp.a[q].idx.end());
  Csr T = csr_from_rows(std::move(rows));
  if (!U) return T;
  const State t = at_host_U(p, d, U);
  HostLaw(p, d, t, U_old).law.add_tangent(t.U.data(), 1.0, T);
  return T;
}

void host_contact_values(Problem &p, const double *U, int count, double *values) {
  const Discretization &d = whole_operators(p, "the contact values");
  const State t = at_host_U(p, d, U);
  const Products none;  // (a host's U: no products, each value from a pass over the points)
  const double all[kHostContactValues] = {contact_force(d, t, none), static_cast<double>(active_points(d, t, none)),
                                          nitsche_energy(d, t, none), max_penetration(d, t, none)};
  std::copy_n(all, std::min(count, kHostContactValues), values);
}

}  // namespace nd
