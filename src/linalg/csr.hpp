// Compressed sparse row matrices. Every operator of a problem shares one
// pattern (all DOF pairs of each cell), so values can be combined entrywise.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nd {

struct Csr {
  int64_t n = 0;
  std::vector<int64_t> ptr, col;  // col sorted within each row
  std::vector<double> val;

  // y = A x
  void multiply(const double *x, double *y) const;
  // position of (i, j) in col/val, or -1 if (i, j) is not in the pattern
  int64_t find(int64_t i, int64_t j) const;
  // (idx[i], idx[j]) += f u[i] v[j] for every pair of idx (all in the pattern):
  // the rank-one terms of K_Theta and of the contact tangent
  void add_outer(const std::vector<int64_t> &idx, const double *u, const double *v, double f);
  Csr zeros_like() const {
    Csr z = *this;
    z.val.assign(val.size(), 0.0);
    return z;
  }
};

// A pattern from unsorted, possibly repeated column lists per row.
Csr csr_from_rows(std::vector<std::vector<int64_t>> rows);
// c = a*A + b*B on one pattern
void csr_combine(double a, const Csr &A, double b, const Csr &B, Csr &C);

double dot(int64_t n, const double *x, const double *y);
double norm2(int64_t n, const double *x);

}  // namespace nd
