// The wide (AVX2) forms of the hottest passes (linalg/node_blocks.hpp, the
// contact points' pass in solve/contact_law.cpp, the Newmark update,
// all_finite): chosen at run time, where
// the CPU has AVX2, and with the bits of the scalar forms (each lane one of
// their sums, added in the same order; no FMA, which rounds once).
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

}  // namespace nd
