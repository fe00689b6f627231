// The Newton tangent's fast paths (the step driver's alone: src/problem
// chooses among them in make_integrator). Each solves with the same T(U) =
// A + kappa N'(U) as the reference make_refactoring_tangent
// (solve/tangent_solver.hpp) and steps aside where it does not apply. The
// low-rank one (docs/design.md §4) never refactors: with B, P the
// columns b_q, p_q of the k active points and D = diag(kappa w_q/gamma_q phi'_q),
// T = A + B D P^T and (Woodbury, scaled capacitance)
//   T^{-1} x = y - Z (I + D P^T Z)^{-1} D P^T y,  y = A^{-1} x,  Z = A^{-1} B,
// the columns Z_q cached for the solver's lifetime, the k x k system dense (LAPACK LU).
#pragma once
#include <cstdint>
#include <memory>

#include "fast/contact_columns.hpp"
#include "solve/tangent_solver.hpp"

namespace nd {

// Which tangent solver make_integrator builds (white-box: tests, benchmarks).
enum class TangentChoice {
  Auto,       // the condensed Newton (fast/newton_condensed.hpp); past the measured rank
              // limit (lowrank_rank_limit) the full Newton with the low-rank tangent, refactoring
  Refactor,   // the reference: the full Newton, T refactored
  LowRank,    // the full Newton with the low-rank tangent at every rank
  Condensed,  // the condensed Newton at every rank
  Updown,     // the full Newton with the updated factor of T at every rank (Theta = 1)
};

// The updated factor (Theta = 1, T symmetric positive definite): a
// Cholesky factor of T (linalg/updatable_cholesky.hpp) kept from solve to
// solve and from step to step,
// changed by rank updates and downdates as points enter and leave the active
// set (fast/tangent_updown.cpp); refactored when the changes since its last
// factorization outgrow a bound.
// factor_weight scales the cost model's price of a factorization (tests: a
// tiny weight refactors at every change, a huge one only updates).
std::unique_ptr<TangentSolver> make_updown_tangent(const Csr &A, const Factorization &A_factor,
                                                   Counters *counters = nullptr, double factor_weight = 1.0);

// Whether a contact law's tangent suits the solvers that add and drop terms
// phi'_q b_q p_q^T with phi'_q >= 0 (the low-rank tangent, the updated factor,
// the condensed Newton): rank-one blocks, a nondecreasing law (LawTraits).
// Else the refactoring tangent, which assembles any law's blocks.
inline bool rank_one_updates_apply(const LawTraits &law) { return law.rank_one && law.nondecreasing; }
// (throws ND_ERR_INTERNAL naming `who` unless they apply: a caller that did not ask)
void require_rank_one_updates(const ContactLaw &law, const char *who);

// Whether the updated factor serves this solver and tangent structure: the
// symmetric tangent, with the library's choice of direct solver or CHOLMOD.
bool updown_tangent_applies(int solver, Structure structure);

// The low-rank solver. Calls with more than max_rank active points are
// solved by the updated factor where updown_tangent_applies, else by a
// refactoring tangent, held inside (made on first need); a
// negative max_rank: no limit. With more than two_solve_rank active points
// (negative: never) T^{-1} x = A^{-1}(x - B w) replaces y - Z w: a second
// solve with A's factor instead of n k multiply-adds. columns: a column
// cache made for A's factor to share (with the condensed Newton), or none:
// the solver keeps its own.
std::unique_ptr<TangentSolver> make_lowrank_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                    Structure structure, int64_t max_rank,
                                                    int64_t two_solve_rank = -1, Counters *counters = nullptr,
                                                    const DofGeometry *geometry = nullptr,
                                                    ContactColumns *columns = nullptr);

// The low-rank tangent of a law with m > 1 values per point (friction:
// fast/tangent_blocks.cpp): the Woodbury identity over the active points'
// m values with A's factor; past max_rank values (negative: no limit) T is
// refactored (make_refactoring_tangent, held inside).
std::unique_ptr<TangentSolver> make_block_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                  Structure structure, int64_t max_rank, Counters *counters = nullptr,
                                                  const DofGeometry *geometry = nullptr);

// The tangent of a law with m > 1 values per point where its columns cost
// more than factoring (friction in 3D: fast/tangent_sticking.cpp): GMRES
// on T, preconditioned by the factor of the sticking tangent of T's active
// set, refactored only when that set changes; T refactored itself where
// GMRES does not converge. A_blocks: A by nodes (Integrator::A_blocks, the
// bits of A's CSR product), or null.
std::unique_ptr<TangentSolver> make_sticking_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                     Structure structure, Counters *counters = nullptr,
                                                     const DofGeometry *geometry = nullptr,
                                                     const NodeBlocks *A_blocks = nullptr);

// The rank above which the second solve beats Z w: the measured crossovers
// lie on either side of it, and near it the two variants cost about the
// same (docs/performance.md, "Second solve or Z w").
constexpr int64_t kLowRankTwoSolveRank = 100;

// The measured rank above which refactoring T beats the low-rank update
// (bench/tangent_bench, bench/results/tangent_crossover.csv), for n unknowns
// and the contact points cp.
int64_t lowrank_rank_limit(int64_t n, const ContactPoints &cp);

}  // namespace nd
