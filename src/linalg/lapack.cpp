#include "linalg/lapack.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace nd::lapack {
namespace {

// out = in as a column-major matrix, in row-major n x n (LAPACKE_dge_trans)
void transpose(lapack_int n, const double *in, double *out) {
  for (lapack_int i = 0; i < n; ++i)
    for (lapack_int j = 0; j < n; ++j) out[i + static_cast<std::ptrdiff_t>(j) * n] = in[static_cast<std::ptrdiff_t>(i) * n + j];
}

// whether the upper triangle of the row-major n x n matrix A is finite
bool upper_finite(lapack_int n, const double *A) {
  for (lapack_int i = 0; i < n; ++i)
    for (lapack_int j = i; j < n; ++j)
      if (!std::isfinite(A[static_cast<std::ptrdiff_t>(i) * n + j])) return false;
  return true;
}

// LAPACKE's rounding of a workspace query to a size
lapack_int work_size(double query) { return std::max<lapack_int>(1, static_cast<lapack_int>(query)); }

}  // namespace

lapack_int dsyev_row_major(char jobz, lapack_int m, double *A, double *w) {
  if (m <= 0) return m < 0 ? -4 : 0;
  if (!upper_finite(m, A)) return -5;
  std::vector<double> a(static_cast<size_t>(m) * static_cast<size_t>(m));
  double query = 0;
  lapack_int info = LAPACKE_dsyev_work(LAPACK_COL_MAJOR, jobz, 'U', m, a.data(), m, w, &query, -1);
  if (info != 0) return info;
  std::vector<double> work(static_cast<size_t>(work_size(query)));
  transpose(m, A, a.data());
  info = LAPACKE_dsyev_work(LAPACK_COL_MAJOR, jobz, 'U', m, a.data(), m, w, work.data(),
                            static_cast<lapack_int>(work.size()));
  transpose(m, a.data(), A);  // (a col-major matrix read row-major is its transpose)
  return info;
}

lapack_int dsygv_values_row_major(lapack_int itype, lapack_int n, double *A, double *B, double *w) {
  if (n <= 0) return n < 0 ? -5 : 0;
  if (!upper_finite(n, A)) return -6;
  if (!upper_finite(n, B)) return -8;
  std::vector<double> a(static_cast<size_t>(n) * static_cast<size_t>(n)), b(a.size());
  double query = 0;
  lapack_int info =
      LAPACKE_dsygv_work(LAPACK_COL_MAJOR, itype, 'N', 'U', n, a.data(), n, b.data(), n, w, &query, -1);
  if (info != 0) return info;
  std::vector<double> work(static_cast<size_t>(work_size(query)));
  transpose(n, A, a.data());
  transpose(n, B, b.data());
  info = LAPACKE_dsygv_work(LAPACK_COL_MAJOR, itype, 'N', 'U', n, a.data(), n, b.data(), n, w, work.data(),
                            static_cast<lapack_int>(work.size()));
  transpose(n, a.data(), A);
  transpose(n, b.data(), B);
  return info;
}

lapack_int dstev(char jobz, lapack_int n, double *d, double *e, double *z, lapack_int ldz) {
  if (n <= 0) return n < 0 ? -2 : 0;
  for (lapack_int i = 0; i < n; ++i)
    if (!std::isfinite(d[i])) return -4;
  for (lapack_int i = 0; i + 1 < n; ++i)
    if (!std::isfinite(e[i])) return -5;
  const bool vectors = jobz == 'V' || jobz == 'v';
  std::vector<double> work(static_cast<size_t>(vectors ? std::max<lapack_int>(1, 2 * n - 2) : 1));
  return LAPACKE_dstev_work(LAPACK_COL_MAJOR, jobz, n, d, e, z, ldz, work.data());
}

}  // namespace nd::lapack
