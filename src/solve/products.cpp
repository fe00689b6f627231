#include "solve/products.hpp"

#include <algorithm>
#include <atomic>
#include <limits>
#include <type_traits>

#include "common/error.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"
#include "solve/clamped_coupling.hpp"
#include "solve/contact_law.hpp"

namespace nd {

ContactLaw state_contact_law(const Discretization &d, const State &s) {
  ContactLaw law{&d.contact, d.theta, nullptr, nullptr, s.gap.empty() ? nullptr : s.gap.data()};
  law.point_law = d.contact_law.get();
  if (!s.slip.empty()) law.gap_t = s.slip.data();
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
void products_of_state(const Discretization &d, const State &s, Products &p) {
  static std::atomic<uint64_t> passes{0};
  p.of = 0;  // stays 0 if anything below throws
  p.pass = ++passes;  // (a query's sums from an earlier pass no longer hold)
  if (d.rows_split && d.rows) products_pass<true, true>(d, s, p);
  else products_pass<true>(d, s, p);
  add_clamped_energy(d, s, p.kinetic, p.strain);  // (prescribed motion: the whole body's)
}
}  // namespace

void compute_products_bounded(const Discretization &d, const State &s, Products &p,
                              std::shared_ptr<const PointReference> ref) {
  products_of_state(d, s, p);
  p.points = PointValues{};
  p.points.ref = std::move(ref);
  p.of = d.id;
}

std::shared_ptr<const PointReference> point_reference(const Discretization &d, const State &s, const Products &p,
                                                      double penetration_limit) {
  if (p.points.ref) return p.points.ref;
  const size_t nq = d.contact.size();
  if (p.points.partial || p.points.P.size() != nq || p.points.un.size() != nq || s.U.empty()) return nullptr;
  auto ref = std::make_shared<PointReference>();
  ref->U = s.U, ref->P = p.points.P, ref->un = p.points.un, ref->gap = s.gap;
  set_reference_reach(d.contact, *ref, penetration_limit, &d.penetration_length);  // (one pass here, none at each check from it)
  return ref;
}

void compute_products(const Discretization &d, const State &s, Products &p, PointValues *known,
                      const HeldPoints *held) {
  products_of_state(d, s, p);
  if (known && known->P.size() == d.contact.size() * static_cast<size_t>(d.contact.m) &&
      known->un.size() == d.contact.size()) {
    std::swap(p.points, *known);  // (known keeps the products' memory: no allocation)
  } else if (held && !d.contact.a.empty()) {  // the rank's points, evaluated here (no message)
    ContactLaw law = state_contact_law(d, s);
    PointValues &v = p.points;
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
    law.P_all(s.U.data(), p.points.P, &p.points.un);
  }
  p.of = d.id;
}

bool products_current(const Discretization &d, const State &s, const Products &p, bool with_acceleration) {
  return p.of == d.id && (!with_acceleration || !s.A_valid || p.MA.size() == p.MU.size());
}

const Products &products_of(const Discretization &d, const State &s, const Products &p, Products &scratch,
                            bool with_acceleration) {
  if (products_current(d, s, p, with_acceleration)) return p;
  compute_products(d, s, scratch);  // (the same pass, into the caller's scratch)
  return scratch;
}

const PointValues &state_points(const Discretization &d, const State &s, const Products &p, PointValues &scratch,
                                Counters *counters) {
  if (p.of == d.id && !p.points.ref) return p.points;
  count(counters, &Counters::contact_evaluations);
  ContactLaw law = state_contact_law(d, s);
  law.local = true;  // a query: every point here, no message
  law.P_all(s.U.data(), scratch.P, &scratch.un);
  return scratch;
}

Products product_sums(const Discretization &d, const State &s) {
  Products sums;
  products_pass<false>(d, s, sums);
  add_clamped_energy(d, s, sums.kinetic, sums.strain);
  return sums;
}

}  // namespace nd
