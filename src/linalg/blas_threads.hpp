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

// OpenBLAS takes a work buffer (BUFFER_SIZE: 128 MiB of address space in
// the usual x86-64 builds) on the first BLAS call of a thread that needs one,
// keeps it, and, when the address space is exhausted (ulimit -v), retries
// forever: the call hangs (issue 54). Before the library's first BLAS call
// this checks that the address-space limit (RLIMIT_AS, against the process's
// size) leaves room for a buffer per BLAS thread, and throws ND_ERR_NOMEM if
// not; then it makes OpenBLAS take its buffer at once (a 3 x 3 eigenproblem)
// while the room is there. Once that succeeded, an atomic load. Other BLAS
// libraries: nothing. Calls of several threads at once each take a buffer
// of their own: the check covers the first only.
void require_blas_buffer();

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
