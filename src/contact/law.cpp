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

}  // namespace nd
