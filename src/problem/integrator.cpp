#include "problem/integrator.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <utility>

#include "assembly/coercivity.hpp"
#include "common/format.hpp"
#include "common/simd.hpp"
#include "parallel/agreement.hpp"
#include "problem/forces.hpp"
#include "solve/newton.hpp"
#include "solve/predictor_check.hpp"
#include "solve/products.hpp"

namespace nd {

namespace {

// The Newton tangent is symmetric (and positive definite with c M + K_Theta)
// iff Theta = 1, for a law whose tangent is (LawTraits::symmetric).
Structure tangent_structure(double theta, const LawTraits &law) {
  return theta == 1 && law.symmetric ? Structure::SymmetricPositiveDefinite : Structure::General;
}

// Newton refactors its tangent: when asked, or in 3D with an iterative solver
// (see make_integrator's choice below), or for a law whose blocks are not
// rank one or whose slope may be negative (the fallback, whatever was asked:
// the condensed Newton, the low-rank tangent and the updated factor add and
// drop terms phi' b_q p_q^T, phi' >= 0)
bool refactoring_tangent(const Definition &def, const Discretization &d) {
  return def.tangent == TangentChoice::Refactor || !rank_one_updates_apply(d.contact_law->traits()) ||
         (def.tangent == TangentChoice::Auto && d.geometry.dim == 3 && linear_solver_iterative(def.solver));
}

}  // namespace

double step_matrix(const Discretization &d, const TimeScheme &scheme, double tau, Csr &A) {
  csr_combine(scheme.coefficients(tau).c, d.M, 1.0, d.K_theta, A);
  if (!d.damped()) return 0;
  // G gains kappa C Vbar; its part in U (docs/design.md §10.5)
  const double damping = scheme.coefficients(tau).kappa * (1 - scheme.mean_weight()) * scheme.velocity_slope(tau);
  csr_combine(1.0, A, damping, d.C, A);
  return damping;
}

std::unique_ptr<Integrator> make_integrator(Discretization &d, const Definition &def,
                                            std::unique_ptr<Factorization> reuse,
                                            const std::function<Csr(double)> &own_part,
                                            const Factorization *ordered_like) {
  require_complete(def.missing_for_step());
  auto in = std::make_unique<Integrator>();
  in->scheme = make_scheme(def.scheme, def.scheme_params);
  in->tau = def.tau;
  if (in->scheme->is_explicit()) {
    if (!d.massless.empty()) in->massless = std::make_unique<MasslessSolver>(d, def.solver);
    // (M + slope C) A^{n+1} = ...: with beta = 0 a multiple of M, else a matrix of its own, factored once
    const double slope = in->scheme->velocity_slope(def.tau);
    if (d.damped() && d.damping_beta != 0 && slope != 0) {
      count(d.counters, &Counters::matrix_assemblies);
      csr_combine(1.0, d.M, slope, d.C, in->damped_mass);
      in->damped_mass_factor = make_factorization(def.solver, in->damped_mass, Structure::SymmetricPositiveDefinite,
                                                  d.counters, &d.geometry);
      in->damped_mass_factor->factor(in->damped_mass, Structure::SymmetricPositiveDefinite);
    }
    return in;
  }
  in->coef = in->scheme->coefficients(def.tau);
  count(d.counters, &Counters::matrix_assemblies);
  in->damping = step_matrix(d, *in->scheme, def.tau, in->A);
  if (d.node_blocks && !d.contact.a.empty()) in->A_blocks = make_node_blocks(in->A, d.M, d.node_blocks->dim);
  const bool refactors = !d.contact.a.empty() && refactoring_tangent(def, d);
  // on split operators a Newton pass that refactors reads the points whose rows touch the rank's rows
  if (refactors && d.rows_split) in->halo = contact_point_halo(d.contact, *d.rows);
  if (d.rows_split && def.distributed_state) {
    std::vector<const Csr *> clamped;  // (their reactions read these columns)
    if (d.clamped) clamped = {&d.clamped->K, &d.clamped->M};
    if (in->halo) in->points = held_points(d.contact, *in->halo);
    in->held = newton_held_rows(in->A, *d.rows, d.contact, clamped, in->points ? &in->points->points : nullptr);
  }
  in->A_factor = reuse ? std::move(reuse)
                       : make_factorization(def.solver, in->A, Structure::SymmetricPositiveDefinite, d.counters,
                                            &d.geometry, ordered_like);
  try {
    if (own_part) {  // several ranks: each adds its own cells' part of A to the distributed matrix
      Csr own;  // assembled by each rank alone: agreed before the factorization, which they make together
      on_every_rank(def.comm.get(), [&] { own = own_part(in->coef.c); }, "the assembly of the step matrix",
                    "no rank factored it");
      in->A_factor->factor_parts(in->A, own, Structure::SymmetricPositiveDefinite);
    } else {
      in->A_factor->factor(in->A, Structure::SymmetricPositiveDefinite);
    }
  } catch (const Error &e) {
    if (e.code() != ND_ERR_INDEFINITE) throw;
    // c M + K_Theta not positive definite: neither is K_Theta (M >= 0), so
    // gamma0 is too large for Theta whatever tau (a smaller tau, a larger c,
    // may still make the step well posed, not the free motion bounded)
    const std::string safe = safe_gamma0(d.theta, d.gamma0_limit);
    const std::string what = "the step operator c*M + K_Theta: " + std::string(e.what()) + "; with Theta = " +
                             num(def.theta) + ", gamma0 = " + num(d.gamma0) + " and tau = " + num(def.tau) +
                             " the step is not well posed";
    if (safe.empty()) fail(ND_ERR_INDEFINITE, what + ": lower the time step");
    fail(ND_ERR_INDEFINITE, what + ": K_Theta is not positive definite either, so gamma0 is too large for Theta; " +
                                safe + ", and gamma0 = 0 chooses one automatically; a smaller time step may also " +
                                "make the step well posed");
  }
  // Newton with contact: condensed on the points (the default), the full
  // Newton with the low-rank update of A's factor past its rank limit, both on
  // one column cache, and the updated factor of T past that where it applies;
  // in 3D the updated factor from the start: there a column A^{-1} b_q is a
  // solve with a factor several times denser per column than in 2D, and a
  // bounce activates hundreds of points, so updating T costs fewer solves
  // per Newton iteration than the columns; in 2D the columns win
  // (docs/performance.md, "Newton tangent by dimension"). Refactoring T is
  // the reference; in 3D it is also the choice of an iterative solver
  // (GAMG), where a column is a Krylov solve and a new tangent reuses the
  // multigrid hierarchy of an earlier one (PetscGamg::refactor); with GAMG
  // in 2D refactoring gains nothing over the condensed Newton.
  if (!d.contact.a.empty()) {
    const Structure s = tangent_structure(def.theta, d.contact_law->traits());
    const bool updown = updown_tangent_applies(def.solver, s) &&
                        (def.tangent == TangentChoice::Updown ||
                         (def.tangent == TangentChoice::Auto && d.geometry.dim == 3));
    // (a law of m > 1 values, friction, with the operators whole on the
    // rank (one process, or CHOLMOD on every rank): in 2D the Woodbury
    // identity over its blocks with A's factor, refactoring past the rank
    // limit; in 3D a column is a solve with a denser factor and a landing
    // activates hundreds of points: GMRES there, preconditioned by a
    // sticking tangent's factor kept while it serves; docs/performance.md,
    // "Friction". Every rank makes the same solves: one process's bits)
    const bool blocks = refactors && d.contact_law->traits().m > 1 && def.tangent == TangentChoice::Auto &&
                        !d.rows_split && d.geometry.dim == 2;
    const bool sticking = refactors && d.contact_law->traits().m > 1 && def.tangent == TangentChoice::Auto &&
                          !d.rows_split && d.geometry.dim == 3 && !linear_solver_iterative(def.solver);
    if (blocks) {
      in->tangent = make_block_tangent(in->A, *in->A_factor, def.solver, s, lowrank_rank_limit(in->A.n, d.contact),
                                       d.counters, &d.geometry);
    } else if (sticking) {
      in->tangent = make_sticking_tangent(in->A, *in->A_factor, def.solver, s, d.counters, &d.geometry);
    } else if (refactors) {
      // on split operators the solves keep the rows Newton reads (a rank's rows and their halo)
      std::vector<int64_t> held = in->held;  // a distributed state's rows, else those Newton reads
      if (held.empty() && d.rows_split) held = newton_held_rows(in->A, *d.rows, d.contact);
      in->tangent = make_refactoring_tangent(in->A, *in->A_factor, def.solver, s, d.counters, &d.geometry,
                                             std::move(held), !in->held.empty());
    } else if (updown) {
      in->tangent = make_updown_tangent(in->A, *in->A_factor, d.counters);
    } else {
      in->max_rank = def.tangent == TangentChoice::Auto ? lowrank_rank_limit(in->A.n, d.contact) : -1;
      // at most twice the rank limit held (the memory bound of lowrank_rank_limit);
      // on split operators each on the rank's rows and the points' DOFs
      in->columns = std::make_unique<ContactColumns>(
          *in->A_factor, in->A.n, in->max_rank >= 0 ? 2 * in->max_rank : static_cast<int64_t>(d.contact.size()),
          d.rows_split ? d.rows.get() : nullptr, in->held.empty() ? nullptr : &in->held, def.column_rows);
      in->tangent = make_lowrank_tangent(in->A, *in->A_factor, def.solver, s, in->max_rank, kLowRankTwoSolveRank,
                                         d.counters, &d.geometry, in->columns.get());
      if (def.tangent != TangentChoice::LowRank) in->condensed = std::make_unique<CondensedCache>(*in->columns);
    }
  }
  return in;
}

}  // namespace nd
