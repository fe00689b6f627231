// METIS under a memory budget (issue 54): METIS prints to standard error
// when one of its own allocations fails (GKlib's gk_malloc), so
// nested_dissection first takes the memory METIS will need
// (metis_memory_bound) and gives it back. This program replaces malloc and
// its kin with a budget, as an address-space limit (ulimit -v) is one: an
// allocation fails when the bytes in use since the call began would exceed
// it. For the patterns of 2D and 3D meshes, P1 and P2, and for budgets from
// none to the call's own peak, nested_dissection must return the ordering
// or fail with ND_ERR_NOMEM (or bad_alloc, which the C API turns into it),
// and print nothing: before the fix a budget between the call's own arrays
// and METIS's peak made METIS print its message (and were the bound below
// METIS's peak, a budget that passed the check would still make it print).
// Where the budget suffices, the ordering is the one without a budget.
#include "common/error.hpp"  // before check.h, whose fail() macro would clash with nd::fail
#include <check.h>
#include <malloc.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <new>
#include <vector>

#include "assembly/bulk.hpp"
#include "linalg/ordering.hpp"
#include "testutil.h"
#include "unit_fixtures.hpp"

namespace {
bool armed = false;
long long in_use = 0, peak = 0, budget = -1;  // bytes since arming; -1: no budget

[[maybe_unused]] bool refuse(size_t n) { return armed && budget >= 0 && in_use + static_cast<long long>(n) > budget; }
[[maybe_unused]] void taken(void *p) {
  if (!armed || !p) return;
  in_use += static_cast<long long>(malloc_usable_size(p));
  if (in_use > peak) peak = in_use;
}
[[maybe_unused]] void given(void *p) {
  if (armed && p) in_use -= static_cast<long long>(malloc_usable_size(p));
}
}  // namespace

// ---- libc's allocator with a budget (not under AddressSanitizer, whose own
// allocator this would bypass: there the test is skipped)
#if defined(__SANITIZE_ADDRESS__)
#define ND_BUDGET 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ND_BUDGET 0
#endif
#endif
#ifndef ND_BUDGET
#define ND_BUDGET 1
#endif
#if ND_BUDGET
extern "C" {
void *__libc_malloc(size_t);
void *__libc_calloc(size_t, size_t);
void *__libc_realloc(void *, size_t);
void *__libc_memalign(size_t, size_t);
void __libc_free(void *);
void *malloc(size_t n) {
  if (refuse(n)) return errno = ENOMEM, nullptr;
  void *p = __libc_malloc(n);
  taken(p);
  return p;
}
void *calloc(size_t n, size_t s) {
  if (refuse(n * s)) return errno = ENOMEM, nullptr;
  void *p = __libc_calloc(n, s);
  taken(p);
  return p;
}
void *realloc(void *p, size_t n) {
  if (n && refuse(n)) return errno = ENOMEM, nullptr;
  given(p);
  void *q = __libc_realloc(p, n);
  taken(q ? q : (n ? p : nullptr));  // (a failed realloc keeps p)
  return q;
}
void *memalign(size_t a, size_t n) {
  if (refuse(n)) return errno = ENOMEM, nullptr;
  void *p = __libc_memalign(a, n);
  taken(p);
  return p;
}
void *aligned_alloc(size_t a, size_t n) { return memalign(a, n); }
int posix_memalign(void **out, size_t a, size_t n) {
  void *p = memalign(a, n);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
void free(void *p) {
  given(p);
  __libc_free(p);
}
}
#endif

namespace {

// the stiffness pattern of a mesh
nd::Csr pattern(const std::shared_ptr<nd::Mesh> &mesh, int degree) {
  nd::Space sp(mesh, degree);
  nd::DofMap dofs(sp, {});
  return nd::assemble_bulk(sp, dofs, nd::Material{50, 0.25, 1}).K;
}

// nested_dissection under `limit` bytes (-1: none): ND_OK with its ordering,
// or ND_ERR_NOMEM; whatever went to standard error is in `printed`
int order(const nd::Csr &A, long long limit, std::vector<int64_t> &perm, std::string &printed) {
  std::fflush(stderr);
  char name[] = "/tmp/unit_metis_memory_XXXXXX";
  const int file = mkstemp(name);
  ck_assert(file >= 0);
  unlink(name);
  const int saved = dup(2);
  dup2(file, 2);
  int status = ND_OK;
  in_use = 0, peak = 0, budget = limit, armed = true;
  try {
    perm = nd::nested_dissection(A);
  } catch (const nd::Error &e) {
    status = e.code();
  } catch (const std::bad_alloc &) {
    status = ND_ERR_NOMEM;
  }
  armed = false, budget = -1;
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  printed.clear();
  char text[512];
  lseek(file, 0, SEEK_SET);
  for (ssize_t got; (got = read(file, text, sizeof text)) > 0;) printed.append(text, static_cast<size_t>(got));
  close(file);
  return status;
}

}  // namespace

START_TEST(metis_prints_nothing_when_memory_runs_out) {
  if (!ND_BUDGET) return;  // (AddressSanitizer: its allocator, not this budget)
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
  const std::vector<std::shared_ptr<nd::Mesh>> meshes = {
      ndtest::irregular_rectangle(12), ndtest::irregular_rectangle(40),
      std::make_shared<nd::Mesh>(nd::make_box(4, 4, 4, lo, hi))};
  for (const auto &mesh : meshes)
    for (int degree = 1; degree <= 2; ++degree) {
      const nd::Csr A = pattern(mesh, degree);
      std::vector<int64_t> free_run, perm;
      std::string printed;
      ck_assert_int_eq(order(A, -1, free_run, printed), ND_OK);
      ck_assert_msg(printed.empty(), "%s", printed.c_str());
      const long long full = peak;
      // every budget from none to the call's peak, in 64 steps: the
      // ordering, the same, or ND_ERR_NOMEM; never a word on stderr
      int refused = 0;
      for (int k = 0; k <= 64; ++k) {
        const long long limit = full * k / 64;
        const int status = order(A, limit, perm, printed);
        ck_assert_msg(printed.empty(), "dim %d P%d, a budget of %lld of %lld bytes: METIS printed: %s", mesh->dim,
                      degree, limit, full, printed.c_str());
        ck_assert_msg(status == ND_OK || status == ND_ERR_NOMEM, "status %d", status);
        if (status == ND_OK) ck_assert(perm == free_run);
        refused += status != ND_OK;
      }
      ck_assert(refused > 0);  // (the small budgets did run out)
    }
}
END_TEST

int main() {
  Suite *s = suite_create("unit_metis_memory");
  TCase *tc = tcase_create("budget");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, metis_prints_nothing_when_memory_runs_out);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
