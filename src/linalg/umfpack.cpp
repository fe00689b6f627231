// UMFPACK: general sparse LU. The pattern is analysed once, each matrix of
// it factored numerically. Our CSR arrays, read as CSC, describe A^T: we
// solve with the transpose.
#include <umfpack.h>

#include <string>
#include <vector>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "linalg/suitesparse.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// An UMFPACK status: singular is ND_ERR_SINGULAR, out of memory ND_ERR_NOMEM,
// any other error ND_ERR_INTERNAL with the status; other warnings (a
// determinant under- or overflow) are not failures.
void check_umfpack(int64_t status, const char *what) {
  if (status == UMFPACK_OK) return;
  const std::string st = " (UMFPACK status " + std::to_string(status) + ")";
  if (status == UMFPACK_WARNING_singular_matrix) fail(ND_ERR_SINGULAR, "the matrix is singular" + st);
  if (status == UMFPACK_ERROR_out_of_memory) fail(ND_ERR_NOMEM, std::string("out of memory in the UMFPACK ") + what + st);
  if (status < 0) fail(ND_ERR_INTERNAL, std::string("UMFPACK ") + what + " failed" + st);
}

class Umfpack : public Factorization {
 public:
  explicit Umfpack(const Csr &pattern) : n_(pattern.n), ptr_(pattern.ptr.vec()), col_(pattern.col.vec()) {
    umfpack_dl_defaults(control_);
    std::vector<double> ones(col_.size(), 1.0);  // the ordering depends on the pattern only
    check_umfpack(umfpack_dl_symbolic(n_, n_, ptr_.data(), col_.data(), ones.data(), &symbolic_, control_, nullptr),
                  "symbolic analysis");
  }
  ~Umfpack() override {
    if (numeric_) umfpack_dl_free_numeric(&numeric_);
    if (symbolic_) umfpack_dl_free_symbolic(&symbolic_);
  }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    require_finite(A);
    if (numeric_) umfpack_dl_free_numeric(&numeric_);
    val_ = A.val;
    const int64_t st = umfpack_dl_numeric(ptr_.data(), col_.data(), val_.data(), symbolic_, &numeric_, control_, nullptr);
    check_umfpack(st, "numeric factorization");
    if (s != Structure::SymmetricPositiveDefinite) return;
    p_.resize(static_cast<size_t>(n_)), q_.resize(p_.size()), udiag_.resize(p_.size());
    check_umfpack(umfpack_dl_get_numeric(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, p_.data(), q_.data(),
                                         udiag_.data(), nullptr, nullptr, numeric_),
                  "pivot query");
    lu_definiteness(n_, p_.data(), q_.data(), udiag_.data(), def_);
  }
  void solve(double *x) const override {
    work_.assign(x, x + n_);
    // the arrays describe A^T, so solve with its transpose
    check_umfpack(
        umfpack_dl_solve(UMFPACK_At, ptr_.data(), col_.data(), val_.data(), x, work_.data(), numeric_, control_, nullptr),
        "solve");
  }
  Definiteness definiteness() const override { return def_; }
  const char *name() const override { return "umfpack"; }

 private:
  int64_t n_;
  std::vector<int64_t> ptr_, col_, p_, q_;
  std::vector<double> val_, udiag_;
  Definiteness def_ = Definiteness::Unknown;
  mutable std::vector<double> work_;
  double control_[UMFPACK_CONTROL];
  void *symbolic_ = nullptr, *numeric_ = nullptr;
};

}  // namespace

std::unique_ptr<Factorization> make_umfpack_factorization(const Csr &p) { return std::make_unique<Umfpack>(p); }

}  // namespace nd
