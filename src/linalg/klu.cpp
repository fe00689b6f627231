// KLU: sparse LU for circuit-like matrices (BTF, then AMD per block). The
// pattern is analysed once, each matrix of it factored numerically. Our CSR
// arrays, read as CSC, describe A^T: we solve with the transpose.
#include <klu.h>

#include <string>
#include <vector>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "linalg/suitesparse.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// A KLU status that is not OK: singular is ND_ERR_SINGULAR, out of memory
// ND_ERR_NOMEM, too large ND_ERR_SIZE, anything else ND_ERR_INTERNAL.
[[noreturn]] void fail_klu(int status, const char *what) {
  const std::string st = " (KLU status " + std::to_string(status) + ")";
  if (status == KLU_SINGULAR) fail(ND_ERR_SINGULAR, "the matrix is singular" + st);
  if (status == KLU_OUT_OF_MEMORY) fail(ND_ERR_NOMEM, std::string("out of memory in the KLU ") + what + st);
  if (status == KLU_TOO_LARGE) fail(ND_ERR_SIZE, std::string("the matrix is too large for the KLU ") + what + st);
  fail(ND_ERR_INTERNAL, std::string("KLU ") + what + " failed" + st);
}

class Klu : public Factorization {
 public:
  explicit Klu(const Csr &pattern) : n_(pattern.n), ptr_(pattern.ptr.vec()), col_(pattern.col.vec()) {
    klu_l_defaults(&c_);
    symbolic_ = klu_l_analyze(n_, ptr_.data(), col_.data(), &c_);
    if (!symbolic_) fail_klu(c_.status, "analysis");
  }
  ~Klu() override {
    if (numeric_) klu_l_free_numeric(&numeric_, &c_);
    klu_l_free_symbolic(&symbolic_, &c_);
  }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    require_finite(A);
    if (numeric_) klu_l_free_numeric(&numeric_, &c_);
    val_ = A.val;
    numeric_ = klu_l_factor(ptr_.data(), col_.data(), val_.data(), symbolic_, &c_);
    if (!numeric_) fail_klu(c_.status, "factorization");
    if (s == Structure::SymmetricPositiveDefinite)  // Udiag in pivot order
      lu_definiteness(n_, numeric_->Pnum, symbolic_->Q, static_cast<const double *>(numeric_->Udiag), def_);
  }
  void solve(double *x) const override {
    if (!klu_l_tsolve(symbolic_, numeric_, n_, 1, x, &c_)) fail_klu(c_.status, "solve");  // the arrays describe A^T
  }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "klu"; }

 private:
  int64_t n_;
  std::vector<int64_t> ptr_, col_;
  std::vector<double> val_;
  mutable klu_l_common c_;
  klu_l_symbolic *symbolic_ = nullptr;
  klu_l_numeric *numeric_ = nullptr;
  Definiteness def_ = Definiteness::Unknown;
};

}  // namespace

std::unique_ptr<Factorization> make_klu_factorization(const Csr &p) { return std::make_unique<Klu>(p); }

}  // namespace nd
