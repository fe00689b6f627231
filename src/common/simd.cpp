#include "common/simd.hpp"

#include <atomic>
#include <cmath>
#include <limits>

namespace nd {

namespace {
#ifdef ND_AVX2
const bool cpu_has_avx2 = __builtin_cpu_supports("avx2");
#else
const bool cpu_has_avx2 = false;
#endif
std::atomic<bool> enabled{true};
}  // namespace

bool simd_on() { return cpu_has_avx2 && enabled.load(std::memory_order_relaxed); }

bool set_simd(bool on) { return enabled.exchange(on); }

namespace {
// |x| <= max is false for inf and NaN (as int: & of two bools reads as a mistaken &&)
int finite_from(const double *x, size_t from, size_t n) {
  int ok = 1;
  for (size_t i = from; i < n; ++i) ok &= std::fabs(x[i]) <= std::numeric_limits<double>::max();
  return ok;
}

#ifdef ND_AVX2
__attribute__((target("avx2"))) bool all_finite_avx2(const double *x, size_t n) {
  const __m256d max = _mm256_set1_pd(std::numeric_limits<double>::max());
  const __m256d abs = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffff));
  __m256d ok = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
  size_t i = 0;
  for (; i + 4 <= n; i += 4) ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_and_pd(_mm256_loadu_pd(x + i), abs), max, _CMP_LE_OQ));
  const bool wide = _mm256_movemask_pd(ok) == 0xf;
  _mm256_zeroupper();
  return wide && finite_from(x, i, n);
}
#endif
}  // namespace

namespace {
// rows [from, n) of combine
void combine_rows(size_t from, size_t n, double a, const double *x, double b, const double *y, double c, const double *z,
                  bool plus_zero, double *out) {
  if (z)
    for (size_t i = from; i < n; ++i) out[i] = a * x[i] + b * y[i] + c * z[i];
  else if (plus_zero)
    for (size_t i = from; i < n; ++i) out[i] = a * x[i] + b * y[i] + 0.0;
  else
    for (size_t i = from; i < n; ++i) out[i] = a * x[i] + b * y[i];
}

#ifdef ND_AVX2
__attribute__((target("avx2"))) void combine_avx2(size_t n, double a, const double *x, double b, const double *y,
                                                  double c, const double *z, bool plus_zero, double *out) {
  const __m256d va = _mm256_set1_pd(a), vb = _mm256_set1_pd(b), vc = _mm256_set1_pd(c);
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    __m256d v = va * _mm256_loadu_pd(x + i) + vb * _mm256_loadu_pd(y + i);
    if (z) v += vc * _mm256_loadu_pd(z + i);
    else if (plus_zero) v += _mm256_setzero_pd();
    _mm256_storeu_pd(out + i, v);
  }
  _mm256_zeroupper();
  combine_rows(i, n, a, x, b, y, c, z, plus_zero, out);
}
#endif
}  // namespace

void combine(size_t n, double a, const double *x, double b, const double *y, double c, const double *z, bool plus_zero,
             double *out) {
#ifdef ND_AVX2
  if (simd_on()) return combine_avx2(n, a, x, b, y, c, z, plus_zero, out);
#endif
  combine_rows(0, n, a, x, b, y, c, z, plus_zero, out);
}

bool all_finite(const double *x, size_t n) {
#ifdef ND_AVX2
  if (simd_on()) return all_finite_avx2(x, n);
#endif
  return finite_from(x, 0, n);
}

}  // namespace nd
