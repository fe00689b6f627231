// SuiteSparse backends. Each analyses the pattern once (ordering, symbolic
// factorization) and refactors numerically for every new matrix of that
// pattern. Our CSR arrays, read as CSC, describe A^T: CHOLMOD needs nothing
// more (A is symmetric), UMFPACK and KLU solve with the transpose.
#include <cholmod.h>
#include <klu.h>
#include <umfpack.h>

#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "common/error.hpp"
#include "linalg/backends.hpp"
#include "nitschedyn.h"

static_assert(std::is_same<SuiteSparse_long, int64_t>::value, "SuiteSparse_long must be int64_t");

namespace nd {
namespace {

class Cholmod : public Factorization {
 public:
  explicit Cholmod(const Csr &pattern) : n_(pattern.n) {
    cholmod_l_start(&c_);
    c_.print = 0;  // the library never prints
    A_ = cholmod_l_allocate_sparse(n_, n_, pattern.col.size(), 1, 1, 1, CHOLMOD_REAL, &c_);
    if (!A_) fail(ND_ERR_NOMEM, "CHOLMOD could not allocate the matrix");
    std::memcpy(A_->p, pattern.ptr.data(), sizeof(int64_t) * pattern.ptr.size());
    std::memcpy(A_->i, pattern.col.data(), sizeof(int64_t) * pattern.col.size());
    L_ = cholmod_l_analyze(A_, &c_);
    if (!L_) fail(ND_ERR_NOMEM, "CHOLMOD analysis failed (status " + std::to_string(c_.status) + ")");
  }
  ~Cholmod() override {
    cholmod_l_free_factor(&L_, &c_);
    cholmod_l_free_sparse(&A_, &c_);
    cholmod_l_finish(&c_);
  }
  void factor(const Csr &A, Structure s) override {
    if (s != Structure::SymmetricPositiveDefinite) fail(ND_ERR_INTERNAL, "CHOLMOD given a non-symmetric matrix");
    std::memcpy(A_->x, A.val.data(), sizeof(double) * A.val.size());
    cholmod_l_factorize(A_, L_, &c_);
    if (c_.status == CHOLMOD_NOT_POSDEF)
      fail(ND_ERR_INDEFINITE, "the matrix is not positive definite (CHOLMOD: leading minor " +
                                  std::to_string(L_->minor + 1) + " is not positive)");
    if (c_.status != CHOLMOD_OK) fail(ND_ERR_NOMEM, "CHOLMOD factorization failed (status " + std::to_string(c_.status) + ")");
  }
  void solve(double *x) const override {
    cholmod_dense b;
    std::memset(&b, 0, sizeof b);
    b.nrow = static_cast<size_t>(n_);
    b.ncol = 1;
    b.nzmax = b.d = static_cast<size_t>(n_);
    b.x = x;
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    cholmod_dense *r = cholmod_l_solve(CHOLMOD_A, L_, &b, &c_);
    if (!r) fail(ND_ERR_NOMEM, "CHOLMOD solve failed");
    std::memcpy(x, r->x, sizeof(double) * static_cast<size_t>(n_));
    cholmod_l_free_dense(&r, &c_);
  }
  const char *name() const override { return "cholmod"; }

 private:
  int64_t n_;
  mutable cholmod_common c_;
  cholmod_sparse *A_ = nullptr;
  cholmod_factor *L_ = nullptr;
};

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
  void factor(const Csr &A, Structure) override {
    if (numeric_) umfpack_dl_free_numeric(&numeric_);
    val_ = A.val;
    const int64_t st = umfpack_dl_numeric(ptr_.data(), col_.data(), val_.data(), symbolic_, &numeric_, control_, nullptr);
    if (st == UMFPACK_WARNING_singular_matrix) fail(ND_ERR_SINGULAR, "the matrix is singular (UMFPACK)");
    if (st != UMFPACK_OK) fail(ND_ERR_NOMEM, "UMFPACK numeric factorization failed (status " + std::to_string(st) + ")");
  }
  void solve(double *x) const override {
    work_.assign(x, x + n_);
    // the arrays describe A^T, so solve with its transpose
    umfpack_dl_solve(UMFPACK_At, ptr_.data(), col_.data(), val_.data(), x, work_.data(), numeric_, control_, nullptr);
  }
  const char *name() const override { return "umfpack"; }

 private:
  int64_t n_;
  std::vector<int64_t> ptr_, col_;
  std::vector<double> val_;
  mutable std::vector<double> work_;
  double control_[UMFPACK_CONTROL];
  void *symbolic_ = nullptr, *numeric_ = nullptr;
};

class Klu : public Factorization {
 public:
  explicit Klu(const Csr &pattern) : n_(pattern.n), ptr_(pattern.ptr), col_(pattern.col) {
    klu_l_defaults(&c_);
    symbolic_ = klu_l_analyze(n_, ptr_.data(), col_.data(), &c_);
    if (!symbolic_) fail(ND_ERR_NOMEM, "KLU analysis failed (status " + std::to_string(c_.status) + ")");
  }
  ~Klu() override {
    if (numeric_) klu_l_free_numeric(&numeric_, &c_);
    klu_l_free_symbolic(&symbolic_, &c_);
  }
  void factor(const Csr &A, Structure) override {
    if (numeric_) klu_l_free_numeric(&numeric_, &c_);
    val_ = A.val;
    numeric_ = klu_l_factor(ptr_.data(), col_.data(), val_.data(), symbolic_, &c_);
    if (!numeric_ && c_.status == KLU_SINGULAR) fail(ND_ERR_SINGULAR, "the matrix is singular (KLU)");
    if (!numeric_) fail(ND_ERR_NOMEM, "KLU factorization failed (status " + std::to_string(c_.status) + ")");
  }
  void solve(double *x) const override {
    klu_l_tsolve(symbolic_, numeric_, n_, 1, x, &c_);  // the arrays describe A^T
  }
  const char *name() const override { return "klu"; }

 private:
  int64_t n_;
  std::vector<int64_t> ptr_, col_;
  std::vector<double> val_;
  mutable klu_l_common c_;
  klu_l_symbolic *symbolic_ = nullptr;
  klu_l_numeric *numeric_ = nullptr;
};

}  // namespace

std::unique_ptr<Factorization> make_cholmod_factorization(const Csr &p) { return std::make_unique<Cholmod>(p); }
std::unique_ptr<Factorization> make_umfpack_factorization(const Csr &p) { return std::make_unique<Umfpack>(p); }
std::unique_ptr<Factorization> make_klu_factorization(const Csr &p) { return std::make_unique<Klu>(p); }

}  // namespace nd
