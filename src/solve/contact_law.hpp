// The Nitsche contact term (docs/design.md §2-3) as a function of U:
//   P_q(U) = p_q.U - g_q,  p_q = a_q - gamma_q s_q,  b_q = a_q - Theta gamma_q s_q
//   N(U)   = sum_q (w_q/gamma_q) phi(P_q(U), P_q^n) b_q
// where phi is the time scheme's contact term ([P]_+ for the theta-scheme and
// Newmark, the hybrid scheme's Phi, generalized-alpha's shifted point), or
// [P]_+ when no scheme is given (energies, pressure, explicit steps). The
// tangent is N'(U) = sum_q (w_q/gamma_q) phi'(P_q(U), P_q^n) b_q p_q^T.
#pragma once
#include <limits>
#include <vector>

#include "assembly/contact.hpp"
#include "common/counters.hpp"
#include "contact/law.hpp"
#include "linalg/csr.hpp"
#include "parallel/share.hpp"
#include "time/scheme.hpp"

namespace nd {

// Every pass over a point reads a_q's index list for s_q too (dots, p_dot,
// add_b, add_point_tangent, the runs; a_fixed and s_fixed likewise: the
// reactions): throws ND_ERR_INTERNAL naming the point unless each s_q has
// a_q's indices, in order. Made once where the points are assembled.
void require_shared_index_lists(const ContactPoints &cp);

// p_q . v, p_q = a_q - gamma_q s_q (P_q(v) without its gap); with place,
// v holds unknown i at v[place[i]] (the same sum, in the same order)
double p_dot(const ContactPoints &cp, size_t q, const double *v, const int64_t *place = nullptr);
// appends c p_q = c (a_q - gamma_q s_q): a_q's indices to idx, the values to val
void append_p(const ContactPoints &cp, size_t q, double c, std::vector<int64_t> &idx, std::vector<double> &val);
// (add_b and add_point_tangent, the rank-one blocks: contact/law.hpp)

// The reused buffers of ContactLaw's passes. The object that owns the
// computation keeps one (the integrator, the massless solver) and hands it
// down (ContactLaw::buffers), so that a step allocates nothing once they
// have grown, and an allocation that fails is a std::bad_alloc of the call
// (not the abort of a thread_local's destructor registration, issue 54).
struct ContactScratch {
  std::vector<double> own;      // contact_free's P_q
  std::vector<double> force;    // add_force's P_q
  std::vector<double> tangent;  // add_tangent's P_q
  std::vector<double> b, p;     // add_point_tangent's b_q, p_q
};

// The contact points a rank's Newton pass reads on split rows (ContactLaw::
// halo): its own and those whose rows touch its rows; null with one rank.
std::shared_ptr<const Halo> contact_point_halo(const ContactPoints &cp, const Share &rows);

// The unknowns (ascending) of the rank's own rows (of `rows`, n of them) and
// of every contact point's rows, with, given A, the columns of A's entries
// in the own rows, and the columns of every row of `also` (the clamped rows,
// whose reactions read them): what a rank reads of a vector held on split rows.
// points (ascending; null: all) limits the contact points to those.
std::vector<int64_t> rows_and_points(int64_t n, const Share &rows, const ContactPoints &cp,
                                     const Csr *A = nullptr, const std::vector<const Csr *> &also = {},
                                     const std::vector<int64_t> *points = nullptr);

// The unknowns (ascending) of every contact point's rows: all that P_q reads.
std::vector<int64_t> point_unknowns(int64_t n, const ContactPoints &cp);

// The contact points a rank holds with a distributed state whose Newton
// passes read a halo: the halo's points (its own and those whose
// rows touch its rows) and every point with rows on clamped DOFs (every
// rank computes the reactions); the state is right at their DOFs only, and
// the state's pass, the bound of certainly_free and the applied term phi
// cover them only.
struct HeldPoints {
  std::vector<int64_t> points;  // ascending
  std::vector<int64_t> dofs;    // the free DOFs their rows touch, ascending
};
std::shared_ptr<const HeldPoints> held_points(const ContactPoints &cp, const Halo &halo);

// Over `dofs`: max |U_i - Uref_i|, max |U_i|, max |Uref_i|, and whether
// every value read is finite (the bounds below read nothing else of U)
struct Reach {
  double d = 0, u_max = 0, ref_max = 0;
  bool finite = true;
};
Reach reach(const std::vector<int64_t> &dofs, const double *U, const double *Uref);

// The reference's free_reach and within_reach (time/state.hpp), the latter
// for the penetration limit `limit` (0: none), made for the reference's
// gaps: at a U whose reach (over cp.dofs, from ref.U) they admit, with the
// gaps bitwise the reference's, certainly_free's test and the bounds below
// hold at every point (the same verdicts), one comparison instead of one a point.
// (length: the points' lengths the limit multiplies, null or empty: h_q)
void set_reference_reach(const ContactPoints &cp, PointReference &ref, double limit,
                         const std::vector<double> *length = nullptr);
// Whether r admits a reach made by set_reference_reach, and whether the gaps
// at the check are bitwise the reference's (what the checks ask)
bool reach_admitted(const Reach &r, double admitted);
bool same_gaps(const double *g, const double *g_ref, size_t nq);

// Whether every point's u_n - g0 at U (gaps `gap`, null: the assembled
// ones), evaluated, would be at most limit h_q (limit length_q with `length`), shown without evaluating
// one: from the point reference's (time/state.hpp),
//   u_n(U) <= u_n(U_ref) + sum_k |a_qk| max_i |U_i - U_ref_i| + g_ref - g
// (i over cp.dofs) with certainly_free's margin. False says nothing: then
// evaluate. The penetration guard's test for a state whose points were not
// evaluated (monitor/guards.cpp).
bool penetration_within(const ContactPoints &cp, const double *U, const double *gap, const PointReference &ref,
                        double limit, const std::vector<double> *length = nullptr);
// Whether every point's P_q at U would be at most 0, shown the same way
// from the reference's P_q (certainly_free's bound and margin): a query of
// a state whose points a step left unevaluated then knows its contact
// forces are zero, the bits of their sums over the evaluated points.
bool nonpositive_within(const ContactPoints &cp, const double *U, const double *gap, const PointReference &ref);

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
  // U^n and its gaps (nullptr: cp->gap), where Pn was evaluated: with them a
  // U near U^n may be shown contact-free without a pass (certainly_free)
  const double *Un = nullptr, *gap_n = nullptr;
  // Where Un and Pn are a point reference's (time/state.hpp): its
  // free_reach, with which certainly_free reads only U's reach where the
  // gaps are bitwise gap_n (-infinity: every point is tested)
  double free_reach_n = -std::numeric_limits<double>::infinity();
  // A Newton pass whose solves and residual read this rank's rows only (the
  // refactoring tangent on split rows): the points it reads, its
  // own and those whose rows touch its rows, received from their owners
  // alone (contact_point_halo). Null: every point on every rank (gathered).
  // Only the passes of P_read and what uses it (add_force, add_tangent,
  // contact_free, summarize) take it; P_all always gives every point.
  const Halo *halo = nullptr;
  // With a halo: its points evaluated by this rank, not received (a
  // distributed state holds U right at the DOFs of the points the rank
  // reads: the same bits as their owners', no message)
  bool halo_here = false;
  // With a halo and a distributed state: the points this rank holds
  // (held_points). certainly_free's bound then covers them only, and
  // contact_free reduces the ranks' verdicts, bound or not (null: every point)
  const HeldPoints *held = nullptr;
  // The buffers the passes reuse (the owner's); null: each call makes its own
  ContactScratch *buffers = nullptr;
  // friction (cp->m > 1): the slip references, m - 1 per point (the
  // tangential values' gaps, State::slip); nullptr: zero
  const double *gap_t = nullptr;

  double g(size_t q) const { return gap ? gap[q] : cp->gap[q]; }
  // cp->size() P_q, then with friction (cp->m > 1) the tangential values:
  // value k >= 1 of point q at size() + q (m - 1) + k - 1 (PointValues::P)
  size_t values() const { return cp->size() * static_cast<size_t>(cp->m); }
  // the tangential values of every point at U into P[size() ..) (P sized
  // values() by the caller): ta . U - gamma ts . U - gap_t
  void tangential_values(const double *U, double *P) const;
  // point q's m values from P (as P_all leaves them) into v
  void point_values(const std::vector<double> &P, size_t q, double *v) const {
    const size_t nq = cp->size(), mt = static_cast<size_t>(cp->m - 1);
    v[0] = P[q];
    for (size_t k = 0; k < mt; ++k) v[k + 1] = P[nq + q * mt + k];
  }
  // the law's m values and Jacobian at point q (rank m: law_object().over_step_m)
  void law_m(size_t q, const std::vector<double> &P, double *value, double *J) const;
  // no halo narrows the passes: P_read is P_all, and its values can stand
  // for any pass over every point at the same U
  bool reads_all() const { return !halo || local; }
  // sa = a_q.U and ss = s_q.U, each summed in index order (the bits of
  // SparseRow::dot), in one loop: a_q and s_q share their index list
  void dots(size_t q, const double *U, double &sa, double &ss) const {
    const SparseRow &a = cp->a[q];
    const double *av = a.val.data(), *sv = cp->s[q].val.data();
    const int64_t *idx = a.idx.data();
    sa = 0, ss = 0;
    for (size_t k = 0, m = a.idx.size(); k < m; ++k) {
      const double u = U[idx[k]];
      sa += av[k] * u;
      ss += sv[k] * u;
    }
  }
  // P_q(U) = a_q.U - gamma_q s_q.U - g_q
  double P(size_t q, const double *U) const {
    double sa, ss;
    dots(q, U, sa, ss);
    return sa - cp->gamma[q] * ss - g(q);
  }
  // P[q] = P_q(U) for every point (P sized here), in a step: with several
  // ranks each evaluates the points of its own cells and the values are
  // gathered (collective; see evaluate), except with friction (cp->m > 1:
  // every rank evaluates every value, no message). Counts one pass. With un, also
  // un[q] = a_q.U - g_q (u_n - g0, the penetration guard's) from the same
  // pass, bitwise SparseRow::dot's.
  void P_all(const double *U, std::vector<double> &P, std::vector<double> *un = nullptr) const;
  // P_all's values (and un's, if given) where one process evaluates every
  // point (no share, or local), run by run of cp->runs (U read once per run,
  // a shared s_q.U once), the bits of P(q, U); false, nothing done, without
  // runs or with several ranks
  bool P_by_runs(const double *U, double *P, double *un) const;
  // True only if the law and its slope vanish at every point at U, shown
  // without evaluating a point: from P^n (Pn at Un, gaps gap_n) and
  //   P_q(U) <= P_q(U^n) + nu_q max_i |U_i - U^n_i| + g^n_q - g_q
  // (i over cp->dofs, the DOFs the points' rows touch)
  // with a margin far above the round-off of either evaluation, for a law
  // zero where free and nondecreasing in P (LawTraits; else false). False says nothing:
  // then evaluate. The same answer on every rank (U, U^n and P^n are the
  // same there), no message; with `held`, over the rank's points only (an
  // answer for this rank). Counts ND_STAT_CONTACT_BOUNDS when true (`counted`).
  bool certainly_free(const std::vector<double> &U, bool counted = true) const;
  // P[q] = eval(q) for the points this process evaluates (with several ranks,
  // those of its own cells; cp->share, parallel/share.hpp), except where
  // skip[q] (skip empty: none is skipped; P[q] is then given, the same on
  // every rank), then the other ranks' points gathered from them: P holds
  // every point on every rank, bitwise as if one process had evaluated them
  // all. Collective when shared. Counts the evaluations (point_evaluations).
  // `also`: fields eval fills as it goes (un of P_all), gathered with P.
  template <class Eval>
  void evaluate(const std::vector<char> &skip, double *P, Eval &&eval, const std::vector<double *> &also = {}) const {
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
    evaluated(share, skip, P, also, own);
  }
  // evaluate's end: the other ranks' points gathered, the evaluations counted
  void evaluated(const Share *share, const std::vector<char> &skip, double *P, const std::vector<double *> &also,
                 int64_t own) const;
  // P[q] = P_q(U) where this rank reads it: with a halo, its own points and
  // (if `received`) the halo's others (evaluated here with halo_here), NaN at
  // the rest (a reader that slipped through fails loudly); without, or with
  // friction (cp->m > 1: every point on every rank), P_all.
  // Counts one pass, each point once for the ranks together.
  void P_read(const double *U, std::vector<double> &P, bool received = true) const;
  // Whether N and N' vanish at U at every point: certainly_free, else a pass
  // (with a halo, each rank its own points, then one reduction; with `held`
  // the ranks' bounds are reduced with it, and counted when all held).
  // Collective. P (if given): P_q(U) at every point when the pass was made
  // and was every point's (one process), else left empty. by_bound (if
  // given): whether the bound alone said free, on every rank.
  bool contact_free(const std::vector<double> &U, std::vector<double> *P = nullptr, bool *by_bound = nullptr) const;
  // From the active sets of add_force (`previous` may be empty): whether a
  // point is active, whether the set changed; with a halo from each rank's
  // own points, reduced in one message (the same answer on every rank).
  void summarize(const std::vector<char> &active, const std::vector<char> &previous, bool &any,
                 bool &changed) const;
  // f(q) for every point this rank reads (halo->read), or every point
  template <class F>
  void for_read(F &&f) const {
    if (!reads_all()) {
      for (int64_t q : halo->read) f(static_cast<size_t>(q));
      return;
    }
    for (size_t q = 0, m = cp->size(); q < m; ++q) f(q);
  }
  // The contact law (contact/law.hpp); null: the frictionless one. Every
  // pass applies it through law() and the blocks, and each fast path asks
  // its traits (traits()) whether it applies.
  const PointLaw *point_law = nullptr;
  const PointLaw &law_object() const { return point_law ? *point_law : frictionless_law(); }
  const LawTraits &traits() const { return law_object().traits(); }
  // The step's time rule (the scheme's; AtEnd without one)
  const TimeRule &rule() const {
    static constexpr TimeRule at_end{};
    return scheme ? scheme->contact_rule() : at_end;
  }
  // phi is [P]_+ at U: the passes apply it inline, no call per point
  bool positive_part() const {
    return (!scheme || scheme->contact_rule().kind == TimeRule::AtEnd) &&
           (!point_law || point_law->traits().positive_part);
  }
  // phi and its slope at P for point q, the law over the step by the
  // scheme's rule ([P]_+ inline where that is the law)
  void law(size_t q, double P, double &value, double &slope) const { law(q, P, value, slope, positive_part()); }
  // the same with positive_part() given: a pass asks it once, not per point
  void law(size_t q, double P, double &value, double &slope, bool pp) const {
    if (!pp) return law_object().over_step(rule(), P, Pn ? (*Pn)[q] : 0.0, value, slope);
    value = P > 0 ? P : 0;
    slope = P > 0 ? 1 : 0;  // the slope of [.]_+ at 0 is taken as 0
  }
  // y += kappa N(U); active[q] = (slope != 0) if active is given (with a
  // halo: y right on this rank's rows, active at the points it reads, else 0)
  // P (if given): P_q(U) as P_read leaves it, for the tangent at U (P_at);
  // un (with P): u_n - g0 from the same pass where P_read is P_all, else
  // left empty (the new state's products take both: PointValues)
  void add_force(const double *U, double kappa, double *y, std::vector<char> *active,
                 std::vector<double> *P = nullptr, std::vector<double> *un = nullptr) const;
  // the same from P = P_q(U) already evaluated
  void add_force_from(const std::vector<double> &P, double kappa, double *y, std::vector<char> *active) const;
  // T += kappa N'(U) (T has the operator pattern, which holds every a_q, s_q pair)
  // P: P_q(U) as add_force left it at this U, or null (evaluated here)
  void add_tangent(const double *U, double kappa, Csr &T, const std::vector<double> *P = nullptr) const;
  // P_q(U) for every point: P if given (what add_force left at this U, when
  // P_read reads every point), else evaluated into `scratch` by P_all
  const std::vector<double> &P_at(const double *U, const std::vector<double> *P, std::vector<double> &scratch) const;
};

}  // namespace nd
