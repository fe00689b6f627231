#include "solve/contact_law.hpp"

namespace nd {

void ContactLaw::law(size_t q, double P, double &value, double &slope) const {
  if (!Pn) {
    value = P > 0 ? P : 0;
    slope = P > 0 ? 1 : 0;
    return;
  }
  // Phi = H(P^n) [(P^n + P)/2]_+ + H(-P^n) ([P^n]_+ + [P]_+)/2
  const double pn = (*Pn)[q];
  const double h_pos = pn > 0 ? 1 : pn < 0 ? 0 : 0.5, h_neg = 1 - h_pos;
  const double mid = 0.5 * (pn + P);
  value = h_pos * (mid > 0 ? mid : 0) + h_neg * 0.5 * ((pn > 0 ? pn : 0) + (P > 0 ? P : 0));
  slope = h_pos * (mid > 0 ? 0.5 : 0) + h_neg * (P > 0 ? 0.5 : 0);
}

void ContactLaw::add_force(const double *U, double kappa, double *y, std::vector<char> *active) const {
  if (active) active->assign(cp->size(), 0);
  for (size_t q = 0; q < cp->size(); ++q) {
    double value, slope;
    law(q, P(q, U), value, slope);
    if (active) (*active)[q] = slope != 0;
    if (value == 0) continue;
    const double f = kappa * cp->w[q] / cp->gamma[q] * value, tg = theta * cp->gamma[q];
    const SparseRow &a = cp->a[q], &s = cp->s[q];
    for (size_t k = 0; k < a.idx.size(); ++k) y[a.idx[k]] += f * (a.val[k] - tg * s.val[k]);
  }
}

void ContactLaw::add_tangent(const double *U, double kappa, Csr &T) const {
  for (size_t q = 0; q < cp->size(); ++q) {
    double value, slope;
    law(q, P(q, U), value, slope);
    if (slope == 0) continue;
    const double f = kappa * cp->w[q] / cp->gamma[q] * slope, g = cp->gamma[q];
    const SparseRow &a = cp->a[q], &s = cp->s[q];  // same index lists
    for (size_t i = 0; i < a.idx.size(); ++i) {
      const double b = a.val[i] - theta * g * s.val[i];
      for (size_t j = 0; j < a.idx.size(); ++j)
        T.val[T.find(a.idx[i], a.idx[j])] += f * b * (a.val[j] - g * s.val[j]);
    }
  }
}

}  // namespace nd
