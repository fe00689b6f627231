#include "contact/law.hpp"

#include "assembly/contact.hpp"
#include "linalg/csr.hpp"

namespace nd {

void PointLaw::over_step(const TimeRule &r, double P, double Pn, double &value, double &slope) const {
  apply_rule(r, P, Pn, [this](double x, double &v, double &s) { at(x, v, s); }, value, slope);
}

void PointLaw::add_residual(const ContactPoints &cp, double theta, size_t q, double f, double value,
                            double *y) const {
  add_b(cp, theta, q, f * value, y);
}

void PointLaw::add_tangent(const ContactPoints &cp, double theta, size_t q, double f, double slope, Csr &T,
                           std::vector<double> &b, std::vector<double> &p) const {
  add_point_tangent(cp, theta, q, f * slope, T, b, p);
}

void add_b(const ContactPoints &cp, double theta, size_t q, double f, double *y) {
  const SparseRow &a = cp.a[q], &s = cp.s[q];
  const double tg = theta * cp.gamma[q];
  for (size_t k = 0; k < a.idx.size(); ++k) y[a.idx[k]] += f * (a.val[k] - tg * s.val[k]);
}

void add_point_tangent(const ContactPoints &cp, double theta, size_t q, double f, Csr &T, std::vector<double> &b,
                       std::vector<double> &p) {
  const double g = cp.gamma[q];
  const SparseRow &a = cp.a[q], &s = cp.s[q];  // same index lists
  b.resize(a.idx.size());
  p.resize(a.idx.size());
  for (size_t i = 0; i < a.idx.size(); ++i) {
    b[i] = a.val[i] - theta * g * s.val[i];
    p[i] = a.val[i] - g * s.val[i];
  }
  T.add_outer(a.idx, b.data(), p.data(), f);
}

}  // namespace nd
