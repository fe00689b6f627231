#include "time/newmark_update.hpp"

#include <cstddef>

#include "common/simd.hpp"

namespace nd {

namespace {

struct Coefficients {
  double c, bt, k, tau, g1, g;  // 1/(beta tau^2), beta tau, 1/(2 beta) - 1, tau, 1 - gamma, gamma
};

// rows [from, n): the formulas of the header, term by term
void update_rows(const Coefficients &k, size_t from, size_t n, const double *U1, const double *U0, const double *V0,
                 const double *A0, double *A1, double *V1) {
  for (size_t i = from; i < n; ++i) {
    A1[i] = k.c * (U1[i] - U0[i]) - V0[i] / k.bt - k.k * A0[i];
    V1[i] = V0[i] + k.tau * (k.g1 * A0[i] + k.g * A1[i]);
  }
}

#ifdef ND_AVX2
__attribute__((target("avx2"))) void update_avx2(const Coefficients &k, size_t n, const double *U1,
                                                 const double *U0, const double *V0, const double *A0, double *A1,
                                                 double *V1) {
  const __m256d c = _mm256_set1_pd(k.c), bt = _mm256_set1_pd(k.bt), kk = _mm256_set1_pd(k.k),
                tau = _mm256_set1_pd(k.tau), g1 = _mm256_set1_pd(k.g1), g = _mm256_set1_pd(k.g);
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    const __m256d v0 = _mm256_loadu_pd(V0 + i), a0 = _mm256_loadu_pd(A0 + i);
    const __m256d a1 = c * (_mm256_loadu_pd(U1 + i) - _mm256_loadu_pd(U0 + i)) - v0 / bt - kk * a0;
    _mm256_storeu_pd(A1 + i, a1);
    _mm256_storeu_pd(V1 + i, v0 + tau * (g1 * a0 + g * a1));
  }
  _mm256_zeroupper();
  update_rows(k, i, n, U1, U0, V0, A0, A1, V1);
}
#endif

}  // namespace

void newmark_velocity(double gamma, double tau, const State &old, State &next) {
  next.V.resize(old.U.size());
  for (size_t i = 0; i < next.V.size(); ++i)
    next.V[i] = old.V[i] + tau * ((1 - gamma) * old.A[i] + gamma * next.A[i]);
}

void newmark_update(double beta, double gamma, double tau, const State &old, State &next) {
  const size_t n = old.U.size();
  next.A.resize(n);
  next.V.resize(n);
  next.A_valid = true;
  const Coefficients k{1 / (beta * tau * tau), beta * tau, 0.5 / beta - 1, tau, 1 - gamma, gamma};
  const double *U1 = next.U.data(), *U0 = old.U.data(), *V0 = old.V.data(), *A0 = old.A.data();
#ifdef ND_AVX2
  if (simd_on()) return update_avx2(k, n, U1, U0, V0, A0, next.A.data(), next.V.data());
#endif
  update_rows(k, 0, n, U1, U0, V0, A0, next.A.data(), next.V.data());
}

}  // namespace nd
