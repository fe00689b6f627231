// A free-flight step allocates no memory once the run is under way: the
// state before the last lends its vectors to the next (reuse_storage), and
// the solves, the residual checks and the Newton workspaces keep theirs
// (linalg/supernodal.hpp's SupernodalWork, Integrator::residual,
// CondensedCache::Work). Counted through this program's operator new, on
// every step but those shown free by the bound after one that evaluated
// the points: such a step makes the bound's reference from that state
// (problem/integrator.cpp: U, P_q and u_n copied into an immutable shared
// PointReference, which later states share). For every implicit scheme, 2D
// (CHOLMOD's supernodal factor) and 3D, P1 and P2.
// (Under valgrind, whose operator new replaces this one, nothing is counted.)
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "testutil.h"
#include "unit_drop.hpp"

namespace {
long g_allocations = 0;
bool g_counting = false;
}  // namespace

// every form of the plain and array operators, so that each allocation and
// its release meet the same pair (malloc, free) under ASan
namespace {
void *counted(std::size_t n) noexcept {
  if (g_counting) ++g_allocations;
  return std::malloc(n ? n : 1);
}
void *counted_or_throw(std::size_t n) {
  if (void *p = counted(n)) return p;
  throw std::bad_alloc();
}
}  // namespace
void *operator new(std::size_t n) { return counted_or_throw(n); }
void *operator new[](std::size_t n) { return counted_or_throw(n); }
void *operator new(std::size_t n, const std::nothrow_t &) noexcept { return counted(n); }
void *operator new[](std::size_t n, const std::nothrow_t &) noexcept { return counted(n); }
void operator delete(void *p) noexcept { std::free(p); }
void operator delete[](void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t) noexcept { std::free(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { std::free(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { std::free(p); }

namespace {

double stat(nd_problem p, int which) {
  double v = 0;
  ND_OK_OR_FAIL(nd_get_scalar(p, which, &v));
  return v;
}

void free_steps_allocate_nothing(int dim, int degree, int refine) {
  for (const ndtest::SchemeCase &sc : ndtest::kSchemes) {
    // far above the plane: free flight, deformed (the body turns and
    // stretches), so that steps are solved, not predicted
    nd_problem p = ndtest::drop_scene(dim, degree, sc, 1.0, 5.0, 0.1, refine);
    if (refine > 1) ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, ND_SOLVER_CHOLMOD));
    for (int k = 0; k < 5; ++k) ND_OK_OR_FAIL(nd_step(p));  // (the set-up, the first capacities)
    int counted = 0, solved = 0;
    bool evaluated_before = true;
    for (int k = 0; k < 30; ++k) {
      const double evaluations = stat(p, ND_STAT_CONTACT_EVALUATIONS), solves = stat(p, ND_STAT_SOLVES);
      g_allocations = 0;
      g_counting = true;
      const int status = nd_step(p);
      g_counting = false;
      ND_OK_OR_FAIL(status);
      // (the bound's new reference: a step shown free after one that evaluated)
      const bool evaluated = stat(p, ND_STAT_CONTACT_EVALUATIONS) != evaluations, skip = !evaluated && evaluated_before;
      evaluated_before = evaluated;
      if (skip) continue;
      ++counted;
      solved += stat(p, ND_STAT_SOLVES) > solves;
      ck_assert_msg(g_allocations == 0, "%dD P%d refine %d %s: step %d allocated %ld times", dim, degree, refine,
                    sc.name, k, g_allocations);
    }
    // (the counts asserted something: most steps, solved ones among them)
    ck_assert_msg(counted >= 20 && solved >= 10, "%dD P%d %s: %d steps counted, %d solved", dim, degree, sc.name,
                  counted, solved);
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}

// dimension, degree, refinement: the rectangles (refined) on CHOLMOD's
// supernodal factor, the boxes
const int kCases[][3] = {{2, 1, 4}, {2, 2, 4}, {3, 1, 1}, {3, 2, 1}};

START_TEST(free_steps) { free_steps_allocate_nothing(kCases[_i][0], kCases[_i][1], kCases[_i][2]); }
END_TEST

}  // namespace

int main() {
  Suite *s = suite_create("step_memory");
  TCase *tc = tcase_create("free_flight");
  tcase_set_timeout(tc, 60);
  tcase_add_loop_test(tc, free_steps, 0, static_cast<int>(sizeof kCases / sizeof kCases[0]));
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
