// The BLAS thread scope inside the C API's barrier: during a call the BLAS
// runs at the library's limit, nested calls keep it, the last one restores
// the caller's count; limit 0 leaves the BLAS alone. Needs OpenBLAS in the
// process to observe counts (said on stdout when absent).
#include <dlfcn.h>

#include <cstdio>

#include "capi/guard.hpp"
#include "linalg/blas_threads.hpp"
#include "testutil.h"

namespace {
int (*blas_get)();
void (*blas_set)(int);

bool have_openblas() {
  blas_get = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  blas_set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!blas_get || !blas_set) std::printf("no OpenBLAS in this process: the thread counts are not observed\n");
  return blas_get && blas_set;
}
}  // namespace

START_TEST(a_call_runs_at_the_limit_nested_calls_too) {
  if (!have_openblas()) return;
  ck_assert_str_eq(nd::blas_thread_control(), "OpenBLAS");
  blas_set(2);
  int outer = 0, inner = 0, after_inner = 0;
  const int status = nd::guarded("outer", [&] {
    outer = blas_get();
    nd::guarded("inner", [&] {
      inner = blas_get();
      return ND_OK;
    });
    after_inner = blas_get();  // the nested call must not restore early
    return ND_OK;
  });
  ck_assert_int_eq(status, ND_OK);
  ck_assert_int_eq(outer, 1);
  ck_assert_int_eq(inner, 1);
  ck_assert_int_eq(after_inner, 1);
  ck_assert_int_eq(blas_get(), 2);
}
END_TEST

START_TEST(an_exception_restores_the_count) {
  if (!have_openblas()) return;
  blas_set(2);
  const int status = nd::guarded("f", []() -> int { throw nd::Error(ND_ERR_VALUE, "refused"); });
  ck_assert_int_eq(status, ND_ERR_VALUE);
  ck_assert_int_eq(blas_get(), 2);
}
END_TEST

START_TEST(limit_zero_leaves_the_blas_alone_and_a_high_limit_never_raises) {
  if (!have_openblas()) return;
  blas_set(2);
  for (int limit : {0, 4}) {
    nd::set_blas_thread_limit(limit);
    int inside = 0;
    nd::guarded("f", [&] {
      inside = blas_get();
      return ND_OK;
    });
    ck_assert_int_eq(inside, 2);
    ck_assert_int_eq(blas_get(), 2);
  }
  nd::set_blas_thread_limit(1);
}
END_TEST

int main() {
  Suite *s = suite_create("blas_threads (unit)");
  TCase *tc = tcase_create("core");
  tcase_add_test(tc, a_call_runs_at_the_limit_nested_calls_too);
  tcase_add_test(tc, an_exception_restores_the_count);
  tcase_add_test(tc, limit_zero_leaves_the_blas_alone_and_a_high_limit_never_raises);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
