#include "fast/contact_columns.hpp"

#include <algorithm>
#include <string>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "common/simd.hpp"
#include "nitschedyn.h"
#include "parallel/communicator.hpp"
#include "solve/contact_law.hpp"

namespace nd {

namespace {
// Columns solved together: a block of right-hand sides is what makes a
// multi-right-hand-side solve pay (MUMPS over several ranks), and bounds
// the copy held besides the cache (kBlock n doubles). 16 gets most of what
// larger blocks gain, at half their memory (docs/performance.md, "Columns
// solved together").
constexpr size_t kBlock = 16;
}  // namespace

bool ContactColumns::bind(const ContactPoints &cp, double theta) {
  if (&cp == cp_ && theta == theta_) return false;
  std::vector<std::vector<double>> Z(cp.size());  // allocate first, commit after
  std::vector<int64_t> position(cp.size(), -1), at, place;
  // own rows and the points' DOFs (a distributed state's rows); on one
  // process the points' DOFs alone when the solves make only those
  if (rows_) at = state_rows_ ? *state_rows_ : rows_and_points(n_, *rows_, cp);
  else if (at_rows_ != ColumnRows::Whole) {
    at = point_unknowns(n_, cp);
    const double share = A_factor_.backward_share_at(at);
    if (share >= 1 || (at_rows_ == ColumnRows::Auto && share > kColumnsAtPointsShare)) at.clear();
  }
  if (!at.empty()) {
    place.assign(static_cast<size_t>(n_), -1);
    for (size_t k = 0; k < at.size(); ++k) place[at[k]] = static_cast<int64_t>(k);
  }
  std::vector<std::vector<double>> D(cp.size());
  Z_.swap(Z);
  D_.swap(D);
  position_.swap(position);
  at_.swap(at);
  place_.swap(place);
  held_ = 0;
  G_S_.clear();
  G_.clear();
  cp_ = &cp;
  theta_ = theta;
  keeps_dots_ = dots_ == ColumnDots::Keep || (dots_ == ColumnDots::Auto && static_cast<int64_t>(cp.size()) <= held());
  return true;
}

void ContactColumns::require(const std::vector<int64_t> &S) {
  // The columns' solves over several ranks are collective, each rank with the
  // same set: a set that parted (a bug: every rank evaluates the points on
  // the same bits) would pair the ranks' block solves wrongly, and MUMPS then
  // corrupts memory. One reduction of a digest per call makes it an error.
  if (rows_) {
    Hash h;
    h.vec(S);
    if (!same_on_all_ranks(rows_->comm.get(), h.h))
      fail(ND_ERR_INTERNAL, "the ranks' active contact points differ (" + std::to_string(S.size()) +
                                " on this rank): no contact column was solved");
  }
  int64_t missing = 0;
  for (int64_t q : S) missing += Z_[q].empty();
  if (missing == 0) return;
  if (held_ + missing > max_columns_) {  // drop the columns of the points off S
    std::vector<char> keep(Z_.size(), 0);
    for (int64_t q : S) keep[q] = 1;
    for (size_t q = 0; q < Z_.size(); ++q)
      if (!keep[q] && !Z_[q].empty()) std::vector<double>().swap(Z_[q]), std::vector<double>().swap(D_[q]), --held_;
    G_S_.clear();  // G's entries of dropped points go with them
  }
  // the missing columns kBlock at a time (a backend may solve a block as one)
  std::vector<int64_t> made;
  for (int64_t q : S)
    if (Z_[q].empty()) made.push_back(q);
  const size_t n = static_cast<size_t>(n_), m_held = static_cast<size_t>(held());
  std::vector<double> X, kept;
  for (size_t first = 0; first < made.size(); first += kBlock) {
    const size_t m = std::min(kBlock, made.size() - first);
    X.assign(n * m, 0.0);
    for (size_t j = 0; j < m; ++j) add_b(*cp_, theta_, static_cast<size_t>(made[first + j]), 1.0, &X[j * n]);
    const double *z = X.data();
    if (at_.empty()) {
      A_factor_.solve_many(X.data(), n_, static_cast<int64_t>(m));
    } else {
      kept.resize(m_held * m);
      A_factor_.solve_many_at(X.data(), n_, static_cast<int64_t>(m), at_, kept.data());
      z = kept.data();
    }
    for (size_t j = 0; j < m; ++j) {
      const int64_t q = made[first + j];
      Z_[q].assign(z + j * m_held, z + (j + 1) * m_held);
      ++held_;
      ++computed_;
      if (keeps_dots_) {
        std::vector<double> &D = D_[q];
        D.resize(cp_->size());
        for (size_t i = 0; i < D.size(); ++i) D[i] = p_dot(*cp_, i, column(q), place_.empty() ? nullptr : place_.data());
      }
    }
  }
}

double ContactColumns::dot(size_t q, int64_t j) const {
  const std::vector<double> &D = D_[static_cast<size_t>(j)];
  if (!D.empty()) return D[q];
  return p_dot(*cp_, q, column(j), place_.empty() ? nullptr : place_.data());
}

template <class F>
void ContactColumns::with_rows(F &&f) const {
  if (at_.empty()) return f([](int64_t i) { return i; });
  const int64_t *at = at_.data();
  f([at](int64_t i) { return at[i]; });
}

namespace {
#ifdef ND_AVX2
// x[i] -= (f0 z0[i] + f1 z1[i]) + (f2 z2[i] + f3 z3[i]), i < m, x's rows the
// columns' own (whole columns): four rows at a time, each with the scalar
// expression's bits (no FMA)
__attribute__((target("avx2"))) void subtract4_avx2(int64_t m, const double *const *z, const double *f,
                                                    double *__restrict x) {
  const __m256d f0 = _mm256_set1_pd(f[0]), f1 = _mm256_set1_pd(f[1]), f2 = _mm256_set1_pd(f[2]),
                f3 = _mm256_set1_pd(f[3]);
  const double *__restrict z0 = z[0], *__restrict z1 = z[1], *__restrict z2 = z[2], *__restrict z3 = z[3];
  int64_t i = 0;
  for (; i + 3 < m; i += 4) {
    const __m256d a = _mm256_add_pd(_mm256_mul_pd(f0, _mm256_loadu_pd(z0 + i)), _mm256_mul_pd(f1, _mm256_loadu_pd(z1 + i)));
    const __m256d b = _mm256_add_pd(_mm256_mul_pd(f2, _mm256_loadu_pd(z2 + i)), _mm256_mul_pd(f3, _mm256_loadu_pd(z3 + i)));
    _mm256_storeu_pd(x + i, _mm256_sub_pd(_mm256_loadu_pd(x + i), _mm256_add_pd(a, b)));
  }
  for (; i < m; ++i) x[i] -= (f[0] * z0[i] + f[1] * z1[i]) + (f[2] * z2[i] + f[3] * z3[i]);
  _mm256_zeroupper();
}
#endif
}  // namespace

void ContactColumns::subtract_blocked(const std::vector<int64_t> &S, const double *f, double *__restrict x) const {
  const int64_t m = held(), k = static_cast<int64_t>(S.size());
#ifdef ND_AVX2
  if (at_.empty() && simd_on()) {  // whole columns: the wide form
    int64_t j = 0;
    for (; j + 4 <= k; j += 4) {
      const double *z[4] = {column(S[j]), column(S[j + 1]), column(S[j + 2]), column(S[j + 3])};
      subtract4_avx2(m, z, f + j, x);
    }
    for (; j < k; ++j) {
      const double *__restrict zj = column(S[j]);
      const double fj = f[j];
      for (int64_t i = 0; i < m; ++i) x[i] -= fj * zj[i];
    }
    return;
  }
#endif
  with_rows([&](auto row) {
    int64_t j = 0;
    for (; j + 4 <= k; j += 4) {
      const double *__restrict z0 = column(S[j]), *__restrict z1 = column(S[j + 1]),
                               *__restrict z2 = column(S[j + 2]), *__restrict z3 = column(S[j + 3]);
      const double f0 = f[j], f1 = f[j + 1], f2 = f[j + 2], f3 = f[j + 3];
      for (int64_t i = 0; i < m; ++i) x[row(i)] -= (f0 * z0[i] + f1 * z1[i]) + (f2 * z2[i] + f3 * z3[i]);
    }
    for (; j < k; ++j) {
      const double *__restrict z = column(S[j]);
      const double fj = f[j];
      for (int64_t i = 0; i < m; ++i) x[row(i)] -= fj * z[i];
    }
  });
}

bool ContactColumns::solve_held(double *x, const double *guess) const {
  if (at_.empty() || !rows_) {  // (a sum of columns at the points' DOFs alone is no state: whole)
    A_factor_.solve_from(x, guess);
    return false;
  }
  A_factor_.solve_at(x, n_, at_, guess);
  return true;
}

void ContactColumns::complete(double *x) const {
  if (rows_ && !state_rows_) gather(*rows_, {x});
}

const std::vector<double> &ContactColumns::G(const std::vector<int64_t> &S) {
  if (S == G_S_) return G_;
  const int64_t k = static_cast<int64_t>(S.size()), k_old = static_cast<int64_t>(G_S_.size());
  // what may throw, before anything changes; the last G and S's memory
  // (not their values) reused
  std::vector<double> &Gn = G_next_;
  std::vector<int64_t> &S_copy = G_S_next_;
  Gn.resize(static_cast<size_t>(k * k));
  S_copy.assign(S.begin(), S.end());
  for (int64_t i = 0; i < k_old; ++i) position_[G_S_[i]] = i;
  for (int64_t j = 0; j < k; ++j) {
    const int64_t oj = position_[S[j]];
    for (int64_t i = 0; i < k; ++i) {
      const int64_t oi = position_[S[i]];
      Gn[i + j * k] = oi >= 0 && oj >= 0 ? G_[oi + oj * k_old] : dot(static_cast<size_t>(S[i]), S[j]);
    }
  }
  for (int64_t q : G_S_) position_[q] = -1;
  G_.swap(Gn);
  G_S_.swap(S_copy);
  // the two buffers of each take turns: both hold the larger set's room, so
  // that the sets of a run replayed (a restart) find it whatever their turn
  if (G_next_.capacity() < G_.capacity()) G_next_.reserve(G_.capacity());
  if (G_S_next_.capacity() < G_S_.capacity()) G_S_next_.reserve(G_S_.capacity());
  return G_;
}

}  // namespace nd
