#include "solve/contact_law.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "common/simd.hpp"
#include "nitschedyn.h"

namespace nd {

namespace {
// what `receive` adds to values_received is also the points' (point_values_received)
template <class Receive>
void receiving_points(Counters *c, Receive &&receive) {
  const int64_t before = c ? c->values_received : 0;
  receive();
  if (c) c->point_values_received += c->values_received - before;
}
}  // namespace

void ContactLaw::evaluated(const Share *share, const std::vector<char> &skip, double *P,
                           const std::vector<double *> &also, int64_t own) const {
  int64_t done = own;
  if (share) {  // the job's count needs no message: the skipped points are the same on every rank
    done = static_cast<int64_t>(cp->size());
    for (char s : skip) done -= s != 0;
    std::vector<double *> fields{P};
    fields.insert(fields.end(), also.begin(), also.end());
    receiving_points(share->counters, [&] { gather(*share, fields); });
  }
  count(counters, &Counters::point_evaluations, done);
  count(counters, &Counters::own_point_evaluations, own);
}

namespace {
typedef double Pair __attribute__((vector_size(16)));
constexpr size_t kRunEntries = 64;  // the longest index list read into a run's copy of U (P2 3D: 30)
constexpr size_t kRunPoints = 64;   // the most points of a run the wide form takes (P2 3D: 16)

#ifdef ND_AVX2
// out[p] = sum_k rows[k n + p] u[k] for the n points of a run (rows:
// ContactPoints::run_rows), each sum in index order from +0 (dots()'s
// bits): four points per lane group, then two, then one
__attribute__((target("avx2"))) void run_dots_avx2(const double *rows, size_t n, size_t m, const double *u,
                                                   double *out) {
  size_t p = 0;
  for (; p + 4 <= n; p += 4) {
    __m256d x = _mm256_setzero_pd();
    for (size_t k = 0; k < m; ++k) x += _mm256_loadu_pd(rows + k * n + p) * _mm256_broadcast_sd(u + k);
    _mm256_storeu_pd(out + p, x);
  }
  _mm256_zeroupper();
  for (; p + 2 <= n; p += 2) {
    __m128d x = _mm_setzero_pd();
    for (size_t k = 0; k < m; ++k) x += _mm_loadu_pd(rows + k * n + p) * _mm_set1_pd(u[k]);
    _mm_storeu_pd(out + p, x);
  }
  for (; p < n; ++p) {
    double x = 0;
    for (size_t k = 0; k < m; ++k) x += rows[k * n + p] * u[k];
    out[p] = x;
  }
}
#endif
}  // namespace

bool ContactLaw::P_by_runs(const double *U, double *P, double *un) const {
  const std::vector<int64_t> &runs = cp->runs;
  const size_t nq = cp->size();
  if (runs.size() != cp->run_shares_s.size() + 1 || runs.back() != static_cast<int64_t>(nq) ||
      (!local && cp->share))
    return false;
  auto finish = [&](size_t q, double sa, double ss) {
    P[q] = sa - cp->gamma[q] * ss - g(q);  // P(q, U)'s expression
    if (un) un[q] = sa - g(q);
  };
  double u[kRunEntries];
  const bool wide = simd_on() && cp->run_row_at.size() + 1 == runs.size();
  for (size_t r = 0; r + 1 < runs.size(); ++r) {
    size_t q = static_cast<size_t>(runs[r]);
    const size_t end = static_cast<size_t>(runs[r + 1]), m = cp->a[q].idx.size();
    if (m > kRunEntries) {
      for (; q < end; ++q) {
        double sa, ss;
        dots(q, U, sa, ss);
        finish(q, sa, ss);
      }
      continue;
    }
    const int64_t *idx = cp->a[q].idx.data();
    for (size_t k = 0; k < m; ++k) u[k] = U[idx[k]];
    // each sum in index order, dots()'s bits; two points in an SSE2 pair
    auto dot = [&](const double *v) {
      double sum = 0;
      for (size_t k = 0; k < m; ++k) sum += v[k] * u[k];
      return sum;
    };
    const bool shared = cp->run_shares_s[r] != 0;
    const double ss_run = shared ? dot(cp->s[q].val.data()) : 0;  // s_q.U once for the run
#ifdef ND_AVX2
    if (wide && end - q <= kRunPoints) {  // the run's rows interleaved: four points per load
      const size_t n = end - q;
      const double *rows = cp->run_rows.data() + cp->run_row_at[r];
      double sa[kRunPoints], ss[kRunPoints];
      run_dots_avx2(rows, n, m, u, sa);
      if (shared) std::fill(ss, ss + n, ss_run);
      else run_dots_avx2(rows + m * n, n, m, u, ss);
      for (size_t p = 0; p < n; ++p) finish(q + p, sa[p], ss[p]);
      continue;
    }
#endif
    for (; q + 1 < end; q += 2) {
      const double *a0 = cp->a[q].val.data(), *a1 = cp->a[q + 1].val.data();
      Pair sa = {0, 0}, ss = {ss_run, ss_run};
      if (shared) {
        for (size_t k = 0; k < m; ++k) sa += Pair{a0[k], a1[k]} * Pair{u[k], u[k]};
      } else {
        const double *s0 = cp->s[q].val.data(), *s1 = cp->s[q + 1].val.data();
        ss = Pair{0, 0};
        for (size_t k = 0; k < m; ++k) {
          const Pair uk = {u[k], u[k]};
          sa += Pair{a0[k], a1[k]} * uk;
          ss += Pair{s0[k], s1[k]} * uk;
        }
      }
      finish(q, sa[0], ss[0]);
      finish(q + 1, sa[1], ss[1]);
    }
    if (q < end) finish(q, dot(cp->a[q].val.data()), shared ? ss_run : dot(cp->s[q].val.data()));
  }
  evaluated(nullptr, {}, P, {}, static_cast<int64_t>(nq));
  return true;
}

namespace {
// ta_j.U and ts_j.U for point q's m - 1 tangential pairs and, with Normal,
// a_q.U and s_q.U (sa, ss), each summed in index order (the bits of
// SparseRow::dot), in one loop over the index list they share with a_q: U
// and the indices read once for all of a point's values
template <bool Normal, int Mt>
void point_dots(const ContactPoints &cp, size_t q, const double *U, double &sa, double &ss, double *ta, double *ts) {
  const size_t j0 = q * Mt;
  const int64_t *idx = cp.a[q].idx.data();
  const double *a0 = cp.a[q].val.data(), *s0 = cp.s[q].val.data();
  const double *a1 = cp.ta[j0].val.data(), *s1 = cp.ts[j0].val.data();
  const double *a2 = Mt == 2 ? cp.ta[j0 + 1].val.data() : nullptr, *s2 = Mt == 2 ? cp.ts[j0 + 1].val.data() : nullptr;
  double sa0 = 0, ss0 = 0, sa1 = 0, ss1 = 0, sa2 = 0, ss2 = 0;
  for (size_t k = 0, len = cp.a[q].idx.size(); k < len; ++k) {
    const double u = U[idx[k]];
    if (Normal) sa0 += a0[k] * u, ss0 += s0[k] * u;
    sa1 += a1[k] * u;
    ss1 += s1[k] * u;
    if (Mt == 2) sa2 += a2[k] * u, ss2 += s2[k] * u;
  }
  sa = sa0, ss = ss0;
  ta[0] = sa1, ts[0] = ss1, ta[1] = sa2, ts[1] = ss2;
}

// every point's tangential values (and, with Normal, P_q and u_n - g0
// into P[q] and un[q], un null: not wanted) at U, one loop per point
template <bool Normal, int Mt>
void friction_pass(const ContactLaw &law, const double *U, double *P, double *un) {
  const ContactPoints &cp = *law.cp;
  const size_t nq = cp.size();
  double sa, ss, ta[2], ts[2];
  for (size_t q = 0; q < nq; ++q) {
    point_dots<Normal, Mt>(cp, q, U, sa, ss, ta, ts);
    if (Normal) {
      if (un) un[q] = sa - law.g(q);
      P[q] = sa - cp.gamma[q] * ss - law.g(q);
    }
    for (size_t k = 0; k < Mt; ++k) {
      const size_t j = q * Mt + k;
      P[nq + j] = ta[k] - cp.gamma[q] * ts[k] - (law.gap_t ? law.gap_t[j] : 0.0);
    }
  }
}

template <bool Normal>
void friction_pass(const ContactLaw &law, const double *U, double *P, double *un) {
  if (law.cp->m == 2) return friction_pass<Normal, 1>(law, U, P, un);
  friction_pass<Normal, 2>(law, U, P, un);
}
}  // namespace

void ContactLaw::tangential_values(const double *U, double *P) const { friction_pass<false>(*this, U, P, nullptr); }

void ContactLaw::law_m(size_t q, const std::vector<double> &P, double *value, double *J) const {
  double v[3], vn[3];
  point_values(P, q, v);
  if (Pn) point_values(*Pn, q, vn);
  law_object().over_step_m(rule(), q, cp->gamma[q], cp->m, v, Pn ? vn : nullptr, value, J);
}

void ContactLaw::P_all(const double *U, std::vector<double> &P, std::vector<double> *un) const {
  P.resize(cp->size());
  if (un) un->resize(cp->size());
  if (P.empty()) return;
  count(counters, &Counters::contact_evaluations);
  // friction: every value here, on every rank (no share, no message): a
  // rank's U is right at every point's DOFs (a whole state, and Newton's
  // solves on split rows keep them: newton_held_rows), so each rank has one
  // process's bits (docs/design.md §10.2)
  if (cp->m > 1) {
    P.resize(values());
    friction_pass<true>(*this, U, P.data(), un ? un->data() : nullptr);
    count(counters, &Counters::point_evaluations, static_cast<int64_t>(cp->size()));
    count(counters, &Counters::own_point_evaluations, static_cast<int64_t>(cp->size()));
    return;
  }
  if (P_by_runs(U, P.data(), un ? un->data() : nullptr)) return;
  if (!un) {
    evaluate({}, P.data(), [&](size_t q) { return this->P(q, U); });
    return;
  }
  double *u = un->data();
  evaluate(
      {}, P.data(),
      [&](size_t q) {
        double sa, ss;
        dots(q, U, sa, ss);
        u[q] = sa - g(q);
        return sa - cp->gamma[q] * ss - g(q);
      },
      {u});
}

void ContactLaw::P_read(const double *U, std::vector<double> &P, bool received) const {
  if (reads_all() || cp->m > 1) return P_all(U, P);  // (friction: every point on every rank, P_all)
  P.assign(cp->size(), std::numeric_limits<double>::quiet_NaN());
  if (P.empty()) return;
  count(counters, &Counters::contact_evaluations);
  count(counters, &Counters::point_evaluations, static_cast<int64_t>(cp->size()));
  if (received && halo_here) {  // every point read, evaluated here
    for (int64_t q : halo->read) P[q] = this->P(q, U);
    count(counters, &Counters::own_point_evaluations, static_cast<int64_t>(halo->read.size()));
    return;
  }
  const Share &share = *halo->share;
  for (const int64_t *q = share.own_begin(); q != share.own_end(); ++q) P[*q] = this->P(*q, U);
  count(counters, &Counters::own_point_evaluations, share.own_count());
  if (received) receiving_points(share.counters, [&] { exchange(*halo, P.data()); });
}

bool ContactLaw::contact_free(const std::vector<double> &U, std::vector<double> *P_out, bool *by_bound) const {
  const bool reduced = !reads_all(), per_rank = held && reduced;
  if (P_out) P_out->clear();
  if (by_bound) *by_bound = false;
  // far from the obstacle: no point evaluated (with `held`, this rank's
  // points: counted below when every rank's bound held, the job's count)
  const bool bound = certainly_free(U, !per_rank);
  if (bound && !per_rank) {
    if (by_bound) *by_bound = true;
    return true;
  }
  double flags[2] = {0, bound ? 0.0 : 1.0};  // a busy own point, a bound that failed
  double &any = flags[0];
  if (!bound) {
    std::vector<double> mine;
    std::vector<double> &P = P_out && !reduced ? *P_out : buffers ? buffers->own : mine;
    P_read(U.data(), P, false);  // own points: the verdict is reduced, no value sent
    const bool pp = positive_part();
    auto busy = [&](int64_t q) {
      double value, slope;
      if (cp->m > 1) {  // every value and slope of the point (friction)
        double v[3], J[9];
        law_m(static_cast<size_t>(q), P, v, J);
        for (int k = 0; k < cp->m; ++k)
          if (v[k] != 0) return true;
        for (int k = 0; k < cp->m * cp->m; ++k)
          if (J[k] != 0) return true;
        return false;
      }
      law(static_cast<size_t>(q), P[q], value, slope, pp);
      return value != 0 || slope != 0;
    };
    if (!reduced) {
      for (size_t q = 0; q < cp->size(); ++q)
        if (busy(static_cast<int64_t>(q))) return false;
      return true;
    }
    for (const int64_t *q = halo->share->own_begin(); q != halo->share->own_end() && any == 0; ++q) any = busy(*q);
  }
  if (!per_rank) return max_over_ranks(halo->share->comm.get(), any) == 0;
  max_over_ranks(halo->share->comm.get(), flags, 2);
  if (flags[1] == 0) count(counters, &Counters::contact_bounds);
  if (by_bound) *by_bound = flags[1] == 0;
  return flags[0] == 0;
}

void ContactLaw::summarize(const std::vector<char> &active, const std::vector<char> &previous, bool &any,
                           bool &changed) const {
  any = false;
  if (reads_all()) {
    for (char a : active) any |= a != 0;
    changed = active != previous;
    return;
  }
  double flags[2] = {0, active.size() != previous.size() ? 1.0 : 0.0};
  for (const int64_t *q = halo->share->own_begin(); q != halo->share->own_end(); ++q) {
    if (active[*q]) flags[0] = 1;
    if (flags[1] == 0 && active[*q] != previous[*q]) flags[1] = 1;
  }
  max_over_ranks(halo->share->comm.get(), flags, 2);
  any = flags[0] != 0, changed = flags[1] != 0;
}

namespace {
// The bound's margin, relative to the size of the terms: the round-off of an
// evaluation of P_q is at most about (m + 2) eps (sum_k |a_qk U_k| + gamma_q
// |s_qk U_k| + |g_q|), m <= 30 entries (P2 in 3D): 7e-15 of it; this is 150
// times that.
constexpr double kBoundMargin = 1e-12;

// The bounds' test at every point q (certainly_free's on P_q, x = P_q(U_r),
// c = nu; penetration_within's on u_n, x = u_n(U_r), c = sum |a_q|):
//   high_q = x_q + c_q d + (gr_q - gn_q) + margin_q,
//   margin_q = kBoundMargin (c_q reach + |gn_q| + |gr_q| + |x_q|),
// and without `scale` -max <= high_q <= 0 (also false for NaN and
// infinities), and x_q <= 0 if `x_nonpositive`; with it high_q / scale_q
// <= limit. Whether it holds at every point. No branch per point.
struct BoundTest {
  const double *x, *c, *gn, *gr, *scale;
  double d, reach, limit;
  bool x_nonpositive;
};

double high_at(const BoundTest &t, size_t q) {
  const double margin =
      kBoundMargin * (t.c[q] * t.reach + std::fabs(t.gn[q]) + std::fabs(t.gr[q]) + std::fabs(t.x[q]));
  return t.x[q] + t.c[q] * t.d + (t.gr[q] - t.gn[q]) + margin;
}

bool all_within_scalar(const BoundTest &t, size_t begin, size_t end) {
  bool all = true;
  for (size_t q = begin; q < end; ++q) {
    const double high = high_at(t, q);
    if (t.scale)
      all &= high / t.scale[q] <= t.limit;
    else
      all &= (high <= 0) & (high >= -std::numeric_limits<double>::max()) & (!t.x_nonpositive || t.x[q] <= 0);
  }
  return all;
}

#ifdef ND_AVX2
// four points a lane group, each lane the scalar test's operations in its
// order (the same verdict)
__attribute__((target("avx2"))) bool all_within_avx2(const BoundTest &t, size_t nq) {
  const __m256d d = _mm256_set1_pd(t.d), reach = _mm256_set1_pd(t.reach), km = _mm256_set1_pd(kBoundMargin),
                zero = _mm256_setzero_pd(), lowest = _mm256_set1_pd(-std::numeric_limits<double>::max()),
                limit = _mm256_set1_pd(t.limit),
                no_sign = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
  __m256d ok = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  size_t q = 0;
  for (; q + 4 <= nq; q += 4) {
    const __m256d x = _mm256_loadu_pd(t.x + q), c = _mm256_loadu_pd(t.c + q), gn = _mm256_loadu_pd(t.gn + q),
                  gr = _mm256_loadu_pd(t.gr + q);
    const __m256d margin = km * (c * reach + _mm256_and_pd(gn, no_sign) + _mm256_and_pd(gr, no_sign) +
                                 _mm256_and_pd(x, no_sign));
    const __m256d high = x + c * d + (gr - gn) + margin;
    if (t.scale) {
      ok = _mm256_and_pd(ok, _mm256_cmp_pd(high / _mm256_loadu_pd(t.scale + q), limit, _CMP_LE_OQ));
    } else {
      ok = _mm256_and_pd(ok, _mm256_and_pd(_mm256_cmp_pd(high, zero, _CMP_LE_OQ),
                                           _mm256_cmp_pd(high, lowest, _CMP_GE_OQ)));
      if (t.x_nonpositive) ok = _mm256_and_pd(ok, _mm256_cmp_pd(x, zero, _CMP_LE_OQ));
    }
  }
  const bool all = _mm256_movemask_pd(ok) == 0xF;
  _mm256_zeroupper();
  return all_within_scalar(t, q, nq) && all;
}
#endif

bool all_within(const BoundTest &t, size_t nq) {
#ifdef ND_AVX2
  if (simd_on()) return all_within_avx2(t, nq);
#endif
  return all_within_scalar(t, 0, nq);
}

// The test above at every point, made once for a reference whose gaps stay
// (gn = gr = g): high_q <= limit scale_q (or <= 0) holds where
//   c_q (d + 2 kBoundMargin reach) <= room_q,
//   room_q = limit (1 - 1e-12) scale_q - x_q - 2 kBoundMargin (2 |g_q| + |x_q|),
// twice the test's margin and 1e-12 of its limit: their excess over the test
// covers this form's round-off (a few eps of the same terms) and the test's
// division by scale_q, so that where d + 2 kBoundMargin reach is at most
// min_q room_q / c_q the test holds at every point (also x_q <= 0): the
// test's verdict. -infinity where some value is not finite.
double admitted_reach(const double *x, const double *c, const double *g, const double *scale, double limit,
                      size_t nq) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double below = limit * (1 - 1e-12);
  double admitted = inf;
  bool finite = true;
  for (size_t q = 0; q < nq; ++q) {
    const double room =
        (scale ? below * scale[q] : 0.0) - x[q] - 2 * kBoundMargin * (2 * std::fabs(g[q]) + std::fabs(x[q]));
    finite &= std::isfinite(room) && std::isfinite(c[q]);
    if (c[q] > 0) admitted = std::min(admitted, room / c[q]);
    else if (!(room >= 0)) admitted = -inf;  // (c_q = 0: no reach admits it)
  }
  return finite ? admitted : -inf;
}
}  // namespace

void set_reference_reach(const ContactPoints &cp, PointReference &ref, double limit,
                         const std::vector<double> *length) {
  const std::vector<double> &len = length && !length->empty() ? *length : cp.h;
  const size_t nq = cp.size();
  const double *g = ref.gap.empty() ? cp.gap.data() : ref.gap.data();
  if ((!ref.gap.empty() && ref.gap.size() != nq) || ref.P.size() != nq || cp.nu.size() != nq) return;
  ref.free_reach = admitted_reach(ref.P.data(), cp.nu.data(), g, nullptr, 0, nq);
  if (limit > 0 && ref.un.size() == nq && cp.a_sum.size() == nq && len.size() == nq)
    ref.within_reach = admitted_reach(ref.un.data(), cp.a_sum.data(), g, len.data(), limit, nq),
    ref.within_limit = limit;
}

bool same_gaps(const double *g, const double *g_ref, size_t nq) {
  return g == g_ref || std::memcmp(g, g_ref, nq * sizeof(double)) == 0;  // (bitwise: g_ref - g is 0)
}

bool reach_admitted(const Reach &r, double admitted) {
  const double needed = r.d + 2 * kBoundMargin * (r.u_max + r.ref_max + r.d);  // (the tests' reach)
  return r.finite && std::isfinite(needed) && needed <= admitted;
}

namespace {
void reach_scalar(const int64_t *dofs, size_t begin, size_t end, const double *U, const double *Uref, Reach &r) {
  int finite = r.finite ? 1 : 0;
  for (size_t k = begin; k < end; ++k) {
    const int64_t i = dofs[k];
    finite &= static_cast<int>(std::isfinite(U[i])) & static_cast<int>(std::isfinite(Uref[i]));  // (no branch)
    r.d = std::max(r.d, std::fabs(U[i] - Uref[i]));
    r.u_max = std::max(r.u_max, std::fabs(U[i]));
    r.ref_max = std::max(r.ref_max, std::fabs(Uref[i]));
  }
  r.finite = finite != 0;
}

#ifdef ND_AVX2
// four DOFs a lane group, gathered; maxima are exact, so the lanes' order
// gives the scalar loop's values (they are read only where every value is
// finite)
__attribute__((target("avx2"))) Reach reach_avx2(const int64_t *dofs, size_t n, const double *U, const double *Uref) {
  const __m256d no_sign = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL)),
                most = _mm256_set1_pd(std::numeric_limits<double>::max());
  __m256d d = _mm256_setzero_pd(), u_max = d, ref_max = d, finite = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256i at = _mm256_loadu_si256(reinterpret_cast<const __m256i *>(dofs + k));
    const __m256d u = _mm256_i64gather_pd(U, at, 8), ur = _mm256_i64gather_pd(Uref, at, 8);
    const __m256d au = _mm256_and_pd(u, no_sign), ar = _mm256_and_pd(ur, no_sign);
    // |x| <= max fails NaN and infinities
    finite = _mm256_and_pd(finite,
                           _mm256_and_pd(_mm256_cmp_pd(au, most, _CMP_LE_OQ), _mm256_cmp_pd(ar, most, _CMP_LE_OQ)));
    d = _mm256_max_pd(d, _mm256_and_pd(u - ur, no_sign));
    u_max = _mm256_max_pd(u_max, au);
    ref_max = _mm256_max_pd(ref_max, ar);
  }
  alignas(32) double lanes[3][4];
  _mm256_store_pd(lanes[0], d), _mm256_store_pd(lanes[1], u_max), _mm256_store_pd(lanes[2], ref_max);
  const bool all_finite = _mm256_movemask_pd(finite) == 0xF;
  _mm256_zeroupper();
  Reach r;
  for (int l = 0; l < 4; ++l) {
    r.d = std::max(r.d, lanes[0][l]);
    r.u_max = std::max(r.u_max, lanes[1][l]);
    r.ref_max = std::max(r.ref_max, lanes[2][l]);
  }
  r.finite = all_finite;
  reach_scalar(dofs, k, n, U, Uref, r);
  return r;
}
#endif
}  // namespace

Reach reach(const std::vector<int64_t> &dofs, const double *U, const double *Uref) {
#ifdef ND_AVX2
  if (simd_on()) return reach_avx2(dofs.data(), dofs.size(), U, Uref);
#endif
  Reach r;
  reach_scalar(dofs.data(), 0, dofs.size(), U, Uref, r);
  return r;
}

bool ContactLaw::certainly_free(const std::vector<double> &U, bool counted) const {
  const size_t nq = cp->size();
  if (!Un || !Pn || Pn->size() != nq || cp->nu.size() != nq) return false;
  // the bound needs a law zero where free and nondecreasing (a bound on P
  // then bounds it): any other is evaluated
  const LawTraits &t = traits();
  if (!t.zero_when_free || !t.nondecreasing) return false;
  // over the DOFs the points' rows touch, usually a small part of U (a pass
  // over the whole of U could cost more than evaluating the points)
  const Reach r = nd::reach(held ? held->dofs : cp->dofs, U.data(), Un);
  if (!r.finite) return false;
  const double d = r.d;
  // the arrays read per point, in locals (the compiler reloaded them at every
  // point: they might alias what the loop writes)
  const double *nu = cp->nu.data(), *Pref = Pn->data(), *g_now = gap ? gap : cp->gap.data(),
               *g_ref = gap_n ? gap_n : cp->gap.data();
  // the reference's test, made once: where it holds, so does every point's below
  if (!held && reach_admitted(r, free_reach_n) && same_gaps(g_now, g_ref, nq)) {
    if (counted) count(counters, &Counters::contact_bounds);
    return true;
  }
  const double reach = r.u_max + r.ref_max + d;
  const BoundTest test{Pref, nu, g_now, g_ref, nullptr, d, reach, 0, false};
  const bool pp = positive_part();
  auto bounded = [&](size_t q) {
    const double h = high_at(test, q);
    if (!std::isfinite(h)) return false;  // (a law may map NaN to 0: not shown)
    double value, slope;
    law(q, h, value, slope, pp);
    return value == 0 && slope == 0;
  };
  if (held) {
    for (int64_t q : held->points)
      if (!bounded(static_cast<size_t>(q))) return false;
  } else if (positive_part()) {
    // [P]_+ and its slope vanish at P <= 0 (law): every point's test, no
    // branch (-max <= h <= 0 also fails NaN and infinities)
    if (!all_within(test, nq)) return false;
  } else {
    // the law vanishes with its slope where P <= 0 and P^n <= 0 under every
    // rule (LawTraits::zero_when_free): that test first, then each point's law
    BoundTest below = test;
    below.x_nonpositive = true;
    if (!all_within(below, nq))
      for (size_t q = 0; q < nq; ++q)
        if (!bounded(q)) return false;
  }
  if (counted) count(counters, &Counters::contact_bounds);
  return true;
}

namespace {
// every point's x_q + c_q max_i |U_i - U_ref_i| + g_ref - g (with the bounds'
// margin) within `limit` (scaled by `scale`), else at most 0: the bound
// from a point reference's values x (its P_q or u_n - g0)
bool within_from_reference(const ContactPoints &cp, const double *U, const double *gap, const PointReference &ref,
                           const std::vector<double> &x, const std::vector<double> &c, const double *scale,
                           double limit, double admitted) {
  const size_t nq = cp.size();
  if (x.size() != nq || c.size() != nq) return false;
  const Reach r = reach(cp.dofs, U, ref.U.data());
  if (!r.finite) return false;
  const double *g_now = gap ? gap : cp.gap.data(), *g_ref = ref.gap.empty() ? cp.gap.data() : ref.gap.data();
  if (reach_admitted(r, admitted) && same_gaps(g_now, g_ref, nq)) return true;  // (the test made once)
  const double reach = r.u_max + r.ref_max + r.d;
  // (false for NaN: not shown)
  return all_within(BoundTest{x.data(), c.data(), g_now, g_ref, scale, r.d, reach, limit, false}, nq);
}
}  // namespace

bool penetration_within(const ContactPoints &cp, const double *U, const double *gap, const PointReference &ref,
                        double limit, const std::vector<double> *length) {
  const std::vector<double> &len = length && !length->empty() ? *length : cp.h;
  if (len.size() != cp.size()) return false;
  // (a reach admitted for a limit is admitted for any larger one: the
  // guard's limit grows with the energy put in)
  const double admitted =
      ref.within_limit > 0 && limit >= ref.within_limit ? ref.within_reach : -std::numeric_limits<double>::infinity();
  return within_from_reference(cp, U, gap, ref, ref.un, cp.a_sum, len.data(), limit, admitted);
}

bool nonpositive_within(const ContactPoints &cp, const double *U, const double *gap, const PointReference &ref) {
  return within_from_reference(cp, U, gap, ref, ref.P, cp.nu, nullptr, 0, ref.free_reach);
}

std::shared_ptr<const Halo> contact_point_halo(const ContactPoints &cp, const Share &rows) {
  if (!cp.share) return nullptr;  // one rank evaluates every point
  const std::vector<int> row_owner = owners(rows, static_cast<int64_t>(rows.order.size()));  // every unknown once
  const int64_t n = static_cast<int64_t>(row_owner.size());
  return make_halo(cp.share, static_cast<int64_t>(cp.size()), [&](int64_t q, std::vector<int> &ranks) {
    for (int64_t i : cp.a[q].idx)  // (s_q has a_q's index list)
      if (i < n && row_owner[i] >= 0) ranks.push_back(row_owner[i]);
  });
}

namespace {
// the unknowns marked, ascending
std::vector<int64_t> marked(const std::vector<char> &read) {
  std::vector<int64_t> held;
  for (size_t i = 0; i < read.size(); ++i)
    if (read[i]) held.push_back(static_cast<int64_t>(i));
  return held;
}
}  // namespace

std::vector<int64_t> point_unknowns(int64_t n, const ContactPoints &cp) {
  std::vector<char> read(static_cast<size_t>(n), 0);
  for (size_t q = 0; q < cp.size(); ++q)
    for (int64_t i : cp.a[q].idx) read[i] = 1;  // (s_q has a_q's index list)
  return marked(read);
}

std::vector<int64_t> rows_and_points(int64_t n, const Share &rows, const ContactPoints &cp, const Csr *A,
                                     const std::vector<const Csr *> &also, const std::vector<int64_t> *points) {
  std::vector<char> read(static_cast<size_t>(n), 0);
  for (const int64_t *i = rows.own_begin(); i != rows.own_end(); ++i) {
    read[*i] = 1;
    if (const int64_t at = A ? A->slot(*i) : -1; at >= 0)
      for (int64_t k = A->ptr[at]; k < A->ptr[at + 1]; ++k) read[A->col[k]] = 1;
  }
  for (const Csr *B : also)
    for (int64_t c : B->col) read[c] = 1;
  auto point = [&](int64_t q) {
    for (int64_t i : cp.a[q].idx) read[i] = 1;  // (s_q has a_q's index list)
  };
  if (points) {
    for (int64_t q : *points) point(q);
  } else {
    for (int64_t q = 0, m = static_cast<int64_t>(cp.size()); q < m; ++q) point(q);
  }
  return marked(read);
}

std::shared_ptr<const HeldPoints> held_points(const ContactPoints &cp, const Halo &halo) {
  auto h = std::make_shared<HeldPoints>();
  std::vector<char> in(cp.size(), 0);
  for (int64_t q : halo.read) in[q] = 1;
  for (size_t q = 0; q < cp.a_fixed.size(); ++q) in[q] |= !cp.a_fixed[q].idx.empty();  // (the reactions')
  std::vector<char> dof;
  for (size_t q = 0; q < in.size(); ++q) {
    if (!in[q]) continue;
    h->points.push_back(static_cast<int64_t>(q));
    for (int64_t i : cp.a[q].idx) {
      if (static_cast<size_t>(i) >= dof.size()) dof.resize(static_cast<size_t>(i) + 1, 0);
      dof[i] = 1;
    }
  }
  for (size_t i = 0; i < dof.size(); ++i)
    if (dof[i]) h->dofs.push_back(static_cast<int64_t>(i));
  return h;
}

void require_shared_index_lists(const ContactPoints &cp) {
  auto check = [](const std::vector<SparseRow> &a, const std::vector<SparseRow> &s, const char *rows) {
    bool same = a.size() == s.size();
    for (size_t q = 0; same && q < a.size(); ++q) {
      if (a[q].idx == s[q].idx && s[q].val.size() == s[q].idx.size() && a[q].val.size() == a[q].idx.size()) continue;
      fail(ND_ERR_INTERNAL, std::string("contact point ") + std::to_string(q) + ": its s_q does not have a_q's " +
                                "index list (" + rows + "), which every pass over the point reads for both");
    }
    if (!same) fail(ND_ERR_INTERNAL, std::string("the contact points have not one s_q per a_q (") + rows + ")");
  };
  check(cp.a, cp.s, "free DOFs");
  check(cp.a_fixed, cp.s_fixed, "clamped DOFs");
}

double p_dot(const ContactPoints &cp, size_t q, const double *v, const int64_t *place) {
  const SparseRow &a = cp.a[q], &s = cp.s[q];  // same index lists
  const double g = cp.gamma[q];
  double sum = 0;
  for (size_t i = 0; i < a.idx.size(); ++i)
    sum += (a.val[i] - g * s.val[i]) * v[place ? place[a.idx[i]] : a.idx[i]];
  return sum;
}

void append_p(const ContactPoints &cp, size_t q, double c, std::vector<int64_t> &idx, std::vector<double> &val) {
  const SparseRow &a = cp.a[q], &s = cp.s[q];  // same index lists
  const double g = cp.gamma[q];
  idx.insert(idx.end(), a.idx.begin(), a.idx.end());
  for (size_t i = 0; i < a.idx.size(); ++i) val.push_back(c * (a.val[i] - g * s.val[i]));
}

void ContactLaw::add_force(const double *U, double kappa, double *y, std::vector<char> *active,
                           std::vector<double> *P, std::vector<double> *un) const {
  if (un) un->clear();
  if (cp->size() == 0) {
    if (active) active->clear();
    if (P) P->clear();
    return;
  }
  std::vector<double> mine;
  std::vector<double> &at = P ? *P : buffers ? buffers->force : mine;
  if (un && P && reads_all()) P_all(U, at, un);  // P_read's pass, u_n - g0 with it
  else P_read(U, at);
  add_force_from(at, kappa, y, active);
}

const std::vector<double> &ContactLaw::P_at(const double *U, const std::vector<double> *P,
                                             std::vector<double> &scratch) const {
  if (P && P->size() == values() && reads_all()) return *P;
  P_all(U, scratch);
  return scratch;
}

void ContactLaw::add_force_from(const std::vector<double> &Pq, double kappa, double *y,
                                std::vector<char> *active) const {
  if (active) active->assign(cp->size(), 0);
  if (cp->m > 1) {  // rank m: the law's values and the blocks of every pair of rows
    double value[3], J[9];
    for_read([&](size_t q) {
      law_m(q, Pq, value, J);
      // (a tangent block of its own: Tresca's sticking points out of contact
      // too, so that the solve does not take A's alone for theirs)
      if (active) {
        bool any = false;
        for (int k = 0; k < cp->m * cp->m; ++k) any = any || J[k] != 0;
        (*active)[q] = any;
      }
      add_blocks(*cp, theta, q, kappa * cp->w[q] / cp->gamma[q], value, y);
    });
    return;
  }
  // a rank-one law's block is phi b_q (inline); any other, the law's own
  const PointLaw *blocks = traits().rank_one ? nullptr : &law_object();
  const bool pp = positive_part();
  for_read([&](size_t q) {
    double value, slope;
    law(q, Pq[q], value, slope, pp);
    if (active) (*active)[q] = slope != 0;
    if (value == 0) return;
    if (!blocks) add_b(*cp, theta, q, kappa * cp->w[q] / cp->gamma[q] * value, y);
    else blocks->add_residual(*cp, theta, q, kappa * cp->w[q] / cp->gamma[q], value, y);
  });
}

void ContactLaw::add_tangent(const double *U, double kappa, Csr &T, const std::vector<double> *P) const {
  count(counters, &Counters::tangent_updates);
  ContactScratch mine;
  ContactScratch &w = buffers ? *buffers : mine;
  if (!P || P->size() != values()) P_read(U, w.tangent), P = &w.tangent;
  if (cp->m > 1) {
    double value[3], J[9];
    for_read([&](size_t q) {
      law_m(q, *P, value, J);
      add_block_tangent(*cp, theta, q, kappa * cp->w[q] / cp->gamma[q], J, T, w.b, w.p);
    });
    return;
  }
  const PointLaw *blocks = traits().rank_one ? nullptr : &law_object();
  const bool pp = positive_part();
  for_read([&](size_t q) {
    double value, slope;
    law(q, (*P)[q], value, slope, pp);
    if (slope == 0) return;
    if (!blocks) add_point_tangent(*cp, theta, q, kappa * cp->w[q] / cp->gamma[q] * slope, T, w.b, w.p);
    else blocks->add_tangent(*cp, theta, q, kappa * cp->w[q] / cp->gamma[q], slope, T, w.b, w.p);
  });
}

}  // namespace nd
