// Sweeps and rank-one modifications of a supernodal LL^T (supernodal.hpp)
#include "linalg/supernodal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "common/simd.hpp"
#include "linalg/backends.hpp"

namespace nd {

SupernodalTree::SupernodalTree(const SupernodalFactor &L) {
  of_column.resize(static_cast<size_t>(L.n));
  parent.assign(static_cast<size_t>(L.count), -1);
  for (int64_t s = 0; s < L.count; ++s)
    for (int64_t j = L.super[s]; j < L.super[s + 1]; ++j) of_column[j] = s;
  for (int64_t s = 0; s < L.count; ++s) {  // the parent holds the first row below the diagonal block
    const SupernodalFactor::Block b = L[s];
    if (b.below > 0) parent[s] = of_column[b.rows[0]];
  }
}

namespace {

// The Fortran BLAS, as CHOLMOD's own solve calls it (its large diagonal
// blocks and the rows below them)
extern "C" {
void dtrsv_(const char *uplo, const char *trans, const char *diag, const int *n, const double *a, const int *lda,
            double *x, const int *incx);
void dgemv_(const char *trans, const int *m, const int *n, const double *alpha, const double *a, const int *lda,
            const double *x, const int *incx, const double *beta, double *y, const int *incy);
}

// The diagonal blocks of at most kCholmodOwnTriangle columns are solved by
// these two loops, wider ones by dtrsv, whose blocked kernels win there
// (the width: docs/performance.md, "Own supernodal solve").
// Both multiply by the diagonal's reciprocals (inv) rather than divide (a
// division's latency sits on the chain from column to column), and L, inv
// and y do not overlap (__restrict: the updates vectorize).
// y = L^{-1} y, L lower triangular, column-major with leading dimension ld
void lower_solve(int cols, const double *__restrict L, int ld, const double *__restrict inv, double *__restrict y) {
  for (int j = 0; j < cols; ++j) {
    const double *__restrict Lj = L + static_cast<int64_t>(j) * ld;
    const double yj = y[j] * inv[j];
    y[j] = yj;
    for (int i = j + 1; i < cols; ++i) y[i] -= Lj[i] * yj;
  }
}
// y = L^{-T} y, L as above: each dot product in four sums (i mod 4), not
// one chain of dependent adds
void lower_transpose_solve(int cols, const double *__restrict L, int ld, const double *__restrict inv,
                           double *__restrict y) {
  for (int j = cols - 1; j >= 0; --j) {
    const double *__restrict Lj = L + static_cast<int64_t>(j) * ld;
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    int i = j + 1;
    for (; i + 3 < cols; i += 4) {
      s0 += Lj[i] * y[i];
      s1 += Lj[i + 1] * y[i + 1];
      s2 += Lj[i + 2] * y[i + 2];
      s3 += Lj[i + 3] * y[i + 3];
    }
    for (; i < cols; ++i) s0 += Lj[i] * y[i];
    y[j] = (y[j] - ((s0 + s1) + (s2 + s3))) * inv[j];
  }
}

const int kOne = 1;
const double kMinusOne = -1.0, kPlusOne = 1.0;

// One column of rank-one modifications (the LINPACK recurrence, sign +1
// an update, -1 a downdate), for each vector in turn: with a = L(j, j) and
// v_j the vector's entry there, r = sqrt(a^2 +- v_j^2), c = r / a,
// s = v_j / a; L(j, j) <- r; below the diagonal L <- (L +- s v) / c and
// v <- c v - s L (the new L). A vector's rotation reads only the diagonal
// and its own v_j, which the rotations before it in the column leave: all
// are made first, then applied two by two in one pass over the column, at
// each entry in the vectors' order (the bits of one vector's pass after the
// other's, with the column read and written half as often). Each entry on
// its own: the wide form (four entries at a time, no FMA) has the scalar
// form's bits.
struct Rotation {
  double c, s, signed_s, inv_c;
};
// entry t of the column, l, and of the vector, v: one rotation
inline double rotated(const Rotation &g, double l, double &v) {
  const double out = (l + g.signed_s * v) * g.inv_c;
  v = g.c * v - g.s * out;
  return out;
}
// entries [from, len) of col and v (one rotation) or of col, v and w (g, then h)
void rotate(const Rotation &g, double *__restrict col, double *__restrict v, int from, int len) {
  for (int t = from; t < len; ++t) col[t] = rotated(g, col[t], v[t]);
}
void rotate(const Rotation &g, const Rotation &h, double *__restrict col, double *__restrict v,
            double *__restrict w, int from, int len) {
  for (int t = from; t < len; ++t) col[t] = rotated(h, rotated(g, col[t], v[t]), w[t]);
}
#ifdef ND_AVX2
struct WideRotation {
  __m256d c, s, signed_s, inv_c;
  __attribute__((target("avx2"))) explicit WideRotation(const Rotation &g)
      : c(_mm256_set1_pd(g.c)), s(_mm256_set1_pd(g.s)), signed_s(_mm256_set1_pd(g.signed_s)),
        inv_c(_mm256_set1_pd(g.inv_c)) {}
  // four entries of `rotated`: l and v at their place
  __attribute__((target("avx2"))) __m256d at(__m256d l, double *v) const {
    const __m256d vt = _mm256_loadu_pd(v);
    const __m256d out = _mm256_mul_pd(_mm256_add_pd(l, _mm256_mul_pd(signed_s, vt)), inv_c);
    _mm256_storeu_pd(v, _mm256_sub_pd(_mm256_mul_pd(c, vt), _mm256_mul_pd(s, out)));
    return out;
  }
};
// rows [1, from) one by one, then four at a time from `from` (where the
// vectors' entries, and the column's, start a 32-byte line: see
// modify_column)
__attribute__((target("avx2"))) void rotate_avx2(const Rotation &g, double *__restrict col, double *__restrict v,
                                                 int from, int len) {
  const WideRotation G(g);
  rotate(g, col, v, 1, std::min(from, len));
  int t = from;
  for (; t + 3 < len; t += 4) _mm256_storeu_pd(col + t, G.at(_mm256_loadu_pd(col + t), v + t));
  rotate(g, col, v, t, len);
  _mm256_zeroupper();
}
__attribute__((target("avx2"))) void rotate_avx2(const Rotation &g, const Rotation &h, double *__restrict col,
                                                 double *__restrict v, double *__restrict w, int from, int len) {
  const WideRotation G(g), H(h);
  rotate(g, h, col, v, w, 1, std::min(from, len));
  int t = from;
  for (; t + 3 < len; t += 4) _mm256_storeu_pd(col + t, H.at(G.at(_mm256_loadu_pd(col + t), v + t), w + t));
  rotate(g, h, col, v, w, t, len);
  _mm256_zeroupper();
}
#endif
// column `col` (from its diagonal, len entries) modified by the r vectors
// v[u] (each from the same row on), inv_diag kept 1 / L(j, j); a vector
// whose entry at the diagonal is zero changes nothing (c = 1, s = 0) and is
// skipped. false: a pivot r^2 not positive and finite (nothing applied
// below the diagonal then).
// The wide passes read and write the vectors and the column four entries
// at a time; where those straddle two 64-byte lines (a 32-byte access at an
// address not a multiple of 32: three in four of them, as CHOLMOD's columns
// and the vectors fell), each costs two accesses, and the rotations run
// markedly slower than aligned (docs/performance.md, "Aligned rotations").
// So the vectors are laid out with their rows in step
// (SupernodalModifier::modify: each at a 32-byte
// boundary, their length a multiple of four), the first rows up to the
// vectors' next boundary are rotated one by one, and with enough vectors to
// pay for it (kCopiedFrom) the column is copied in step with them into
// `scratch` and back. The same operations on each entry: the same bits.
constexpr int kCopiedFrom = 8;
bool modify_column(double sign, double *__restrict col, double *const *v, int r, int len, double &inv_diag,
                   double *scratch, int64_t &rotated) {
  Rotation g[SupernodalModifier::kBatch];
  double *vs[SupernodalModifier::kBatch];
  int m = 0;
  double a = col[0];
  for (int u = 0; u < r; ++u) {
    const double vj = v[u][0];
    if (vj == 0) continue;
    // a downdate's a^2 - v_j^2 as (a - v_j)(a + v_j): no cancellation of two squares
    const double r2 = sign > 0 ? a * a + vj * vj : (a - vj) * (a + vj);
    if (!(r2 > 0) || !std::isfinite(r2)) return false;
    const double rr = std::sqrt(r2), su = vj / a;
    g[m] = Rotation{rr / a, su, sign * su, a / rr};
    vs[m++] = v[u];
    a = rr;
  }
  if (m == 0) return true;
  rotated += static_cast<int64_t>(m) * len;
  col[0] = a;
  inv_diag = 1.0 / a;
#ifdef ND_AVX2
  if (simd_on()) {
    // the vectors' first row at a 32-byte boundary (all alike), and the column in step
    const int phase = static_cast<int>((reinterpret_cast<uintptr_t>(vs[0]) / sizeof(double)) % 4);
    const int from = 4 - phase;  // the first row t >= 1 with phase + t a multiple of four
    double *c = col;
    if (m >= kCopiedFrom) {
      c = scratch + phase;
      std::copy(col + 1, col + len, c + 1);
    }
    for (int u = 0; u < m; u += 2) {
      if (u + 1 < m) rotate_avx2(g[u], g[u + 1], c, vs[u], vs[u + 1], from, len);
      else rotate_avx2(g[u], c, vs[u], from, len);
    }
    if (c != col) std::copy(c + 1, c + len, col + 1);
    return true;
  }
#endif
  for (int u = 0; u < m; u += 2) {
    if (u + 1 < m) rotate(g[u], g[u + 1], col, vs[u], vs[u + 1], 1, len);
    else rotate(g[u], col, vs[u], 1, len);
  }
  return true;
}

// The supernodes on the paths from the columns `first` to the root, ascending
// (a child before its parent)
void union_of_paths(const SupernodalTree &tree, const std::vector<int64_t> &first, std::vector<char> &marked,
                    std::vector<int64_t> &out) {
  out.clear();
  for (int64_t j : first)
    for (int64_t s = tree.of_column[j]; s >= 0 && !marked[s]; s = tree.parent[s]) marked[s] = 1, out.push_back(s);
  std::sort(out.begin(), out.end());
  for (int64_t s : out) marked[s] = 0;
}

}  // namespace

void supernodal_forward(const SupernodalFactor &L, const SupernodalTree &tree, const double *inv, const double *x,
                        std::vector<double> &y, std::vector<char> &reached, std::vector<double> &e) {
  std::fill(reached.begin(), reached.end(), 0);
  for (int64_t c = 0; c < L.n; ++c) {  // y = P x, and the supernodes its nonzeros reach
    y[c] = x[L.perm[c]];
    if (y[c] != 0) tree.mark_path(c, reached);
  }
  for (int64_t s = 0; s < L.count; ++s) {  // y = L^{-1} y over those (a parent comes after its children)
    if (!reached[s]) continue;
    const SupernodalFactor::Block b = L[s];
    double *ys = y.data() + b.first;
    for (int i = 0; i < b.below; ++i) e[i] = y[b.rows[i]];
    if (b.cols <= kCholmodOwnTriangle) lower_solve(b.cols, b.L, b.ld, inv + b.first, ys);
    else dtrsv_("L", "N", "N", &b.cols, b.L, &b.ld, ys, &kOne);
    if (b.below > 0) {
      dgemv_("N", &b.below, &b.cols, &kMinusOne, b.L + b.cols, &b.ld, ys, &kOne, &kPlusOne, e.data(), &kOne);
      for (int i = 0; i < b.below; ++i) y[b.rows[i]] = e[i];
    }
  }
}

void supernodal_backward(const SupernodalFactor &L, const double *inv, std::vector<double> &y,
                         std::vector<double> &e, const std::vector<char> *needed) {
  for (int64_t s = L.count - 1; s >= 0; --s) {
    if (needed && !(*needed)[s]) continue;
    const SupernodalFactor::Block b = L[s];
    double *ys = y.data() + b.first;
    for (int i = 0; i < b.below; ++i) e[i] = y[b.rows[i]];
    if (b.below > 0)
      dgemv_("C", &b.below, &b.cols, &kMinusOne, b.L + b.cols, &b.ld, e.data(), &kOne, &kPlusOne, ys, &kOne);
    if (b.cols <= kCholmodOwnTriangle) lower_transpose_solve(b.cols, b.L, b.ld, inv + b.first, ys);
    else dtrsv_("L", "C", "N", &b.cols, b.L, &b.ld, ys, &kOne);
  }
}

bool SupernodalModifier::modify(const SupernodalFactor &L, const SupernodalTree &tree, double *inv, bool add,
                                const int64_t *ptr, const int64_t *rows, const double *vals, int64_t k) {
  // w_'s width: the widest batch met so far (a power of two), so that a
  // scene whose calls carry few vectors holds no more than it uses
  int width = std::max(width_, 4);
  while (width < std::min<int64_t>(kBatch, k)) width *= 2;
  if (width != width_ || w_.size() != static_cast<size_t>(L.n) * width) {
    width_ = width;
    w_.assign(static_cast<size_t>(L.n) * width_, 0.0);
  }
  if (marked_.size() != static_cast<size_t>(L.count)) marked_.assign(static_cast<size_t>(L.count), 0);
  const double sign = add ? 1.0 : -1.0;
  std::vector<int64_t> &first = first_;  // (its memory kept from call to call)
  for (int64_t j0 = 0; j0 < k; j0 += kBatch) {  // the vectors kBatch at a time
    const int r = static_cast<int>(std::min<int64_t>(kBatch, k - j0));
    first.clear();
    for (int t = 0; t < r; ++t) {
      const int64_t *rt = rows + ptr[j0 + t], m = ptr[j0 + t + 1] - ptr[j0 + t];
      int64_t j = L.n;
      for (int64_t e = 0; e < m; ++e) j = std::min(j, rt[e]);
      if (j == L.n) continue;  // no entry
      // every row in column j's structure: then so are the modification's (no fill)
      const SupernodalFactor::Block b = L[tree.of_column[j]];
      const int64_t last = b.first + b.cols;  // the diagonal block's rows end there
      for (int64_t e = 0; e < m; ++e)
        if (rt[e] >= last && !std::binary_search(b.rows, b.rows + b.below, rt[e])) {
          clear(L, tree, first);
          return false;
        }
      for (int64_t e = 0; e < m; ++e) w_[rt[e] * width_ + t] = vals[ptr[j0 + t] + e];
      first.push_back(j);
    }
    union_of_paths(tree, first, marked_, path_);
    for (int64_t s : path_) {
      const SupernodalFactor::Block b = L[s];
      int c0 = b.cols;  // the first column a vector has an entry at
      for (int t = 0; t < b.cols && c0 == b.cols; ++t)
        for (int u = 0; u < r; ++u)
          if (w_[(b.first + t) * width_ + u] != 0) c0 = t;
      const int len = b.ld - c0;
      // the vectors at the block's rows from column c0's diagonal on, one
      // after the other, each from a 32-byte boundary (modify_column): their
      // stride a multiple of four entries, and not of 512 (4 KB: a vector's
      // stores and the next one's loads would share their addresses' low
      // bits, which the CPU takes for a dependence)
      size_t stride = (static_cast<size_t>(len) + 3) / 4 * 4;
      if (stride % 512 == 0) stride += 4;
      // then the scratch column (up to 3 + len entries), and 3 entries to reach the first boundary
      const size_t vectors = stride * static_cast<size_t>(r);
      if (v_.size() < vectors + stride + 6) v_.resize(vectors + stride + 6);
      double *vb = v_.data() + (4 - (reinterpret_cast<uintptr_t>(v_.data()) / sizeof(double)) % 4) % 4;
      double *scratch = vb + vectors;
      auto row_at = [&](int i) { return i < b.cols - c0 ? b.first + c0 + i : b.rows[i - (b.cols - c0)]; };
      for (int i = 0; i < len; ++i) {
        const int64_t at = row_at(i) * width_;
        for (int u = 0; u < r; ++u) vb[u * stride + i] = w_[at + u], w_[at + u] = 0;
      }
      bool ok = true;
      double *v[kBatch];
      for (int c = c0; ok && c < b.cols; ++c) {
        for (int u = 0; u < r; ++u) v[u] = vb + u * stride + (c - c0);
        ok = modify_column(sign, b.L + static_cast<int64_t>(c) * b.ld + c, v, r, b.ld - c, inv[b.first + c], scratch,
                           rotated_);
      }
      if (!ok) {
        clear(L, tree, first);
        return false;
      }
      for (int i = b.cols - c0; i < len; ++i) {
        const int64_t at = row_at(i) * width_;
        for (int u = 0; u < r; ++u) w_[at + u] = vb[u * stride + i];
      }
    }
  }
  return true;
}

void SupernodalModifier::clear(const SupernodalFactor &L, const SupernodalTree &tree,
                               const std::vector<int64_t> &first) {
  for (int64_t j : first)
    for (int64_t s = tree.of_column[j]; s >= 0; s = tree.parent[s]) {
      const SupernodalFactor::Block b = L[s];
      for (int t = 0; t < b.cols; ++t) std::fill_n(w_.begin() + (b.first + t) * width_, width_, 0.0);
    }
  // (a vector's rows are on its path: its first row's column and ancestors)
}

std::vector<double> supernodal_paths(const SupernodalFactor &L) {
  std::vector<double> path(static_cast<size_t>(L.n), 0.0);
  for (int64_t s = L.count - 1; s >= 0; --s) {  // a parent comes after its children
    const SupernodalFactor::Block b = L[s];
    double above = b.below > 0 ? path[b.rows[0]] : 0.0;
    for (int c = b.cols - 1; c >= 0; --c) {
      above += static_cast<double>(b.ld - c);
      path[b.first + c] = above;
    }
  }
  return path;
}

}  // namespace nd
