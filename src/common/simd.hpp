// The wide (AVX2) forms of the hottest passes (linalg/node_blocks.hpp, the
// contact points' pass in solve/contact_law.cpp, the Newmark update,
// all_finite, the updated factor's rotations in linalg/supernodal.cpp, the
// sums of contact columns in fast/contact_columns.cpp):
// chosen at run time, where
// the CPU has AVX2, and with the bits of the scalar forms (each lane one of
// their sums, added in the same order; no FMA, which rounds once). Each
// ends with _mm256_zeroupper(): GCC does not always put it there, and SSE
// code (CHOLMOD's, the BLAS's) after a wide form that left the registers'
// upper halves set runs much slower (docs/performance.md, "AVX2").
#pragma once
#include <cstddef>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define ND_AVX2 1
#endif

namespace nd {

// whether the wide forms run: the CPU has AVX2 and no one turned them off
bool simd_on();
// set_simd(false) turns them off (tests compare the two forms' bits);
// returns the previous setting
bool set_simd(bool on);

// every x[0 .. n) finite (not inf, not NaN), without a branch per entry
bool all_finite(const double *x, size_t n);

// out[i] = (a x[i] + b y[i]) + t_i, i < n, with t_i = c z[i] where z is not
// null, else +0.0 where plus_zero (which turns a -0 into +0), else no term:
// the scalar expressions' bits (the predictor, the mass combinations of the
// right-hand sides)
void combine(size_t n, double a, const double *x, double b, const double *y, double c, const double *z, bool plus_zero,
             double *out);

}  // namespace nd
