// BLAS thread limits found with dlsym: the library links the system's BLAS
// through LAPACK and CHOLMOD and cannot know at build time which one the
// process will load (Debian switches it with update-alternatives).
#include "linalg/blas_threads.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <lapacke.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <string>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

struct Control {
  const char *name = "none";
  int (*get)() = nullptr;        // OpenBLAS, BLIS: the process-wide count
  void (*set)(int) = nullptr;
  int (*mkl_local)(int) = nullptr;  // MKL: sets the thread's own, returns the old
};

template <class F>
F symbol(const char *name) {
  return reinterpret_cast<F>(dlsym(RTLD_DEFAULT, name));
}

const Control &control() {
  static const Control c = [] {
    Control k;
    if ((k.mkl_local = symbol<int (*)(int)>("MKL_Set_Num_Threads_Local"))) {
      k.name = "MKL";
    } else if ((k.get = symbol<int (*)()>("openblas_get_num_threads")) &&
               (k.set = symbol<void (*)(int)>("openblas_set_num_threads"))) {
      k.name = "OpenBLAS";
    } else if ((k.get = symbol<int (*)()>("bli_thread_get_num_threads")) &&
               (k.set = symbol<void (*)(int)>("bli_thread_set_num_threads"))) {
      k.name = "BLIS";
    } else {
      k.get = nullptr, k.set = nullptr;
    }
    return k;
  }();
  return c;
}

std::atomic<int> limit{1};
// the scopes alive in the process and the caller's count saved by the first
std::mutex shared_mutex;
int alive = 0;
int saved = 0;

// require_blas_buffer's state: OpenBLAS holds its buffer (or is not the BLAS)
std::atomic<bool> buffer_ready{false};
std::mutex buffer_mutex;
constexpr uint64_t kOpenBlasBuffer = uint64_t{128} << 20;  // BUFFER_SIZE (common/common_x86_64.h)
constexpr uint64_t kBufferMargin = uint64_t{16} << 20;     // its bookkeeping, a thread's first allocations

// The address space the limit leaves (UINT64_MAX: no limit or unknown);
// read without allocating (open/read, not stdio)
uint64_t address_space_left() {
  rlimit r{};
  if (getrlimit(RLIMIT_AS, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return UINT64_MAX;
  const int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return UINT64_MAX;
  char text[64] = {};
  const ssize_t got = read(fd, text, sizeof text - 1);
  close(fd);
  if (got <= 0) return UINT64_MAX;
  uint64_t pages = 0;
  for (const char *c = text; *c >= '0' && *c <= '9'; ++c) pages = pages * 10 + static_cast<uint64_t>(*c - '0');
  const uint64_t used = pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE));
  const uint64_t cap = static_cast<uint64_t>(r.rlim_cur);
  return cap > used ? cap - used : 0;
}

}  // namespace

void require_blas_buffer() {
  if (buffer_ready.load(std::memory_order_acquire)) return;
  const Control &c = control();
  std::lock_guard<std::mutex> lock(buffer_mutex);
  if (buffer_ready.load(std::memory_order_relaxed)) return;
  if (std::strcmp(c.name, "OpenBLAS") == 0) {
    const uint64_t threads = static_cast<uint64_t>(std::max(1, c.get ? c.get() : 1));
    const uint64_t need = threads * kOpenBlasBuffer + kBufferMargin, left = address_space_left();
    if (left < need)
      fail(ND_ERR_NOMEM, "out of memory: the address-space limit (ulimit -v) leaves " + std::to_string(left >> 20) +
                             " MiB, and the BLAS (OpenBLAS) needs " + std::to_string(need >> 20) +
                             " MiB for its work buffers (it would wait for them forever); raise the limit");
    // dsytd2 of a 3 x 3 matrix calls dsymv, which takes OpenBLAS's buffer
    double a[9] = {2, 1, 1, 1, 2, 1, 1, 1, 2}, w[3], work[64];
    LAPACKE_dsyev_work(LAPACK_COL_MAJOR, 'N', 'U', 3, a, 3, w, work, 64);
  }
  buffer_ready.store(true, std::memory_order_release);
}

void set_blas_thread_limit(int threads) noexcept { limit.store(threads); }
int blas_thread_limit() noexcept { return limit.load(); }
const char *blas_thread_control() noexcept { return control().name; }

BlasThreadScope::BlasThreadScope() noexcept {
  const int n = limit.load();
  if (n <= 0) return;
  const Control &c = control();
  if (c.mkl_local) {
    mkl_previous_ = c.mkl_local(n);
  } else if (c.set) {
    std::lock_guard<std::mutex> lock(shared_mutex);
    if (alive++ == 0) {
      saved = c.get();
      if (saved > n) c.set(n);
    }
    counted_ = true;
  }
}

BlasThreadScope::~BlasThreadScope() {
  const Control &c = control();
  if (mkl_previous_ >= 0) c.mkl_local(mkl_previous_);
  if (!counted_) return;
  std::lock_guard<std::mutex> lock(shared_mutex);
  if (--alive == 0 && c.get() != saved) c.set(saved);
}

}  // namespace nd
