// The contact law of the Nitsche term (docs/design.md §2-3, docs/architecture.md
// §3 "A new contact law"): what happens at a contact point given its Nitsche
// values P_q = p_q.U - g_q (m per point: m = 1 frictionless), as an object.
// The contact term is geometry (assembly/contact.hpp: a_q, s_q, w_q, gamma_q,
// g_q) times this law; the time scheme only says where over the step the law
// is taken (TimeRule). The passes over the points (solve/contact_law.hpp), the
// tangent solvers, the monitors, the nodal forces and the critical step see
// the law through this interface, and each fast path asks its traits whether
// it applies, else takes the generic pass (the refactoring tangent).
//
// A new law is one file (a class below) and one line in laws.cpp's
// registry. A law of m > 1 values per point (friction: m = dim, the normal
// and the tangential values, contact/friction.hpp) implements over_step_m;
// the passes then apply it through the rank-m blocks (add_blocks,
// add_block_tangent) and every rank-one fast path steps aside.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "assembly/contact.hpp"
#include "linalg/csr.hpp"

namespace nd {

// Where a time scheme takes the law over a step, given P = P_q(U^{n+1}) and
// P^n = P_q(U^n) (docs/design.md §3): the scheme returns it
// (TimeScheme::contact_rule), the law applies it (apply_rule).
struct TimeRule {
  enum Kind : int {
    AtEnd,    // phi(P), phi'(P): the theta-scheme, Newmark, explicit steps, the monitors
    Shifted,  // phi(Y), (1 - af) phi'(Y) at Y = (1 - af) P + af P^n: generalized-alpha
    // H(P^n) phi((P^n + P)/2) + H(-P^n) (phi(P^n) + phi(P))/2, H(0) = 1/2:
    // the paper's hybrid scheme (eq. (17)); slope the same with phi'/2
    Hybrid
  };
  Kind kind = AtEnd;
  double af = 0;  // Shifted's alpha_f
};

// What a law is: the promises the fast paths read (docs/architecture.md §3).
struct LawTraits {
  int m = 1;  // values per contact point
  // the tangent block of a point is slope b_q p_q^T (one column b_q, one
  // row p_q): the condensed Newton, the low-rank (Woodbury) tangent and the
  // updated Cholesky factor add and remove such terms
  bool rank_one = true;
  // with Theta = 1 the tangent is symmetric (b_q = p_q): the symmetric
  // positive definite solvers and the updated Cholesky factor
  bool symmetric = true;
  // value and slope vanish wherever P <= 0 and P^n <= 0 under every rule:
  // the bounds that show a state contact-free without evaluating a point
  // (ContactLaw::certainly_free, the reference's reach), states whose points
  // are left unevaluated, the predictor check
  bool zero_when_free = true;
  // nondecreasing in P (slope >= 0): the bounds (a bound on P bounds the
  // law) and the condensed Newton's active-set iteration
  bool nondecreasing = true;
  // the value is [P]_+ itself (slope 1 for P > 0, else 0): the passes apply
  // it inline under TimeRule::AtEnd, without a call per point; the hybrid
  // rule then reads of a P^n <= 0 only its sign (TimeRule's same bits)
  bool positive_part = true;
  // an upper bound of the slope (the stiffest the point can be): the
  // critical time step takes every point active with it
  double max_slope = 1;
};

// The law at a contact point, its value phi and slope phi' in P (m = 1).
class PointLaw {
 public:
  explicit PointLaw(const LawTraits &t) : traits_(t) {}
  virtual ~PointLaw() = default;
  const LawTraits &traits() const { return traits_; }
  virtual const char *name() const = 0;
  // phi(x) and phi'(x) (the slope at a kink: the right one's at 0 is taken as 0)
  virtual void at(double x, double &value, double &slope) const = 0;
  // phi and phi' over a step by the scheme's rule, P = P_q(U), Pn = P_q(U^n)
  virtual void over_step(const TimeRule &r, double P, double Pn, double &value, double &slope) const;
  // The point's residual block y += f phi b_q, b_q = a_q - Theta gamma_q s_q,
  // and tangent block T += f phi' b_q p_q^T, p_q = a_q - gamma_q s_q (T has
  // the operator pattern); b, p: the caller's reused buffers
  virtual void add_residual(const ContactPoints &cp, double theta, size_t q, double f, double value,
                            double *y) const;
  virtual void add_tangent(const ContactPoints &cp, double theta, size_t q, double f, double slope, Csr &T,
                           std::vector<double> &b, std::vector<double> &p) const;
  // Rank m: point q's m values P (P[0] normal, P[1..m-1] tangential) and
  // Pn at U^n; value (m) and J = d value / d P (m x m, row-major) over the
  // step by rule r. gamma: the point's gamma_q. The default (an m = 1 law
  // at a point of a problem with friction elsewhere): over_step on P[0],
  // the tangential values and their derivatives zero.
  virtual void over_step_m(const TimeRule &r, size_t q, double gamma, int m, const double *P, const double *Pn,
                           double *value, double *J) const;

 private:
  LawTraits traits_;
};

// phi(x), phi'(x) of a law, [x]_+ inline where that is the law (no call per
// point: the monitors' and the nodal forces' passes)
inline void law_at(const PointLaw &law, bool positive_part, double x, double &value, double &slope) {
  if (!positive_part) return law.at(x, value, slope);
  value = x > 0 ? x : 0;
  slope = x > 0 ? 1 : 0;
}
inline void law_at(const PointLaw &law, double x, double &value, double &slope) {
  law_at(law, law.traits().positive_part, x, value, slope);
}

// The rule applied to a law's at(x) (the one form of each rule: a law's
// over_step may inline it with its own at). The same operations, in the same
// order, as the schemes' contact terms had before the rule was the law's.
template <class At>
inline void apply_rule(const TimeRule &r, double P, double Pn, At &&at, double &value, double &slope) {
  if (r.kind == TimeRule::AtEnd) return at(P, value, slope);
  if (r.kind == TimeRule::Shifted) {
    at((1 - r.af) * P + r.af * Pn, value, slope);
    slope *= 1 - r.af;
    return;
  }
  const double h_pos = Pn > 0 ? 1 : Pn < 0 ? 0 : 0.5, h_neg = 1 - h_pos;
  double vm, sm, vn, sn, vp, sp;
  at(0.5 * (Pn + P), vm, sm);
  at(Pn, vn, sn);
  at(P, vp, sp);
  value = h_pos * vm + h_neg * 0.5 * (vn + vp);
  slope = h_pos * (0.5 * sm) + h_neg * (0.5 * sp);
}

// Whether the law over a step under rule r is the same, bit for bit, for
// every P^n <= 0: a state whose P_q are only known to be <= 0
// (PointValues::ref) can stand as P^n (tests/unit_contact_bounds.cpp). At the
// end of the step P^n is not read; the hybrid rule reads its sign, and with
// [P]_+ its halves are exact ([P/2]_+ / 2 + [P]_+ / 4 = [P]_+ / 2 at P^n = 0).
inline bool same_for_nonpositive_Pn(const TimeRule &r, const LawTraits &t) {
  return r.kind == TimeRule::AtEnd || (r.kind == TimeRule::Hybrid && t.positive_part);
}

// y += f b_q, b_q = a_q - Theta gamma_q s_q (inline: the residual's hot loop)
inline void add_b(const ContactPoints &cp, double theta, size_t q, double f, double *y) {
  const SparseRow &a = cp.a[q], &s = cp.s[q];
  const double tg = theta * cp.gamma[q];
  for (size_t k = 0; k < a.idx.size(); ++k) y[a.idx[k]] += f * (a.val[k] - tg * s.val[k]);
}
// T += f b_q p_q^T (T has the operator pattern); b and p: the caller's
// reused buffers (resized here)
inline void add_point_tangent(const ContactPoints &cp, double theta, size_t q, double f, Csr &T,
                              std::vector<double> &b, std::vector<double> &p) {
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

// Rank m (cp.m values per point): y += f sum_k value_k b_qk and
// T += f sum_kl J_kl b_qk p_ql^T, b_qk = a_qk - Theta gamma_q s_qk,
// p_qk = a_qk - gamma_q s_qk (the k-th pair of rows, ContactPoints::a_row)
void add_blocks(const ContactPoints &cp, double theta, size_t q, double f, const double *value, double *y);
void add_block_tangent(const ContactPoints &cp, double theta, size_t q, double f, const double *J, Csr &T,
                       std::vector<double> &b, std::vector<double> &p);

// ---- the registry (laws.cpp) ------------------------------------------------
// The law ids: ND_FRICTION_* of the public header.
constexpr int kFrictionNone = 0;  // frictionless: [P]_+
// The law of an id with its parameters (params[0]: a friction law's
// coefficient or threshold) in dimension dim; throws ND_ERR_VALUE naming
// the id for an unknown one.
std::shared_ptr<const PointLaw> make_law(int id, const double *params = nullptr, int dim = 1);
// Whether id names a registered law, and how many parameters it takes
bool law_registered(int id, int *n_params = nullptr);
// The law of each contact point, one per region (regions[q] the region of
// point q; law_of(region): its law, null: the frictionless one) as one law:
// traits joined (m the largest; a promise holds if every law makes it)
std::shared_ptr<const PointLaw> laws_by_point(
    const std::vector<int> &regions, const std::vector<std::pair<int, std::shared_ptr<const PointLaw>>> &by_region);
// The frictionless law (shared, never destroyed): the default of every pass.
const PointLaw &frictionless_law();

// The registry's entries, one per law file.
std::shared_ptr<const PointLaw> make_frictionless_law();
std::shared_ptr<const PointLaw> make_tresca_law(const double *params, int dim);
std::shared_ptr<const PointLaw> make_coulomb_law(const double *params, int dim);

}  // namespace nd
