// The wide (AVX2) forms of common/simd.hpp's kernels have the scalar forms'
// results, bit for bit, and run by default where the CPU has AVX2:
//  - all_finite: false for an inf, -inf or NaN at any place of arrays of 0
//    to 13 entries (the lane groups of four, and the rest after them), true
//    for arrays of finite extremes (+-DBL_MAX, the least subnormal, -0);
//  - the Newmark update (A^{n+1}, V^{n+1}): the same bits for lengths 0 to
//    1,001 and three (beta, gamma, tau), against the header's formulas
//    evaluated here term by term;
//  - combine, (a x + b y) + c z, + 0.0 or nothing: the scalar expressions'
//    bits, signed zeros included (+ 0.0 turns -0 into +0, nothing keeps it).
// (The node-block passes and the contact points' pass are compared with
// their CSR and point-by-point forms in unit_operators and unit_tangent.)
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "common/simd.hpp"
#include "testutil.h"
#include "time/newmark_update.hpp"

namespace {

bool cpu_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

bool same_bits(const std::vector<double> &a, const std::vector<double> &b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

}  // namespace

START_TEST(simd_is_on_where_the_cpu_has_avx2) {
  ck_assert(nd::simd_on() == cpu_avx2());
  ck_assert(nd::set_simd(false));  // (the previous setting: on)
  ck_assert(!nd::simd_on());
  ck_assert(!nd::set_simd(true));
  ck_assert(nd::simd_on() == cpu_avx2());
}
END_TEST

START_TEST(all_finite_finds_every_non_finite_entry) {
  const double bad[] = {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                        std::numeric_limits<double>::quiet_NaN()};
  const double extremes[] = {DBL_MAX, -DBL_MAX, std::numeric_limits<double>::denorm_min(), -0.0, 1.0};
  int checked = 0;
  for (int simd = 0; simd <= 1; ++simd) {
    nd::set_simd(simd == 1);
    for (size_t n = 0; n <= 13; ++n) {
      std::vector<double> x(n);
      for (size_t i = 0; i < n; ++i) x[i] = extremes[i % 5];
      ck_assert_msg(nd::all_finite(x.data(), n), "simd %d n %zu: finite extremes", simd, n);
      for (size_t at = 0; at < n; ++at)
        for (double b : bad) {
          std::vector<double> y = x;
          y[at] = b;
          ck_assert_msg(!nd::all_finite(y.data(), n), "simd %d n %zu: %g at %zu not found", simd, n, b, at);
          ++checked;
        }
    }
  }
  nd::set_simd(true);
  ck_assert_int_eq(checked, 2 * 3 * (13 * 14 / 2));
}
END_TEST

START_TEST(newmark_update_has_the_formulas_bits) {
  const double params[][3] = {{0.25, 0.5, 0.05}, {0.3025, 0.6, 1e-3}, {0.5, 1.0, 0.7}};
  int compared = 0;
  for (const auto &p : params)
    for (size_t n : {0, 1, 3, 4, 5, 17, 1001}) {
      const double beta = p[0], gamma = p[1], tau = p[2];
      nd::State old, next;
      old.U.resize(n), old.V.resize(n), old.A.resize(n), next.U.resize(n);
      for (size_t i = 0; i < n; ++i)  // magnitudes that differ, of both signs
        old.U[i] = std::sin(1.3 * i + 0.2), old.V[i] = 40 * std::cos(0.7 * i), old.A[i] = 1e3 * std::sin(0.37 * i * i),
        next.U[i] = old.U[i] + 1e-3 * std::cos(2.1 * i);
      old.A_valid = true;
      std::vector<double> A(n), V(n);  // the header's formulas, term by term
      for (size_t i = 0; i < n; ++i) {
        A[i] = 1 / (beta * tau * tau) * (next.U[i] - old.U[i]) - old.V[i] / (beta * tau) - (0.5 / beta - 1) * old.A[i];
        V[i] = old.V[i] + tau * ((1 - gamma) * old.A[i] + gamma * A[i]);
      }
      for (int simd = 0; simd <= 1; ++simd) {
        nd::set_simd(simd == 1);
        nd::State s = next;
        nd::newmark_update(beta, gamma, tau, old, s);
        ck_assert_msg(same_bits(s.A, A) && same_bits(s.V, V) && s.A_valid, "simd %d beta %g n %zu: other bits",
                      simd, beta, n);
        ++compared;
      }
    }
  nd::set_simd(true);
  ck_assert_int_eq(compared, 3 * 7 * 2);
}
END_TEST

START_TEST(combine_has_the_expressions_bits) {
  int compared = 0;
  for (size_t n : {0, 1, 3, 4, 5, 17, 1001}) {
    std::vector<double> x(n), y(n), z(n);
    for (size_t i = 0; i < n; ++i)  // every fifth entry: -0 from -0 and -0 products
      x[i] = i % 5 ? std::sin(1.3 * i) : -0.0, y[i] = i % 5 ? 40 * std::cos(0.7 * i) : -0.0,
      z[i] = 1e3 * std::sin(0.37 * i * i);
    const double a = 1.0, b = 0.05, c = 1.25e-3;
    for (int tail = 0; tail < 3; ++tail) {  // c z, + 0.0, nothing
      std::vector<double> expect(n);
      for (size_t i = 0; i < n; ++i)
        expect[i] = tail == 0 ? a * x[i] + b * y[i] + c * z[i] : tail == 1 ? a * x[i] + b * y[i] + 0.0 : a * x[i] + b * y[i];
      if (n >= 5 && tail == 2) ck_assert(std::signbit(expect[0]) && expect[0] == 0);  // a -0 to keep
      if (n >= 5 && tail == 1) ck_assert(!std::signbit(expect[0]));
      for (int simd = 0; simd <= 1; ++simd) {
        nd::set_simd(simd == 1);
        std::vector<double> out(n, 7.0);
        nd::combine(n, a, x.data(), b, y.data(), c, tail == 0 ? z.data() : nullptr, tail == 1, out.data());
        ck_assert_msg(same_bits(out, expect), "simd %d tail %d n %zu: other bits", simd, tail, n);
        ++compared;
      }
    }
  }
  nd::set_simd(true);
  ck_assert_int_eq(compared, 7 * 3 * 2);
}
END_TEST

int main(void) {
  Suite *s = suite_create("simd");
  TCase *tc = tcase_create("simd");
  tcase_add_test(tc, simd_is_on_where_the_cpu_has_avx2);
  tcase_add_test(tc, all_finite_finds_every_non_finite_entry);
  tcase_add_test(tc, newmark_update_has_the_formulas_bits);
  tcase_add_test(tc, combine_has_the_expressions_bits);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
