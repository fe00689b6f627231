// A sparse Cholesky factor that is modified in place by rank updates and
// downdates: L L^T +/- C C^T for a few sparse columns C costs what the
// columns' paths in the elimination tree touch, a small part of a
// factorization. Where CHOLMOD's analysis is supernodal (3D meshes, the
// larger 2D ones), a supernodal LL^T modified by our updates and solved by
// our sweeps (linalg/supernodal.hpp); elsewhere a simplicial LDL^T modified
// by CHOLMOD's (its Modify module, which needs that form). The Newton tangent of the symmetric contact problem (Theta = 1)
// changes by such terms as contact points come and go (fast/tangent_updown.cpp).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "common/counters.hpp"
#include "linalg/csr.hpp"
#include "linalg/factorization.hpp"

namespace nd {

// Sparse columns: column j has rows idx[ptr[j] .. ptr[j+1]) (free DOF
// numbers, any order, no repeats) with the values val[...].
struct SparseColumns {
  std::vector<int64_t> ptr{0}, idx;
  std::vector<double> val;
  int64_t count() const { return static_cast<int64_t>(ptr.size()) - 1; }
};

class UpdatableCholesky {
 public:
  // the symbolic analysis of the pattern (in the CHOLMOD backend's ordering:
  // that of ordered_like, a CHOLMOD factor of the same pattern, reused rather
  // than computed again: no second METIS run); counted as an
  // analysis, each factor() as a factorization and each solve() as a solve
  UpdatableCholesky(const Csr &pattern, Counters *counters, const Factorization *ordered_like = nullptr);
  ~UpdatableCholesky();
  // numeric LDL^T of T (its pattern the constructor's); throws ND_ERR_INDEFINITE
  // when a pivot is not positive
  void factor(const Csr &T);
  // L D L^T <- L D L^T + C C^T (add) or - C C^T; C's columns must lie in the
  // pattern's rows/columns so that L's structure is unchanged. false (the
  // factor then no longer valid: factor again) when a pivot of the result is
  // not positive and finite.
  bool modify(bool add, const SparseColumns &C);
  void solve(double *x) const;
  // the factor of A itself, copied from A's own CHOLMOD factor (same
  // pattern, same ordering) and converted: far cheaper than a
  // factorization. false, and nothing changed, when
  // A_factor is not a CHOLMOD factor of this ordering.
  bool start_from(const Factorization &A_factor);

  // Estimated costs, in nanoseconds of the machine the model was fitted on
  // (one BLAS thread; docs/performance.md, "Cost model of the updated
  // factor"): deterministic functions of the structure, so that a run's
  // choices between updating and refactoring, and its bits, do not depend on
  // timings. A factorization: max(50 ns nnz(L), flops / 40 GFlop/s); an
  // update or downdate: for each nonzero of L on each column's path in the
  // elimination tree, 0.25 ns in the supernodal form, 0.7 ns in the
  // simplicial one. modify_cost: once has_costs().
  double factor_cost() const;
  // a solve (forward and backward): 0.6 ns nnz(L)
  double solve_cost() const;
  double modify_cost(const SparseColumns &C) const;
  bool has_costs() const;  // modify_cost is known (after a factor() or start_from())
  // the entries of L on the columns' paths (modify_cost's measure of the work)
  double path_entries(const SparseColumns &C) const;
  // the work of the modifications since construction: the entries of L
  // times the vectors that rotated them (the supernodal form's count; the
  // simplicial form, CHOLMOD's, counts each column's path_entries)
  int64_t modified_entries() const;

 private:
  struct Impl;  // CHOLMOD's types stay in cholmod.cpp
  std::unique_ptr<Impl> impl_;
  Counters *counters_;
};

}  // namespace nd
