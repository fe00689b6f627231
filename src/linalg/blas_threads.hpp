// The library's BLAS threading policy (docs/performance.md, "BLAS threads"): while a call
// of the C API runs, the BLAS found in the process runs at most
// blas_thread_limit() threads, and the caller's own setting is restored when
// the last such call returns. Limit 0: the library never touches the BLAS.
// Why: on the sizes a step solves, a threaded BLAS (OpenBLAS's pthread build)
// mostly waits, its threads spinning, which on a machine shared with other
// jobs slows a whole run by a large factor.
#pragma once

namespace nd {

// process-wide, because BLAS thread pools are; default 1
void set_blas_thread_limit(int threads) noexcept;
int blas_thread_limit() noexcept;

// which BLAS was found at run time ("OpenBLAS", "MKL", "BLIS" or "none")
const char *blas_thread_control() noexcept;

// Scoped limit: the first scope alive in the process saves the BLAS's
// thread count and lowers it to the limit; the last one restores it. Scopes
// nest (a monitor calling back into the library) and may live in several
// threads at once. MKL's limit is thread-local and needs no sharing.
class BlasThreadScope {
 public:
  BlasThreadScope() noexcept;
  ~BlasThreadScope();
  BlasThreadScope(const BlasThreadScope &) = delete;
  BlasThreadScope &operator=(const BlasThreadScope &) = delete;

 private:
  int mkl_previous_ = -1;  // MKL: the thread's local setting to put back
  bool counted_ = false;   // OpenBLAS/BLIS: this scope is in the shared count
};

}  // namespace nd
