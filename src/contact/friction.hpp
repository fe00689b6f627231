// Friction through Nitsche's method (docs/design.md §10.2): at a contact
// point the normal value P_n and the tangential values P_t (m - 1 = dim - 1
// of them, in the point's tangent basis), with
//   phi_n = [P_n]_+ over the step by the scheme's rule (as frictionless),
//   phi_t = Pi_{B(0, r)}(Y_t),  r = radius(phi_n)  (Coulomb F phi_n, Tresca gamma s),
// Y_t = P_t at the end of the step (the theta-scheme, Newmark, explicit
// steps and the hybrid scheme: dissipative, §10.2), or at generalized-
// alpha's shifted point. (Coulomb's vanish wherever the normal ones do, r =
// 0 there; Tresca's need not: the passes ask every value, ContactLaw::law_m.)
// A frictional law is one file: its radius, and a line in laws.cpp.
#pragma once
#include "contact/law.hpp"

namespace nd {

class FrictionLaw : public PointLaw {
 public:
  FrictionLaw(int dim, double parameter, bool symmetric);
  // The radius r of the disk Y_t is projected on, and dr/dphi_n, from the
  // normal value phi_n the step applies and the point's gamma
  virtual void radius(double phi_n, double gamma, double &r, double &dr) const = 0;
  double parameter() const { return parameter_; }
  // the normal part: [x]_+
  void at(double x, double &value, double &slope) const override;
  void over_step_m(const TimeRule &r, size_t q, double gamma, int m, const double *P, const double *Pn,
                   double *value, double *J) const override;

 private:
  double parameter_;
};

// Where a rule takes the tangential values (Y_t = c P_t + (1 - c) P_t^n):
// c = 1 except generalized-alpha's shifted point, c = 1 - alpha_f
inline double tangential_weight(const TimeRule &r) { return r.kind == TimeRule::Shifted ? 1 - r.af : 1.0; }

}  // namespace nd
