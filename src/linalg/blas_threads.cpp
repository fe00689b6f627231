// BLAS thread limits found with dlsym: the library links the system's BLAS
// through LAPACK and CHOLMOD and cannot know at build time which one the
// process will load (Debian switches it with update-alternatives).
#include "linalg/blas_threads.hpp"

#include <dlfcn.h>

#include <atomic>
#include <mutex>

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

}  // namespace

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
