// Compressed sparse row matrices. Every operator of a problem shares one
// pattern (all DOF pairs of each cell), so values can be combined entrywise.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/row_set.hpp"

namespace nd {

// An index array that the operators of one pattern share (M, K, K_Theta,
// A = c M + K_Theta, and any copy of them): read as a const vector; written
// through mut(), which first copies it if another matrix shares it. One
// copy instead of four: less memory, and no copy to make.
class SharedIndex {
 public:
  SharedIndex() : v_(std::make_shared<std::vector<int64_t>>()) {}
  size_t size() const { return v_->size(); }
  const int64_t &operator[](size_t i) const { return (*v_)[i]; }
  const int64_t *data() const { return v_->data(); }
  std::vector<int64_t>::const_iterator begin() const { return v_->cbegin(); }
  std::vector<int64_t>::const_iterator end() const { return v_->cend(); }
  const std::vector<int64_t> &vec() const { return *v_; }
  // the array to write (its own, copied first when shared)
  std::vector<int64_t> &mut() {
    if (v_.use_count() > 1) v_ = std::make_shared<std::vector<int64_t>>(*v_);
    return *v_;
  }
  bool shared_with(const SharedIndex &o) const { return v_ == o.v_; }
  bool operator==(const SharedIndex &o) const { return v_ == o.v_ || *v_ == *o.v_; }

 private:
  std::shared_ptr<std::vector<int64_t>> v_;
};

struct Csr {
  int64_t n = 0;         // rows and columns
  SharedIndex ptr, col;  // col sorted within each row
  std::vector<double> val;
  // A part of an operator (a rank's own rows, or the rows its own cells
  // touch) stores only the rows of `held`, ascending: ptr has held.size() + 1
  // entries, not n + 1, so its row pointers fall with the ranks.
  // Its columns keep the whole numbering. Not a part: every row, ptr n + 1.
  bool part = false;
  std::vector<int64_t> held;  // (part) the rows stored
  int64_t stored() const { return part ? static_cast<int64_t>(held.size()) : n; }
  int64_t row_at(int64_t s) const { return part ? held[s] : s; }  // the row stored at s
  int64_t slot(int64_t i) const;                                   // row i's place, -1 if not stored
  // A pass over the rows of `rows`: f(r, i, begin, end) for the r-th, row i,
  // whose entries are [begin, end). A part reads rows[r] at place r (`rows`
  // must then be its held rows, checked: ND_ERR_INTERNAL), any other matrix
  // at row i; one loop for each, so neither chooses per row. f is called
  // from both loops: mark it __attribute__((always_inline)), or GCC at -O2
  // calls it per row, which slows the hottest passes markedly.
  template <class F>
  void for_rows(RowSet rows, F &&f) const {
    const int64_t m = rows.size(n);
    if (part) {
      require_places(rows);
      for (int64_t r = 0; r < m; ++r) f(r, rows[r], ptr[r], ptr[r + 1]);
    } else {
      for (int64_t r = 0; r < m; ++r) {
        const int64_t i = rows[r];
        f(r, i, ptr[i], ptr[i + 1]);
      }
    }
  }
  // a part's pass must be over its held rows (else ND_ERR_INTERNAL)
  void require_places(RowSet rows) const;

  // y = A x (each row's even and odd entries summed apart, then added), on
  // the rows of `rows` (the others of y untouched)
  void multiply(const double *x, double *y, RowSet rows = {}) const;
  // position of (i, j) in col/val, or -1 if (i, j) is not in the pattern
  int64_t find(int64_t i, int64_t j) const;
  // (idx[i], idx[j]) += f u[i] v[j] for every pair of idx (each must be in
  // the pattern, else ND_ERR_INTERNAL naming the entry: never written into
  // a neighbour's place; the matrix is then half updated, a bug to report):
  // the rank-one terms of K_Theta and of the contact tangent. Rows without
  // entries are left out: a matrix of a rank's own rows holds no others (a
  // whole matrix has every row's diagonal)
  void add_outer(const std::vector<int64_t> &idx, const double *u, const double *v, double f);
  Csr zeros_like() const {
    Csr z = *this;
    z.val.assign(val.size(), 0.0);
    return z;
  }
};

// A pattern from unsorted, possibly repeated column lists per row.
Csr csr_from_rows(std::vector<std::vector<int64_t>> rows);
// throws ND_ERR_INTERNAL unless A and B have the same shape (operators of one problem share their pattern)
void require_same_pattern(const Csr &A, const Csr &B);
// f(i, (A x)_i, (B y)_i) for every row of `rows`, in one pass over the pattern A and
// B share, without storing either: both products in one SSE2 multiply-add
// per entry, even and odd entries of a row in separate sums (two chains of
// dependent adds, as in Csr::multiply: the same bits as it)
template <class F>
void multiply_pair(const Csr &A, const double *x, const Csr &B, const double *y, F &&f, RowSet rows = {}) {
  require_same_pattern(A, B);
  typedef double Pair __attribute__((vector_size(16)));
  const double *a = A.val.data(), *b = B.val.data();
  const int64_t *col = A.col.data();
  A.for_rows(rows, [&](int64_t, int64_t i, int64_t k, int64_t e) __attribute__((always_inline)) {
    Pair s = {0, 0}, s1 = {0, 0};
    for (; k + 1 < e; k += 2) {
      const int64_t c = col[k], c1 = col[k + 1];
      s += Pair{a[k], b[k]} * Pair{x[c], y[c]};
      s1 += Pair{a[k + 1], b[k + 1]} * Pair{x[c1], y[c1]};
    }
    if (k < e) s += Pair{a[k], b[k]} * Pair{x[col[k]], y[col[k]]};
    s += s1;
    f(i, s[0], s[1]);
  });
}
// c = a*A + b*B on one pattern
void csr_combine(double a, const Csr &A, double b, const Csr &B, Csr &C);

double dot(int64_t n, const double *x, const double *y);
double norm2(int64_t n, const double *x);

}  // namespace nd
