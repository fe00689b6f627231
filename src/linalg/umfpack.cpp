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

class Umfpack : public Factorization {
 public:
  explicit Umfpack(const Csr &pattern) : n_(pattern.n), ptr_(pattern.ptr), col_(pattern.col) {
    umfpack_dl_defaults(control_);
    std::vector<double> ones(col_.size(), 1.0);  // the ordering depends on the pattern only
    if (umfpack_dl_symbolic(n_, n_, ptr_.data(), col_.data(), ones.data(), &symbolic_, control_, nullptr) != UMFPACK_OK)
      fail(ND_ERR_NOMEM, "UMFPACK symbolic analysis failed");
  }
  ~Umfpack() override {
    if (numeric_) umfpack_dl_free_numeric(&numeric_);
    if (symbolic_) umfpack_dl_free_symbolic(&symbolic_);
  }
  void factor(const Csr &A, Structure s) override {
    def_ = Definiteness::Unknown;
    if (numeric_) umfpack_dl_free_numeric(&numeric_);
    val_ = A.val;
    const int64_t st = umfpack_dl_numeric(ptr_.data(), col_.data(), val_.data(), symbolic_, &numeric_, control_, nullptr);
    if (st == UMFPACK_WARNING_singular_matrix) fail(ND_ERR_SINGULAR, "the matrix is singular (UMFPACK)");
    if (st != UMFPACK_OK) fail(ND_ERR_NOMEM, "UMFPACK numeric factorization failed (status " + std::to_string(st) + ")");
    if (s != Structure::SymmetricPositiveDefinite) return;
    p_.resize(static_cast<size_t>(n_)), q_.resize(p_.size()), udiag_.resize(p_.size());
    if (umfpack_dl_get_numeric(nullptr, nullptr, nullptr, nullptr, nullptr, nullptr, p_.data(), q_.data(),
                               udiag_.data(), nullptr, nullptr, numeric_) != UMFPACK_OK)
      fail(ND_ERR_NOMEM, "UMFPACK could not return its pivots");
    lu_definiteness(n_, p_.data(), q_.data(), udiag_.data(), def_);
  }
  void solve(double *x) const override {
    work_.assign(x, x + n_);
    // the arrays describe A^T, so solve with its transpose
    umfpack_dl_solve(UMFPACK_At, ptr_.data(), col_.data(), val_.data(), x, work_.data(), numeric_, control_, nullptr);
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
