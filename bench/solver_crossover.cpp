// Benchmark (not a test): where dense LAPACK stops paying. Factor + solve of
// c M + K (SPD) on 2D P1 rectangles of growing size, through the dense,
// banded, CHOLMOD, UMFPACK and KLU backends; median of repeats, one CSV row
// per size and backend. Sets kDenseMax / kBandMax in src/linalg/factorization.cpp.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <vector>

#include "assembly/bulk.hpp"
#include "linalg/factorization.hpp"
#include "nitschedyn.h"

namespace {
double seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

int main() {
  std::printf("unknowns,backend,factor_ms,solve_ms\n");
  const int sizes[] = {2, 3, 4, 6, 8, 10, 12, 16, 20, 28};
  const int backends[] = {ND_SOLVER_DENSE, ND_SOLVER_BANDED, ND_SOLVER_CHOLMOD, ND_SOLVER_UMFPACK, ND_SOLVER_KLU};
  const char *names[] = {"dense", "banded", "cholmod", "umfpack", "klu"};
  for (int nx : sizes) {
    const double lo[2] = {0, 0}, hi[2] = {2, 1};
    auto mesh = std::make_shared<nd::Mesh>(nd::make_rectangle(nx, nx / 2 > 0 ? nx / 2 : 1, lo, hi));
    nd::Space s(mesh, 1);
    nd::DofMap dofs(s, {});
    nd::BulkOperators ops = nd::assemble_bulk(s, dofs, nd::Material{50, 0.25, 1});
    nd::Csr A;
    nd::csr_combine(1e4, ops.M, 1.0, ops.K, A);  // c = 4/tau^2, tau = 0.02
    for (int b = 0; b < 5; ++b) {
      std::vector<double> tf, ts;
      for (int r = 0; r < 7; ++r) {
        double t0 = seconds();
        auto f = nd::make_factorization(backends[b], A, nd::Structure::SymmetricPositiveDefinite);
        f->factor(A, nd::Structure::SymmetricPositiveDefinite);
        tf.push_back(seconds() - t0);
        std::vector<double> x(static_cast<size_t>(A.n), 1.0);
        t0 = seconds();
        f->solve(x.data());
        ts.push_back(seconds() - t0);
      }
      std::sort(tf.begin(), tf.end());
      std::sort(ts.begin(), ts.end());
      std::printf("%lld,%s,%.4f,%.4f\n", static_cast<long long>(A.n), names[b], 1e3 * tf[3], 1e3 * ts[3]);
    }
  }
  return 0;
}
