#include "common/simd.hpp"

#include <atomic>

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

}  // namespace nd
