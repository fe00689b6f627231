// The integrator for one time scheme and one step size: the scheme, the step
// operator A = c M + K_Theta with its factorization, and the tangent solver
// of the Newton iterations. advance() is the step driver: it names no scheme.
#pragma once
#include <functional>
#include <memory>
#include <vector>

#include "linalg/factorization.hpp"
#include "problem/definition.hpp"
#include "problem/discretization.hpp"
#include "problem/massless.hpp"
#include "fast/newton_condensed.hpp"
#include "fast/tangents.hpp"
#include "time/scheme.hpp"

namespace nd {

struct Integrator {
  std::unique_ptr<TimeScheme> scheme;
  double tau = 0;
  StepCoefficients coef{0, 0};
  Csr A;  // c M + K_Theta (implicit schemes), + damping * C with damping
  // the coefficient of C in A: kappa (1 - a) dV^{n+1}/dU^{n+1}, a the
  // scheme's mean_weight (docs/design.md §10.5); 0 without damping
  double damping = 0;
  // explicit scheme, beta > 0: M + slope C factored, slope = dV^{n+1}/dA^{n+1}
  Csr damped_mass;
  std::unique_ptr<Factorization> damped_mass_factor;
  // A and M by nodes for Newton's residual, where the discretization has
  // its operators so (Discretization::node_blocks) and contact points
  std::shared_ptr<const NodeBlocks> A_blocks;
  std::unique_ptr<Factorization> A_factor;
  // the columns A^{-1} b_q of both fast paths (before them: they hold it),
  // the low-rank or refactoring tangent when there are contact points, and
  // what the condensed Newton keeps (not with the refactoring reference, nor
  // the forced low-rank path)
  std::unique_ptr<ContactColumns> columns;
  std::unique_ptr<TangentSolver> tangent;
  // the contact points a rank's Newton reads with the refactoring tangent on
  // split rows (ContactLaw::halo), or null: every point gathered
  std::shared_ptr<const Halo> halo;
  // a distributed state (Definition::distributed_state on split rows): the
  // rows every solve of a step keeps, the new state right there only
  // (newton_held_rows with the clamped rows' columns); empty: whole vectors
  std::vector<int64_t> held;
  // with a distributed state and a halo: the contact points this
  // rank holds (held_points); the state is right at their DOFs only, and the
  // new state's pass evaluates them only. Null: every point on every rank.
  std::shared_ptr<const HeldPoints> points;
  std::unique_ptr<CondensedCache> condensed;
  int64_t max_rank = -1;  // the most active points the condensed Newton takes (negative: any)
  std::unique_ptr<MasslessSolver> massless;  // explicit scheme with massless DOFs (mass redistribution)
  ContactScratch contact_scratch;  // the buffers of the step's contact passes (ContactLaw::buffers)
  std::vector<double> rhs;  // a step's right-hand side (kept for its memory; its values are not read again)
  // a step's n-long workspace: the schemes' K_Theta U^n, the predictor's
  // residual (likewise)
  std::vector<double> scratch;
  // Newton's vectors, and the points at a step's solution (a step's
  // at_U), kept likewise: the points' memory goes round between these, the
  // Newton's and the states' products, exchanged, never made anew
  NewtonWork newton;
  PointValues at_solution;
};

// A = c M + K_Theta (+ damping C) of an implicit scheme: the step matrix;
// returns the coefficient of C (0 without damping)
double step_matrix(const Discretization &d, const TimeScheme &scheme, double tau, Csr &A);

// Factorizes A for an implicit scheme, or (K_Theta)_mm for an explicit one
// with massless DOFs: throws ND_ERR_INDEFINITE when the step is not well posed. reuse: a factorization made for A's pattern (of
// this discretization and solver), or none: its symbolic analysis is reused.
// own_part (several ranks): this rank's part of A for the scheme's c
// (assemble_own_step_matrix), from which a distributed solver assembles A.
// ordered_like (without reuse; may be null): a factor of a matrix of A's
// pattern, whose fill-reducing ordering A's reuses (make_factorization): a
// refresh of the contact rows keeps A's pattern, and the old factor, which
// a failed step gives back, stays as it is.
std::unique_ptr<Integrator> make_integrator(Discretization &d, const Definition &def,
                                            std::unique_ptr<Factorization> reuse = nullptr,
                                            const std::function<Csr(double)> &own_part = {},
                                            const Factorization *ordered_like = nullptr);

// What is prescribed at t^{n+1}: the load on the free DOFs and on the clamped
// ones (empty: none), and the gaps g_q of the obstacle where it is then.
// gap_old (curved obstacles, contact/obstacles.hpp): g^n as this step sees
// it, the obstacles at t^n measured from U^n with this step's normals
// (null: the old state's gaps, as for planes alone).
struct StepData {
  std::shared_ptr<const std::vector<double>> F;  // (the next state shares it)
  const std::vector<double> &F_fixed, &gap;
  const std::vector<double> *gap_old = nullptr;
  // the clamped DOFs' prescribed displacement at t^{n+1} (ClampedRows order;
  // null or empty: none, at 0 unless the old state moved them)
  const std::vector<double> *Uc = nullptr;
  // friction against a moving obstacle: the shift of the slip references
  // over the step (solve/friction.hpp: obstacle_slip; null or empty: none)
  const std::vector<double> *slip_shift = nullptr;
};

// A state and its products (time/products.hpp): the cache kept beside it
struct StateWithProducts {
  State state;
  Products products;
};

// The state at t^{n+1} from `old` (old_products: its products, read when
// current, else made aside) with the data at t^{n+1}, and its products;
// also the obstacle's work and the reactions of the step. Throws (and
// changes nothing) when the step fails. storage: a state and products no
// longer needed (the ones before `old`), whose vectors' memory the new ones
// reuse, so that a free-flight step allocates nothing once a run is under way.
StateWithProducts advance(Integrator &in, Discretization &d, const Definition &def, const State &old,
                          const Products &old_products, const StepData &at_new,
                          StateWithProducts &&storage = StateWithProducts{});

}  // namespace nd
