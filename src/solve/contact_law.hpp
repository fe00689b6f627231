// The Nitsche contact term (DESIGN §2-3) as a function of U:
//   P_q(U) = p_q.U - g_q,  p_q = a_q - gamma_q s_q,  b_q = a_q - Theta gamma_q s_q
//   N(U)   = sum_q (w_q/gamma_q) phi(P_q(U), P_q^n) b_q
// where phi is the time scheme's contact term ([P]_+ for the theta-scheme and
// Newmark, the hybrid scheme's Phi, generalized-alpha's shifted point), or
// [P]_+ when no scheme is given (energies, pressure, explicit steps). The
// tangent is N'(U) = sum_q (w_q/gamma_q) phi'(P_q(U), P_q^n) b_q p_q^T.
#pragma once
#include <vector>

#include "assembly/contact.hpp"
#include "common/counters.hpp"
#include "linalg/csr.hpp"
#include "parallel/share.hpp"
#include "time/scheme.hpp"

namespace nd {

// p_q . v, p_q = a_q - gamma_q s_q (P_q(v) without its gap)
double p_dot(const ContactPoints &cp, size_t q, const double *v);
// appends c p_q = c (a_q - gamma_q s_q): a_q's indices to idx, the values to val
void append_p(const ContactPoints &cp, size_t q, double c, std::vector<int64_t> &idx, std::vector<double> &val);
// y += f b_q, b_q = a_q - Theta gamma_q s_q
void add_b(const ContactPoints &cp, double theta, size_t q, double f, double *y);
// T += f b_q p_q^T (T has the operator pattern)
void add_point_tangent(const ContactPoints &cp, double theta, size_t q, double f, Csr &T);

struct ContactLaw {
  const ContactPoints *cp = nullptr;
  double theta = 1;                         // Nitsche's Theta
  const TimeScheme *scheme = nullptr;       // the step's contact term; nullptr: [P]_+
  const std::vector<double> *Pn = nullptr;  // P_q(U^n), needed with a scheme
  const double *gap = nullptr;              // the gaps in force (moving obstacle); nullptr: cp->gap
  Counters *counters = nullptr;             // the problem's (ND_STAT_*), or none
  // every point evaluated by this process, whatever cp->share says: for a
  // query outside a step, which is not collective
  bool local = false;

  double g(size_t q) const { return gap ? gap[q] : cp->gap[q]; }
  double P(size_t q, const double *U) const { return cp->a[q].dot(U) - cp->gamma[q] * cp->s[q].dot(U) - g(q); }
  // P[q] = P_q(U) for every point (P sized here), in a step: with several
  // ranks each evaluates the points of its own cells and the values are
  // gathered (collective; see evaluate). Counts one pass.
  void P_all(const double *U, std::vector<double> &P) const;
  // P[q] = eval(q) for the points this process evaluates (with several ranks,
  // those of its own cells; cp->share, parallel/share.hpp), except where
  // skip[q] (skip empty: none is skipped; P[q] is then given, the same on
  // every rank), then the other ranks' points gathered from them: P holds
  // every point on every rank, bitwise as if one process had evaluated them
  // all. Collective when shared. Counts the evaluations (point_evaluations).
  template <class Eval>
  void evaluate(const std::vector<char> &skip, double *P, Eval &&eval) const {
    const Share *share = local ? nullptr : cp->share.get();
    int64_t own = 0;
    auto visit = [&](int64_t q) {
      if (skip.empty() || !skip[q]) P[q] = eval(static_cast<size_t>(q)), ++own;
    };
    if (!share) {
      for (int64_t q = 0, n = static_cast<int64_t>(cp->size()); q < n; ++q) visit(q);
    } else {
      for (const int64_t *q = share->own_begin(); q != share->own_end(); ++q) visit(*q);
    }
    evaluated(share, skip, P, own);
  }
  // evaluate's end: the other ranks' points gathered, the evaluations counted
  void evaluated(const Share *share, const std::vector<char> &skip, double *P, int64_t own) const;
  // phi and its slope at P for point q
  void law(size_t q, double P, double &value, double &slope) const;
  // y += kappa N(U); active[q] = (slope != 0) if active is given
  void add_force(const double *U, double kappa, double *y, std::vector<char> *active) const;
  // T += kappa N'(U) (T has the operator pattern, which holds every a_q, s_q pair)
  void add_tangent(const double *U, double kappa, Csr &T) const;
};

}  // namespace nd
