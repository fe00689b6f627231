// The bytes the program holds through operator new (the library's
// containers: its vectors, operators and contact rows; not PETSc's or
// MUMPS's, which allocate with malloc), for scaling_bench's accounting of
// what a rank keeps and what a step adds. This file replaces the global
// operator new and delete of the program that links it; the library's own
// calls bind to them (the dynamic linker looks in the executable first).
// Each block carries its requested size in front, and whether it was
// counted as whole-length: n ints, n doubles or 8-byte indices, the n + 1
// row pointers of an operator, n pairs or n triples of doubles (node
// coordinates), n the unknowns.
#include <atomic>
#include <cstdlib>
#include <new>

namespace {
constexpr std::size_t kHeader = 16;  // keeps the blocks 16-byte aligned
std::atomic<long long> g_now{0}, g_peak{0}, g_whole{0}, g_whole_peak{0};
std::atomic<long long> g_vector_bytes{0};  // 8 n: blocks of 4 n, 8 n, 8 (n + 1), 16 n, 24 n bytes are whole

void raise(std::atomic<long long> &peak, long long now) {
  long long seen = peak.load(std::memory_order_relaxed);
  while (now > seen && !peak.compare_exchange_weak(seen, now)) {
  }
}

bool whole(std::size_t n) {
  const long long v = g_vector_bytes.load(std::memory_order_relaxed);
  const long long b = static_cast<long long>(n), h = v / 2;  // 4 n
  return v > 0 && (b == h || b == v || b == v + 8 || b == 2 * v || b == 3 * v);
}

void *take(std::size_t n) {
  char *p = static_cast<char *>(std::malloc(n + kHeader));
  if (!p) throw std::bad_alloc();
  const bool counted = whole(n);  // (the mark: a block counted stays counted)
  reinterpret_cast<std::size_t *>(p)[0] = n;
  reinterpret_cast<std::size_t *>(p)[1] = counted;
  raise(g_peak, g_now += static_cast<long long>(n));
  if (counted) raise(g_whole_peak, g_whole += static_cast<long long>(n));
  return p + kHeader;
}

void give(void *q) noexcept {
  if (!q) return;
  char *p = static_cast<char *>(q) - kHeader;
  const std::size_t n = reinterpret_cast<std::size_t *>(p)[0];
  g_now -= static_cast<long long>(n);
  if (reinterpret_cast<std::size_t *>(p)[1]) g_whole -= static_cast<long long>(n);
  std::free(p);
}

void *take_nothrow(std::size_t n) noexcept {
  try {
    return take(n);
  } catch (...) {
    return nullptr;
  }
}
}  // namespace

void *operator new(std::size_t n) { return take(n); }
void *operator new[](std::size_t n) { return take(n); }
void *operator new(std::size_t n, const std::nothrow_t &) noexcept { return take_nothrow(n); }
void *operator new[](std::size_t n, const std::nothrow_t &) noexcept { return take_nothrow(n); }
void operator delete(void *p) noexcept { give(p); }
void operator delete[](void *p) noexcept { give(p); }
void operator delete(void *p, std::size_t) noexcept { give(p); }
void operator delete[](void *p, std::size_t) noexcept { give(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { give(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { give(p); }

extern "C" {
// From now on, blocks of n = `doubles` elements of 4, 8, 16 or 24 bytes,
// or n + 1 of 8 bytes, count as whole-length.
void nd_bench_heap_watch_vectors(long long doubles) { g_vector_bytes = 8 * doubles; }
// the bytes held now, and those in whole vectors
long long nd_bench_heap_now(void) { return g_now.load(); }
long long nd_bench_heap_vectors_now(void) { return g_whole.load(); }
// the most held since the last nd_bench_heap_reset_peak (or the start)
long long nd_bench_heap_peak(void) { return g_peak.load(); }
long long nd_bench_heap_vectors_peak(void) { return g_whole_peak.load(); }
void nd_bench_heap_reset_peak(void) {
  g_peak.store(g_now.load());
  g_whole_peak.store(g_whole.load());
}
}
