// The Nitsche contact term (DESIGN §2-3) as a function of U:
//   P_q(U) = p_q.U - g_q,  p_q = a_q - gamma_q s_q,  b_q = a_q - Theta gamma_q s_q
//   N(U)   = sum_q (w_q/gamma_q) phi_q(P_q(U)) b_q
// with phi_q(P) = [P]_+ for the theta-scheme and Newmark, and the hybrid
// scheme's Phi_q(P; P_q^n) (eq. (17)). The tangent is
//   N'(U)  = sum_q (w_q/gamma_q) phi_q'(P_q(U)) b_q p_q^T.
#pragma once
#include <vector>

#include "assembly/contact.hpp"
#include "linalg/csr.hpp"

namespace nd {

struct ContactLaw {
  const ContactPoints *cp = nullptr;
  double theta = 1;                    // Nitsche's Theta
  const std::vector<double> *Pn = nullptr;  // P_q(U^n): set for the hybrid scheme

  double P(size_t q, const double *U) const {
    return cp->a[q].dot(U) - cp->gamma[q] * cp->s[q].dot(U) - cp->gap[q];
  }
  // value and slope of phi_q at P; H(0) = 1/2 in the hybrid switch (paper),
  // the slope of [.]_+ at 0 is taken as 0.
  void law(size_t q, double P, double &value, double &slope) const;
  // y += kappa N(U); active[q] = (slope != 0) if active is given
  void add_force(const double *U, double kappa, double *y, std::vector<char> *active) const;
  // T += kappa N'(U) (T has the operator pattern, which holds every a_q, s_q pair)
  void add_tangent(const double *U, double kappa, Csr &T) const;
};

}  // namespace nd
