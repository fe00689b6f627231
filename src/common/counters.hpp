// Per-problem work counters (ND_STAT_* scalars): one struct owned by the
// problem and passed down to where the work happens. No globals: distinct
// handles may step in distinct threads. They count work done, failed steps
// included, since the problem was created; they are not part of the state
// (a checkpoint neither saves nor restores them).
#pragma once
#include <cstdint>

namespace nd {

struct Counters {
  int64_t factorizations = 0;       // numeric factorizations of any matrix
  int64_t symbolic_analyses = 0;    // factorization objects made for a pattern
  int64_t solves = 0;               // forward/backward solves, per right-hand side
  int64_t matrix_assemblies = 0;    // M, K, K_Theta, A (and c M + K_Theta for checks)
  int64_t load_assemblies = 0;      // load vectors built
  int64_t tangent_updates = 0;      // capacitance builds or tangent assemblies
  int64_t contact_evaluations = 0;  // passes over all contact points
  int64_t spmv = 0;                 // sparse matrix-vector products (fused passes count once)
  // P_q of one point evaluated in a step (ContactLaw::P_all): by all the
  // ranks together (the same count as on one rank), and by this rank
  int64_t point_evaluations = 0, own_point_evaluations = 0;
  // contact checks settled by ContactLaw::certainly_free's bound, no point evaluated
  int64_t contact_bounds = 0;
  // values this rank received from the others: the rows, points and sums of
  // the split work (parallel/share.hpp) and the solutions of the distributed
  // solves (the other ranks' rows of each)
  int64_t values_received = 0;
  // of them, the contact points' values (P_q, u_n - g0): gathered, or
  // exchanged with the ranks whose rows a point touches (ContactLaw::halo)
  int64_t point_values_received = 0;
  // iterations of the Krylov solves of an iterative backend (GAMG)
  int64_t krylov_iterations = 0;
  // implicit steps their predictor solved (fast/predictor_check.hpp): no solve
  int64_t predicted_steps = 0;
  // steps whose first Newton iteration kept the last step's tangent (the
  // updated factor, fast/tangent_updown.cpp: kLagSolves)
  int64_t lagged_steps = 0;
  // steps nd_step took, and adaptive steps it tried and rejected (retried smaller)
  int64_t steps_accepted = 0, steps_rejected = 0;
  int64_t normal_refreshes = 0;  // curved obstacles: points whose frozen normal was made again
  // the updated factor's rank-one modifications (columns updated or
  // downdated), and their work: the entries of L times the vectors that
  // rotated them (UpdatableCholesky::modified_entries)
  int64_t factor_modifications = 0, factor_modified_entries = 0;
  // not a count: the entries of M, K and K_Theta held now (a rank's rows
  // when they are split over the ranks, problem/discretization.hpp)
  int64_t matrix_entries = 0;
};

// c->*field += by when there is a counter struct (unit tests pass none)
inline void count(Counters *c, int64_t Counters::*field, int64_t by = 1) {
  if (c) c->*field += by;
}

}  // namespace nd
