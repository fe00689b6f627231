#include "contact/law.hpp"

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

void PointLaw::over_step_m(const TimeRule &r, size_t, double, int m, const double *P, const double *Pn,
                           double *value, double *J) const {
  for (int k = 0; k < m * m; ++k) J[k] = 0;
  for (int k = 1; k < m; ++k) value[k] = 0;
  over_step(r, P[0], Pn ? Pn[0] : 0.0, value[0], J[0]);
}

void add_blocks(const ContactPoints &cp, double theta, size_t q, double f, const double *value, double *y) {
  const double tg = theta * cp.gamma[q];
  for (int k = 0; k < cp.m; ++k) {
    if (value[k] == 0) continue;
    const SparseRow &a = cp.a_row(q, k), &s = cp.s_row(q, k);  // (same index lists)
    const double c = f * value[k];
    for (size_t i = 0; i < a.idx.size(); ++i) y[a.idx[i]] += c * (a.val[i] - tg * s.val[i]);
  }
}

void add_block_tangent(const ContactPoints &cp, double theta, size_t q, double f, const double *J, Csr &T,
                       std::vector<double> &b, std::vector<double> &p) {
  const int m = cp.m;
  const double g = cp.gamma[q];
  const size_t len = cp.a[q].idx.size();
  b.resize(len);
  p.resize(len);
  for (int k = 0; k < m; ++k)
    for (int l = 0; l < m; ++l) {
      if (J[k * m + l] == 0) continue;
      const SparseRow &ak = cp.a_row(q, k), &sk = cp.s_row(q, k), &al = cp.a_row(q, l), &sl = cp.s_row(q, l);
      for (size_t i = 0; i < len; ++i) {
        b[i] = ak.val[i] - theta * g * sk.val[i];
        p[i] = al.val[i] - g * sl.val[i];
      }
      T.add_outer(cp.a[q].idx, b.data(), p.data(), f * J[k * m + l]);
    }
}

}  // namespace nd
