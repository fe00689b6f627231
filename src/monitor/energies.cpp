#include "monitor/energies.hpp"

#include <algorithm>
#include <atomic>
#include <limits>
#include <type_traits>

#include "parallel/share.hpp"
#include "solve/contact_law.hpp"

namespace nd {

ContactLaw state_contact_law(const Discretization &d, const State &s) {
  ContactLaw law{&d.contact, d.theta, nullptr, nullptr, s.gap.empty() ? nullptr : s.gap.data()};
  law.point_law = d.contact_law.get();
  return law;
}

namespace {

// The pass behind compute_products and mechanical_energy: each product
// summed in one fixed order (even and odd entries of a row apart, then
// added), V.MV and U.KU row by row, so that the energy has the same bits
// whether or not the products are stored. With several ranks (d.rows) the
// stored products are each rank's rows, and V.MV, U.KU the ranks' sums added
// rank after rank (the same bits on every rank; not those of one process,
// nor of the unstored pass, which sums every row on each rank). The rows are
// gathered to every rank where the solves read whole right-hand sides; with
// split operators they stay on their rank (Products::rows).
// Two products share one SSE2 multiply and add: (mu, mv) += m (U_c, V_c) and
// (ma, ku) += (m, k) (A_c, U_c), from interleaved copies of U, V, A (each
// lane sums in the same order as a scalar sum would).
typedef double Pair __attribute__((vector_size(16)));

// The same pass over K and M by nodes (linalg/node_blocks.hpp: the same
// bits), where they have that form: one process, every row (the stored pass
// with several ranks keeps to the CSR pattern).
template <bool store, bool acc>
void node_pass(const NodeBlocks &b, const State &s, Products &p) {
  const size_t n = s.U.size();
  if (store) {
    p.rows = nullptr;
    p.n = static_cast<int64_t>(n);
    p.MU.resize(n), p.MV.resize(n), p.KU.resize(n);
    if (acc) p.MA.resize(n);
    else p.MA.clear();
  }
  const double *U = s.U.data(), *V = s.V.data();
  double *MU = p.MU.data(), *MV = p.MV.data(), *KU = p.KU.data(), *MA = p.MA.data();
  auto keep = [=](int64_t i, double ku, double mu, double mv, double ma) __attribute__((always_inline)) {
    if (store) {
      MU[i] = mu, MV[i] = mv, KU[i] = ku;
      if (acc) MA[i] = ma;
    }
  };
  double energy[2];  // V.MV and U.KU, summed in the pass
  for_node_rows<true, acc>(&b, U, V, s.A.data(), keep, energy);
  p.kinetic = energy[0];
  p.strain = energy[1];
}

// local: with split rows, the copies at the columns the rank's rows read
// (their places, Discretization::own_columns), else n long
template <bool store, bool local = false>
void products_pass(const Discretization &d, const State &s, Products &p) {
  const Csr &M = d.M, &K = d.K;
  require_same_pattern(K, M);
  count(d.counters, &Counters::spmv);
  const size_t n = s.U.size();
  const bool acc = store && s.A_valid;
  if (const NodeBlocks *b = d.node_blocks.get(); b && !local && !(store && d.rows))
    return acc ? node_pass<store, store>(*b, s, p) : node_pass<store, false>(*b, s, p);
  // with several ranks (store only): each its own rows, gathered below
  // unless the operators are split; then the copies hold the columns those
  // rows read (Discretization::own_columns), not n
  const Share *share = store ? d.rows.get() : nullptr;
  const bool kept = share && d.rows_split;
  const RowSet rows = own_rows(share);
  static_assert(store || !local, "the columns' places are the stored pass's");
  const Discretization::OwnColumns *own = local ? &d.own_columns() : nullptr;
  const size_t n_cols = own ? own->cols.size() : n;
  std::vector<Pair> x1(n_cols), x2(store ? n_cols : 0);  // store: (U, V) and (A, U); energy only: (V, U)
  for (size_t l = 0; l < n_cols; ++l) {
    const size_t c = own ? static_cast<size_t>(own->cols[l]) : l;
    if (store) {
      x1[l] = Pair{s.U[c], s.V[c]};
      x2[l] = Pair{acc ? s.A[c] : 0.0, s.U[c]};
    } else {
      x1[l] = Pair{s.V[c], s.U[c]};
    }
  }
  if (store) {
    const size_t held = kept ? static_cast<size_t>(share->own_count()) : n;
    p.rows = kept ? d.rows : nullptr;
    p.n = static_cast<int64_t>(n);
    p.MU.resize(held);
    p.MV.resize(held);
    p.KU.resize(held);
    if (acc) p.MA.resize(held);
    else p.MA.clear();
  }
  const double *m = M.val.data(), *k = K.val.data(), *U = s.U.data(), *V = s.V.data();
  // an entry's column among the copies: its own, or (local) its place
  const int64_t *col = K.col.data();
  const int32_t *place = local ? own->place.data() : nullptr;
  auto column = [&](int64_t j) -> int64_t {
    if constexpr (local) return place[j];
    return col[j];
  };
  const Pair *X1 = x1.data(), *X2 = x2.data();
  double kinetic = 0, strain = 0;
  K.for_rows(rows, [&](int64_t r, int64_t i, int64_t j, int64_t e) __attribute__((always_inline)) {
    // even and odd entries in separate sums: two chains of dependent adds
    // instead of one (the add's latency, not the memory, bounded this loop)
    Pair a = {0, 0}, b = {0, 0}, a1 = {0, 0}, b1 = {0, 0};
    for (; j + 1 < e; j += 2) {
      const int64_t c = column(j), c1 = column(j + 1);
      if (store) {
        a += Pair{m[j], m[j]} * X1[c];
        b += Pair{m[j], k[j]} * X2[c];
        a1 += Pair{m[j + 1], m[j + 1]} * X1[c1];
        b1 += Pair{m[j + 1], k[j + 1]} * X2[c1];
      } else {
        a += Pair{m[j], k[j]} * X1[c];
        a1 += Pair{m[j + 1], k[j + 1]} * X1[c1];
      }
    }
    if (j < e) {
      const int64_t c = column(j);
      if (store) {
        a += Pair{m[j], m[j]} * X1[c];
        b += Pair{m[j], k[j]} * X2[c];
      } else {
        a += Pair{m[j], k[j]} * X1[c];
      }
    }
    a += a1;
    b += b1;
    const double mv = store ? a[1] : a[0], ku = store ? b[1] : a[1];
    kinetic += V[i] * mv;
    strain += U[i] * ku;
    if (store) {
      const int64_t o = kept ? r : i;  // the entry of row i
      p.MU[o] = a[0], p.MV[o] = mv, p.KU[o] = ku;
      if (acc) p.MA[o] = b[0];
    }
  });
  if (share) {
    double sums[2] = {kinetic, strain};
    std::vector<double *> fields;
    if (!kept) fields = {p.MU.data(), p.MV.data(), p.KU.data()};
    if (acc && !kept) fields.push_back(p.MA.data());
    gather(*share, fields, sums, 2);
    kinetic = sums[0], strain = sums[1];
  }
  p.kinetic = kinetic;
  p.strain = strain;
}

}  // namespace

namespace {
void products_of_state(const Discretization &d, State &s) {
  static std::atomic<uint64_t> passes{0};
  s.products.of = 0;  // stays 0 if anything below throws
  s.products.pass = ++passes;  // (a query's sums from an earlier pass no longer hold)
  if (d.rows_split && d.rows) products_pass<true, true>(d, s, s.products);
  else products_pass<true>(d, s, s.products);
}
}  // namespace

void compute_products_bounded(const Discretization &d, State &s, std::shared_ptr<const PointReference> ref) {
  products_of_state(d, s);
  s.products.points = PointValues{};
  s.products.points.ref = std::move(ref);
  s.products.of = d.id;
}

std::shared_ptr<const PointReference> point_reference(const Discretization &d, const State &s, const Products &p,
                                                      double penetration_limit) {
  if (p.points.ref) return p.points.ref;
  const size_t nq = d.contact.size();
  if (p.points.partial || p.points.P.size() != nq || p.points.un.size() != nq || s.U.empty()) return nullptr;
  auto ref = std::make_shared<PointReference>();
  ref->U = s.U, ref->P = p.points.P, ref->un = p.points.un, ref->gap = s.gap;
  set_reference_reach(d.contact, *ref, penetration_limit);  // (one pass here, none at each check from it)
  return ref;
}

void compute_products(const Discretization &d, State &s, PointValues *known, const HeldPoints *held) {
  products_of_state(d, s);
  if (known && known->P.size() == d.contact.size() && known->un.size() == d.contact.size()) {
    std::swap(s.products.points, *known);  // (known keeps the products' memory: no allocation)
  } else if (held && !d.contact.a.empty()) {  // the rank's points, evaluated here (no message)
    ContactLaw law = state_contact_law(d, s);
    PointValues &v = s.products.points;
    v = PointValues{};
    v.P.assign(d.contact.size(), std::numeric_limits<double>::quiet_NaN());
    v.un = v.P;
    int64_t evaluated = 0;
    for (int64_t q : held->points) {
      ++evaluated;
      double sa, ss;
      law.dots(static_cast<size_t>(q), s.U.data(), sa, ss);
      v.un[q] = sa - law.g(q);
      v.P[q] = sa - d.contact.gamma[q] * ss - law.g(q);  // (P_q's bits: ContactLaw::P)
    }
    v.partial = true;
    count(d.counters, &Counters::contact_evaluations);
    count(d.counters, &Counters::point_evaluations, static_cast<int64_t>(d.contact.size()));
    count(d.counters, &Counters::own_point_evaluations, evaluated);
  } else {
    ContactLaw law = state_contact_law(d, s);
    law.counters = d.counters;
    // (a partial state without held points is right at every point's DOFs on every rank: no message)
    law.local = s.partial;
    law.P_all(s.U.data(), s.products.points.P, &s.products.points.un);
  }
  s.products.of = d.id;
}

bool products_current(const Discretization &d, const State &s, bool with_acceleration) {
  const Products &p = s.products;
  return p.of == d.id && (!with_acceleration || !s.A_valid || p.MA.size() == p.MU.size());
}

const Products &products_of(const Discretization &d, const State &s, Products &scratch, bool with_acceleration) {
  if (products_current(d, s, with_acceleration)) return s.products;
  State copy;  // the same pass as compute_products, on a state we may not change
  copy.U = s.U, copy.V = s.V, copy.A = s.A, copy.A_valid = s.A_valid, copy.gap = s.gap, copy.partial = s.partial;
  compute_products(d, copy);
  scratch = std::move(copy.products);
  return scratch;
}

double mechanical_energy(const Discretization &d, const State &s) {
  if (s.products.of == d.id) return 0.5 * s.products.kinetic + 0.5 * s.products.strain;
  // a rank holds its rows only: the other rows' sums come in a collective
  // pass, which a query on one rank cannot make (set-up makes it)
  if (d.rows_split)
    fail(ND_ERR_STATE, "the energy of a state that was not set up: with the operators split over the ranks it is "
                       "computed by nd_problem_setup, collective (call it on every rank first)");
  Products sums;
  products_pass<false>(d, s, sums);
  return 0.5 * sums.kinetic + 0.5 * sums.strain;
}

const PointValues &state_points(const Discretization &d, const State &s, PointValues &scratch, Counters *counters) {
  if (s.products.of == d.id && !s.products.points.ref) return s.products.points;
  count(counters, &Counters::contact_evaluations);
  ContactLaw law = state_contact_law(d, s);
  law.local = true;  // a query: every point here, no message
  law.P_all(s.U.data(), scratch.P, &scratch.un);
  return scratch;
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
template <bool PP>
inline __attribute__((always_inline)) void add_point(const ContactPoints &cp, const PointLaw &law, size_t q, double P,
                                                     double un, const double *phi, const double *U, bool nitsche,
                                                     PointSums &t) {
  double Pp, slope;
  law_at(law, PP, P, Pp, slope);
  if (nitsche) {
    const double sn = cp.s[q].dot(U);
    t.nitsche += 0.5 * cp.w[q] * (cp.gamma[q] * sn * sn - Pp * Pp / cp.gamma[q]);
  }
  if (Pp != 0) t.force += cp.w[q] * Pp / cp.gamma[q];
  t.active += slope != 0;  // (+0 or 1: the count's bits either way)
  t.force_applied += cp.w[q] * (phi ? phi[q] : Pp) / cp.gamma[q];
  t.penetration = std::max(t.penetration, un);
}
// the sums of a state: the step's when it left them, else over every point
// in order (phi_q = phi(P_q) before a step: the applied force is the force)
PointSums state_sums(const Discretization &d, const State &s, bool nitsche) {
  const Products &p = s.products;
  if (p.of == d.id && p.points.summed) return p.points.sums;
  // the sums an earlier query made at these products (the same pass, the same bits)
  const bool kept = p.of == d.id && p.pass != 0;
  if (kept && p.queried_pass == p.pass && (p.queried_nitsche || !nitsche)) return p.queried;
  PointValues scratch;
  const PointValues &v = state_points(d, s, scratch);
  const std::vector<double> &P = whole(v.P, v), &un = whole(v.un, v);
  PointSums t;
  const PointLaw &law = *d.contact_law;
  const double *phi = s.phi.empty() ? nullptr : s.phi.data();
  auto pass = [&](auto pp) {
    for (size_t q = 0; q < P.size(); ++q)
      add_point<decltype(pp)::value>(d.contact, law, q, P[q], un[q], phi, s.U.data(), nitsche, t);
  };
  if (law.traits().positive_part) pass(std::true_type{});
  else pass(std::false_type{});
  if (kept) p.queried = t, p.queried_pass = p.pass, p.queried_nitsche = nitsche;
  return t;
}
}  // namespace

void sum_points(const Discretization &d, State &s, const std::vector<double> &dW) {
  const ContactPoints &cp = d.contact;
  PointValues &v = s.products.points;
  PointSums t;
  double W = 0;
  const Share *share = cp.share.get();
  const RowSet own = own_rows(share);  // each rank its own points, added rank after rank
  for (int64_t k = 0, m = own.size(static_cast<int64_t>(cp.size())); k < m; ++k) {
    const int64_t q = own[k];
    add_point<false>(cp, *d.contact_law, static_cast<size_t>(q), v.P[q], v.un[q], s.phi.data(), s.U.data(), true, t);
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

double nitsche_energy(const Discretization &d, const State &s) { return state_sums(d, s, true).nitsche; }

std::vector<double> contact_pressure(const Discretization &d, const State &s) {
  PointValues scratch;
  const PointValues &points = state_points(d, s, scratch);
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
bool shown_free(const Discretization &d, const State &s) {
  const PointValues &v = s.products.points;
  return s.products.of == d.id && v.ref && d.contact_law->traits().zero_when_free &&
         nonpositive_within(d.contact, s.U.data(), s.gap.empty() ? nullptr : s.gap.data(), *v.ref);
}
}  // namespace

double contact_force(const Discretization &d, const State &s) {
  return shown_free(d, s) ? 0.0 : state_sums(d, s, false).force;
}

double contact_force_applied(const Discretization &d, const State &s) {
  return shown_free(d, s) ? 0.0 : state_sums(d, s, false).force_applied;
}

int64_t active_points(const Discretization &d, const State &s) {
  return shown_free(d, s) ? 0 : static_cast<int64_t>(state_sums(d, s, false).active);
}

double max_penetration(const Discretization &d, const State &s) { return state_sums(d, s, false).penetration; }

}  // namespace nd
