// The seam between Newton and the factorizations: solves with the Newton
// tangent T(U) = A + kappa N'(U), A = c M + K_Theta factored once per time
// step size. The reference here refactors T numerically at every Newton
// iteration with an active point (the symbolic analysis of A's pattern
// reused), for any law; the solvers that avoid it (the low-rank update, the
// updated factor, friction's blocks and sticking preconditioner) are the step
// driver's fast paths, in src/fast (fast/tangents.hpp), each asking whether
// it applies. The tangent's history (TangentLog), which fixes an updated
// factor's bits, is the checkpoint's: its format is here.
#pragma once
#include <cstdint>
#include <memory>

#include "linalg/factorization.hpp"
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
  // updated factor (fast/tangents.hpp: make_updown_tangent) has one; the others' bits depend on
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

// At most this many columns updated since the factorization, for n_points
// contact points: the room of a TangentLog in a checkpoint (1 + points + 2
// of these indices, points + these coefficients). The updated factor
// usually refactors earlier, by its cost model (fast/tangent_updown.cpp).
int64_t updown_max_updates(int64_t n_points);
// Reserves the room of a history's largest form for n_points (that bound):
// a history that grows step by step then allocates nothing.
void reserve_tangent_log(TangentLog &log, int64_t n_points);
// Two bodies (contact/pairing.hpp): a pair's point couples its slave cell's
// DOFs with its master cell's, which A's pattern (the cells') lacks. The
// pattern of A and of every point's a_q x a_q (s_q has a_q's index list),
// with A's entry k at place[k]: the pattern a tangent with pairs is
// assembled and factored on.
Csr widened_pattern(const Csr &A, const ContactPoints &cp, std::vector<int64_t> &place);

// Whether a history (from a checkpoint) has the form the updated factor
// writes for n_points contact points: indices in range and increasing within
// the base and each update, coefficients finite and positive, at most
// updown_max_updates(n_points) columns updated.
bool tangent_log_well_formed(const TangentLog &log, int64_t n_points);

}  // namespace nd
