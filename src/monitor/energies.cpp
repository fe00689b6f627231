#include "monitor/energies.hpp"

#include <algorithm>

#include "solve/contact_law.hpp"

namespace nd {

ContactLaw state_contact_law(const Discretization &d, const State &s) {
  return ContactLaw{&d.contact, d.theta, nullptr, nullptr, s.gap.empty() ? nullptr : s.gap.data()};
}

double mechanical_energy(const Discretization &d, const State &s) {
  // M and K share one pattern (lumped M included): one pass over it
  const Csr &M = d.M, &K = d.K;
  count(d.counters, &Counters::spmv);
  double kinetic = 0, strain = 0;
  for (int64_t i = 0; i < K.n; ++i) {
    double mv = 0, ku = 0;
    for (int64_t k = K.ptr[i]; k < K.ptr[i + 1]; ++k) {
      mv += M.val[k] * s.V[K.col[k]];
      ku += K.val[k] * s.U[K.col[k]];
    }
    kinetic += s.V[i] * mv;
    strain += s.U[i] * ku;
  }
  return 0.5 * kinetic + 0.5 * strain;
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
