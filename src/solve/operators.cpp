#include "solve/operators.hpp"

#include <algorithm>
#include <atomic>
#include <cstdint>

#include "common/error.hpp"
#include "linalg/pcg.hpp"
#include "nitschedyn.h"
#include "parallel/share.hpp"
#include "solve/clamped_coupling.hpp"
#include "solve/contact_law.hpp"
#include "solve/products.hpp"

namespace nd {

namespace {
// The initial acceleration's mass solve by conjugate gradients from this
// many unknowns on (below, a factorization is cheap), to this relative
// residual, within this many iterations: a few dozen for a general
// right-hand side, a few from rest under gravity (F = M g), to within
// round-off of the factored solve (unit_linalg); the first step then
// neither factors M nor holds its factor (docs/performance.md, "Initial
// acceleration by CG").
constexpr int64_t kMassCgMinSize = 2048;
constexpr double kMassCgTolerance = 1e-15;
// ... and on, while round-off lets the residual fall, toward this one: A^0's
// error excites the round-off vibrations a predicted step cannot follow
// (fast/predictor_check.hpp; its residual holds (omega tau)^2/2 times that
// error). The few more iterations this costs bring the first predicted
// step well within kPredictorRoundOffs.
constexpr double kMassCgTarget = 1e-16;
constexpr int kMassCgMaxIterations = 300;
}  // namespace

const Share *own_rows_of(const Discretization &d, bool in_step) {
  return in_step || d.rows_split ? d.rows.get() : nullptr;
}

void Discretization::mass_solve(double *x, int solver, bool once) {
  if (lumped) {  // explicit steps with lumped mass: no solve at all
    for (size_t i = 0; i < M_lumped.size(); ++i) x[i] = M_lumped[i] == 0 ? 0.0 : x[i] / M_lumped[i];
    return;
  }
  for (size_t i = 0; i < massless.size(); ++i)
    if (massless[i]) x[i] = 0;
  if (M_factor) {
    M_factor->solve(x);
    return;
  }
  // massless DOFs: M + diag(massless) is block diagonal, a unit block on
  // them (a copy of M, made only then)
  Csr with_unit_block;
  if (std::any_of(massless.begin(), massless.end(), [](char m) { return m != 0; })) {
    with_unit_block = M;
    for (size_t i = 0; i < massless.size(); ++i)
      if (massless[i])
        with_unit_block.val[with_unit_block.find(static_cast<int64_t>(i), static_cast<int64_t>(i))] = 1;
  }
  const Csr &Mf = with_unit_block.n ? with_unit_block : M;
  // (whole M only: a rank's rows of a split M are not an operator on its own)
  if (once && !rows_split && Mf.n >= kMassCgMinSize) {
    std::vector<double> y(x, x + Mf.n);
    const PcgResult r = pcg_jacobi(Mf, y.data(), kMassCgTolerance, kMassCgMaxIterations, kMassCgTarget);
    count(counters, &Counters::spmv, r.iterations + 1);
    if (r.converged) {
      std::copy(y.begin(), y.end(), x);
      return;
    }  // else (not expected of a mass matrix) factored as below
  }
  auto f = make_factorization(solver, Mf, Structure::SymmetricPositiveDefinite, counters, &geometry);
  f->factor(Mf, Structure::SymmetricPositiveDefinite);
  M_factor = std::move(f);  // kept only once factored: a failure leaves nothing half-built
  M_factor->solve(x);
}

namespace {
std::atomic<uint64_t> last_discretization_id{0};
}  // namespace

const Discretization::OwnColumns &Discretization::own_columns() const {
  if (own_columns_) return *own_columns_;
  if (!rows_split || !rows) fail(ND_ERR_INTERNAL, "the columns of a rank's rows, without split rows");
  auto oc = std::make_shared<OwnColumns>();
  if (!K.part) fail(ND_ERR_INTERNAL, "split rows whose operators are not the rank's part");
  K.require_places(own_rows(rows.get()));  // K's entries are then the rank's rows', row after row
  const std::vector<int64_t> &entries = K.col.vec();
  std::vector<int64_t> sorted = entries;
  std::sort(sorted.begin(), sorted.end());
  oc->cols.assign(sorted.begin(), std::unique(sorted.begin(), sorted.end()));
  if (oc->cols.size() > static_cast<size_t>(INT32_MAX))
    fail(ND_ERR_SIZE, "a rank's rows read more than 2^31 - 1 columns");
  oc->place.resize(entries.size());
  for (size_t k = 0; k < entries.size(); ++k)
    oc->place[k] = static_cast<int32_t>(std::lower_bound(oc->cols.begin(), oc->cols.end(), entries[k]) - oc->cols.begin());
  own_columns_ = std::move(oc);
  return *own_columns_;
}

Discretization::Discretization(DofMap d, bool lump)
    : id(++last_discretization_id), dofs(std::move(d)), lumped(lump) {}

void Discretization::equilibrium_acceleration(State &s, int solver, bool once, bool in_step, PointValues *at_U,
                                              const DampedVelocity *damping) {
  const size_t n = s.U.size();
  std::vector<double> rhs(n);
  count(counters, &Counters::spmv);
  const Share *share = own_rows_of(*this, in_step);
  // an explicit step (not once) in one process: by nodes (the same bits)
  const bool by_nodes = !once && !share && node_blocks;
  if (by_nodes && !k_theta_blocks) k_theta_blocks = make_node_blocks(K_theta, M, node_blocks->dim);
  auto keep = [&](int64_t i, double ku, double, double, double) __attribute__((always_inline)) { rhs[i] = ku; };
  if (!for_node_rows<false, false>(by_nodes ? k_theta_blocks.get() : nullptr, s.U.data(), nullptr, nullptr, keep))
    K_theta.multiply(s.U.data(), rhs.data(), own_rows(share));
  if (damped()) {  // + C V (the known part of V^{n+1} in an explicit step)
    std::vector<double> CV(n, 0.0);
    C.multiply((damping ? *damping->V_known : s.V).data(), CV.data(), own_rows(share));
    for (size_t i = 0; i < n; ++i) rhs[i] += CV[i];
  }
  // split operators: the mass solve is distributed and reads this rank's rows only
  if (share && !rows_split) gather(*share, {rhs.data()});
  ContactLaw law = state_contact_law(*this, s);
  law.counters = counters;
  law.local = !in_step;
  if (at_U && contact.size() > 0) {
    law.P_all(s.U.data(), at_U->P, &at_U->un);
    law.add_force_from(at_U->P, 1.0, rhs.data(), nullptr);
  } else {
    law.add_force(s.U.data(), 1.0, rhs.data(), nullptr);
  }
  // prescribed motion: the free rows' coupling to the clamped DOFs at U_c, A_c
  if (!s.Uc.empty() && clamped) subtract_clamped_coupling(*this, ClampedMean{s.Uc, s.Ac, s.Vc}, -1.0, rhs.data());
  const std::vector<double> &F = s.load();
  for (size_t i = 0; i < n; ++i) rhs[i] = (F.empty() ? 0.0 : F[i]) - rhs[i];
  if (damping && damping->factor) {
    damping->factor->solve(rhs.data());  // M + slope C, beta > 0
  } else {
    mass_solve(rhs.data(), solver, once);
    // beta = 0: M + slope alpha M, a scalar multiple of M (a lumped mass stays a division)
    if (damping && damping->slope != 0)
      for (size_t i = 0; i < n; ++i) rhs[i] /= 1 + damping->slope * damping_alpha;
  }
  s.A = std::move(rhs);
  s.A_valid = true;
}
}  // namespace nd
