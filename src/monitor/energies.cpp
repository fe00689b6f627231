#include "monitor/energies.hpp"

#include <algorithm>

#include "solve/contact_law.hpp"

namespace nd {

ContactLaw state_contact_law(const Discretization &d, const State &s) {
  return ContactLaw{&d.contact, d.theta, nullptr, nullptr, s.gap.empty() ? nullptr : s.gap.data()};
}

namespace {

// The pass behind compute_products and mechanical_energy: each product
// summed in the order of Csr::multiply, V.MV and U.KU row by row, so that
// the energy has the same bits whether or not the products are stored
template <bool store>
void products_pass(const Discretization &d, const State &s, Products &p) {
  const Csr &M = d.M, &K = d.K;
  require_same_pattern(K, M);
  count(d.counters, &Counters::spmv);
  const bool acc = store && s.A_valid;
  if (store) {
    p.MU.resize(s.U.size());
    p.MV.resize(s.U.size());
    p.KU.resize(s.U.size());
    if (acc) p.MA.resize(s.U.size());
    else p.MA.clear();
  }
  const double *m = M.val.data(), *k = K.val.data(), *U = s.U.data(), *V = s.V.data(), *A = s.A.data();
  const int64_t *col = K.col.data(), *ptr = K.ptr.data();
  double kinetic = 0, strain = 0;
  for (int64_t i = 0; i < K.n; ++i) {
    double mu = 0, mv = 0, ma = 0, ku = 0;
    for (int64_t j = ptr[i]; j < ptr[i + 1]; ++j) {
      const int64_t c = col[j];
      mv += m[j] * V[c];
      ku += k[j] * U[c];
      if (store) mu += m[j] * U[c];
      if (acc) ma += m[j] * A[c];
    }
    kinetic += V[i] * mv;
    strain += U[i] * ku;
    if (store) {
      p.MU[i] = mu, p.MV[i] = mv, p.KU[i] = ku;
      if (acc) p.MA[i] = ma;
    }
  }
  p.kinetic = kinetic;
  p.strain = strain;
}

}  // namespace

void compute_products(const Discretization &d, State &s) {
  s.products.of = 0;  // stays 0 if anything below throws
  products_pass<true>(d, s, s.products);
  const ContactLaw law = state_contact_law(d, s);
  s.products.P.resize(d.contact.size());
  if (!s.products.P.empty()) count(d.counters, &Counters::contact_evaluations);
  for (size_t q = 0; q < s.products.P.size(); ++q) s.products.P[q] = law.P(q, s.U.data());
  s.products.of = d.id;
}

const Products &products_of(const Discretization &d, const State &s, Products &scratch) {
  if (s.products.of == d.id) return s.products;
  State copy;  // the same pass as compute_products, on a state we may not change
  copy.U = s.U, copy.V = s.V, copy.A = s.A, copy.A_valid = s.A_valid, copy.gap = s.gap;
  compute_products(d, copy);
  scratch = std::move(copy.products);
  return scratch;
}

double mechanical_energy(const Discretization &d, const State &s) {
  if (s.products.of == d.id) return 0.5 * s.products.kinetic + 0.5 * s.products.strain;
  Products sums;
  products_pass<false>(d, s, sums);
  return 0.5 * sums.kinetic + 0.5 * sums.strain;
}

double nitsche_energy(const Discretization &d, const State &s) {
  const ContactPoints &cp = d.contact;
  const ContactLaw law = state_contact_law(d, s);
  double R = 0;
  for (size_t q = 0; q < cp.size(); ++q) {
    const double P = law.P(q, s.U.data()), Pp = P > 0 ? P : 0;
    const double sn = cp.s[q].dot(s.U.data());
    R += 0.5 * cp.w[q] * (cp.gamma[q] * sn * sn - Pp * Pp / cp.gamma[q]);
  }
  return R;
}

std::vector<double> contact_pressure(const Discretization &d, const State &s) {
  const ContactLaw law = state_contact_law(d, s);
  std::vector<double> lam(d.contact.size());
  for (size_t q = 0; q < lam.size(); ++q) {
    const double P = law.P(q, s.U.data());
    lam[q] = P > 0 ? -P / d.contact.gamma[q] : 0.0;
  }
  return lam;
}

double contact_force(const Discretization &d, const State &s) {
  const ContactLaw law = state_contact_law(d, s);
  double F = 0;
  for (size_t q = 0; q < d.contact.size(); ++q) {
    const double P = law.P(q, s.U.data());
    if (P > 0) F += d.contact.w[q] * P / d.contact.gamma[q];
  }
  return F;
}

int64_t active_points(const Discretization &d, const State &s) {
  const ContactLaw law = state_contact_law(d, s);
  int64_t k = 0;
  for (size_t q = 0; q < d.contact.size(); ++q) k += law.P(q, s.U.data()) > 0;
  return k;
}

double max_penetration(const Discretization &d, const State &s) {
  const ContactLaw law = state_contact_law(d, s);
  double m = 0;
  for (size_t q = 0; q < d.contact.size(); ++q) m = std::max(m, d.contact.a[q].dot(s.U.data()) - law.g(q));
  return m;
}

}  // namespace nd
