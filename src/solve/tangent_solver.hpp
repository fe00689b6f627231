// The seam between Newton and the factorizations: solves with the Newton
// tangent T(U) = A + kappa N'(U), A = c M + K_Theta factored once per time
// step size. Two implementations: the reference refactors T numerically at
// every Newton iteration with an active point (the symbolic analysis of A's
// pattern reused); the low-rank one (docs/design.md §4) never refactors: with B, P the
// columns b_q, p_q of the k active points and D = diag(kappa w_q/gamma_q phi'_q),
// T = A + B D P^T and (Woodbury, scaled capacitance)
//   T^{-1} x = y - Z (I + D P^T Z)^{-1} D P^T y,  y = A^{-1} x,  Z = A^{-1} B,
// the columns Z_q cached for the solver's lifetime, the k x k system dense (LAPACK LU).
#pragma once
#include <cstdint>
#include <memory>

#include "linalg/factorization.hpp"
#include "solve/contact_columns.hpp"
#include "solve/contact_law.hpp"
#include "time/state.hpp"

namespace nd {

struct NodeBlocks;  // (linalg/node_blocks.hpp)

// What a tangent solver did, for tests and benchmarks.
struct TangentStats {
  int64_t calls = 0;             // solve() calls
  int64_t refactorizations = 0;  // numeric factorizations of T
  int64_t restarts = 0;          // T rebuilt from A's factor by updates (the updated factor)
  int64_t lowrank = 0;           // calls solved by the Woodbury update (k >= 1)
  int64_t columns = 0;           // columns Z_q = A^{-1} b_q computed (each one solve with A's factor)
  int64_t max_rank = 0;          // the largest k seen
  int64_t krylov = 0;            // Krylov iterations (the sticking tangent's GMRES)
};

class TangentSolver {
 public:
  virtual ~TangentSolver() = default;
  // x <- T(U)^{-1} x; with no active point T(U) = A, solved from `guess`
  // where the solver is iterative (Factorization::solve_from; null: from 0).
  // P: P_q(U) as Newton's residual at this U left it (ContactLaw::add_force),
  // or null: the solver evaluates the points (the same bits either way)
  virtual void solve(const ContactLaw &law, double kappa, const double *U, bool any_active, double *x,
                     const double *guess = nullptr, const std::vector<double> *P = nullptr) = 0;
  virtual const char *name() const = 0;
  // The step starts from a state whose tangent history is `committed`
  // (TangentLog, time/state.hpp); log(): the history after the step's
  // solves, for the next state (nullptr: this solver keeps none). Only the
  // updated factor (make_updown_tangent) has one; the others' bits depend on
  // nothing but U.
  virtual void begin_step(const TangentLog &committed) { (void)committed; }
  virtual const TangentLog *log() const { return nullptr; }
  // The rows at which solve() with an active point leaves x right
  // (ascending), or null: every row, as every solve without one. On split
  // operators a solver may keep a rank's rows and the rows Newton reads there
  // (make_refactoring_tangent's `held`); the others are NaN, and newton_solve
  // gathers them from their ranks once, at its end.
  virtual const std::vector<int64_t> *held() const { return nullptr; }
  TangentStats stats;

 protected:
  // With no active point T = A: x solved with A's factor from `guess`
  // (true: done). The solvers that keep no rows of their own start so.
  static bool solved_without_contact(const Factorization &A_factor, bool any_active, double *x, const double *guess) {
    if (any_active) return false;
    A_factor.solve_from(x, guess);
    return true;
  }
};

// Which tangent solver make_integrator builds (white-box: tests, benchmarks).
enum class TangentChoice {
  Auto,       // the condensed Newton (solve/newton_condensed.hpp); past the measured rank
              // limit (lowrank_rank_limit) the full Newton with the low-rank tangent, refactoring
  Refactor,   // the reference: the full Newton, T refactored
  LowRank,    // the full Newton with the low-rank tangent at every rank
  Condensed,  // the condensed Newton at every rank
  Updown,     // the full Newton with the updated factor of T at every rank (Theta = 1)
};

// A and its factor must outlive the solver. solver: ND_SOLVER_* for the
// tangent, structure: the tangent's (symmetric positive definite iff Theta = 1).
// counters: where the tangent's own factorizations are counted (or none); the
// contact evaluations and tangent updates go to the ContactLaw's.
// geometry (may be null): for the tangent's factorizations (DofGeometry).
// held (ascending; empty: every row): on split operators, the rows the solves
// with an active point keep (TangentSolver::held; newton_held_rows), and with
// linear_held those of Newton's linear step too (a distributed state).
std::unique_ptr<TangentSolver> make_refactoring_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                        Structure structure, Counters *counters = nullptr,
                                                        const DofGeometry *geometry = nullptr,
                                                        std::vector<int64_t> held = {}, bool linear_held = false);

// The updated factor (Theta = 1, T symmetric positive definite): a
// Cholesky factor of T (linalg/updatable_cholesky.hpp) kept from solve to
// solve and from step to step,
// changed by rank updates and downdates as points enter and leave the active
// set (solve/tangent_updown.cpp); refactored when the changes since its last
// factorization outgrow a bound.
// At most this many columns updated since the factorization, for n_points
// contact points: the room of a TangentLog in a checkpoint (1 + points + 2
// of these indices, points + these coefficients). The updated factor
// usually refactors earlier, by its cost model (solve/tangent_updown.cpp).
int64_t updown_max_updates(int64_t n_points);
// Reserves the room of a history's largest form for n_points (that bound):
// a history that grows step by step then allocates nothing.
void reserve_tangent_log(TangentLog &log, int64_t n_points);
// factor_weight scales the cost model's price of a factorization (tests: a
// tiny weight refactors at every change, a huge one only updates).
// Two bodies (contact/pairing.hpp): a pair's point couples its slave cell's
// DOFs with its master cell's, which A's pattern (the cells') lacks. The
// pattern of A and of every point's a_q x a_q (s_q has a_q's index list),
// with A's entry k at place[k]: the pattern a tangent with pairs is
// assembled and factored on.
Csr widened_pattern(const Csr &A, const ContactPoints &cp, std::vector<int64_t> &place);

std::unique_ptr<TangentSolver> make_updown_tangent(const Csr &A, const Factorization &A_factor,
                                                   Counters *counters = nullptr, double factor_weight = 1.0);
// Whether a history (from a checkpoint) has the form the updated factor
// writes for n_points contact points: indices in range and increasing within
// the base and each update, coefficients finite and positive, at most
// updown_max_updates(n_points) columns updated.
bool tangent_log_well_formed(const TangentLog &log, int64_t n_points);
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
// solve/tangent_blocks.cpp): the Woodbury identity over the active points'
// m values with A's factor; past max_rank values (negative: no limit) T is
// refactored (make_refactoring_tangent, held inside).
std::unique_ptr<TangentSolver> make_block_tangent(const Csr &A, const Factorization &A_factor, int solver,
                                                  Structure structure, int64_t max_rank, Counters *counters = nullptr,
                                                  const DofGeometry *geometry = nullptr);

// The tangent of a law with m > 1 values per point where its columns cost
// more than factoring (friction in 3D: solve/tangent_sticking.cpp): GMRES
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
