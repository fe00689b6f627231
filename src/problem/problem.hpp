// A problem, split by lifetime (docs/design.md §5): the definition (what the C API
// sets) -> the discretization derived from it -> the integrator (scheme and
// solvers for one step size) -> the state at t^n -> the monitors. Derived
// objects are built on demand and dropped when an aspect they depend on
// changes. A step builds the next state aside and commits it only when it
// succeeded, so a failed step leaves the problem exactly as it was.
#pragma once
#include <functional>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "fem/space.hpp"
#include "parallel/ownership.hpp"
#include "contact/obstacles.hpp"
#include "problem/definition.hpp"
#include "problem/checkpoint.hpp"
#include "problem/discretization.hpp"
#include "problem/integrator.hpp"

namespace nd {

class Problem {
 public:
  Problem(std::shared_ptr<const Mesh> mesh, int degree);

  // ---- definition
  void set_material(const Material &m);
  // The material of the cells of a cell region (ND_ERR_REGION: no cell in
  // it); the others keep the default (set_material), which stays required.
  void set_material_region(int cell_region, const Material &m);
  void add_dirichlet(int region);
  // Prescribed motion (docs/design.md §10.5): the displacement a clamped
  // region's nodes (dim values), or every clamped DOF (n_dofs values, the
  // free ones not read), take at t^{n+1} of the next step, as a load's value.
  void set_dirichlet_value(int region, const double *u);
  void set_dirichlet_nodal(const double *u);
  void set_body_force(const double *f);
  void add_neumann(int region, const double *g);
  // Sets the region's plane: replaces the one it has. With the same normal
  // only the point moves (the gaps change, nothing is rebuilt); after setup
  // the new point is where the obstacle is at t^{n+1} of the next step.
  void set_contact_plane(int region, const double *point, const double *normal);
  // Another rigid obstacle of the region (contact/obstacle.hpp), at its
  // definition's place until moved; at each point the nearest acts.
  void add_obstacle(int region, std::shared_ptr<const Shape> shape);
  // The region's obstacle `index` (0-based among those added) at x -> R x +
  // translation from its definition (rotation: dim x dim row-major, or
  // null); like a plane's point, where it is at t^{n+1} of the next step.
  void move_obstacle(int region, int index, const double *translation, const double *rotation);
  static constexpr double kRotationTolerance = 1e-12;
  // Contact between two regions (docs/design.md §10.3): the slave region's
  // points against the master region's surface; a slave region has one
  // master (set again: replaced)
  void set_contact_pair(int slave, int master);
  void set_nitsche(double theta, double gamma0);
  // the friction law of a contact region (law registered, parameter checked by its law)
  void set_friction(int region, int law, const double *params);
  // params: scheme_parameter_count(scheme) values, checked by the scheme
  void set_scheme(int scheme, const std::vector<double> &params);
  void set_nodal_forces(const double *f);  // n_dofs values
  void set_newton(const NewtonOptions &o);
  void set_mass_lumping(bool lumped);
  void set_damping(double alpha, double beta);  // checked by the caller: >= 0, finite
  void set_plane_stress(bool on);               // ND_ERR_DIMENSION outside 2D
  void set_mass_redistribution(bool on);
  void set_linear_solver(int solver);
  void set_timestep(double tau);
  // Adaptive time steps (docs/design.md §10.8; tolerance 0: off): each step
  // is judged by its error estimate and retried smaller, leaving no trace,
  // until it passes; the step that first touches is cut to land there.
  // Checked by the caller: finite, tolerance >= 0, 0 < tau_min <= tau_max.
  void set_adaptive_timestep(double tolerance, double tau_min, double tau_max);
  void set_initial_state(const double *u0, const double *v0);  // n_dofs each, or nullptr
  void set_guard(int guard, double value);  // an ND_GUARD_* and its value
  // The ranks that step this problem together (null: this process alone);
  // only before the set-up (ND_ERR_STATE after it). See step().
  void set_communicator(CommunicatorPtr comm);
  // Each rank keeps the state on the rows its steps read (with split rows:
  // the PETSc solvers over several ranks); the reads of whole vectors are
  // then collective. Only before the set-up (ND_ERR_STATE after it).
  void set_distributed_state(bool on);
  // Replaces U and V at the current time (n_dofs each, nullptr: unchanged);
  // t, n and W stay, A is re-derived from the equilibrium when the scheme
  // carries it, and the energy guard counts the change as energy put in.
  void overwrite_state(const double *u, const double *v);

  // The critical step of the scheme if it is conditionally stable, else of
  // the central difference: limit / omega_max (monitor/critical_step.hpp).
  double critical_timestep();

  // ---- checkpoint (problem/checkpoint.hpp)
  std::vector<unsigned char> save_state();
  void load_state(const unsigned char *buf, int64_t nbytes);  // all or nothing
  // the same block in a file, written atomically (common/atomic_file.hpp)
  void save_state_file(const char *path);
  void load_state_file(const char *path);
  // white-box (tests, benchmarks): the Newton tangent solver; drops the integrator
  void set_tangent(TangentChoice t) {
    def_.tangent = t;
    integrator_.reset();
  }
  // white-box (tests): a contact law outside the registry (contact/law.hpp)
  // in place of the definition's; null: the registry's again
  void set_contact_law(std::shared_ptr<const PointLaw> law) {
    def_.contact_law_given = std::move(law);
    changed(kNitsche);
  }
  // white-box: where the contact columns are held; drops the integrator
  void set_column_rows(ColumnRows at) {
    def_.column_rows = at;
    integrator_.reset();
  }
  // white-box: whether a step may show its contact checks by the bound
  // (ContactLaw::certainly_free); the same bits either way
  void set_contact_bounds(bool on) { def_.contact_bounds = on; }
  // white-box: whether a step may be its predictor (fast/predictor_check.hpp)
  void set_predicted_steps(bool on) { def_.predicted_steps = on; }

  // ---- queries
  const Space &space() const { return space_; }
  CellMaterials materials() const { return materials_of(space_, def_); }
  const Definition &definition() const { return def_; }  // white-box (tests)
  const Discretization &discretization() { return discretization_(); }
  // white-box (tests): the state at t^n in free DOFs, with its load and gaps
  const State &current_state() { return state(); }
  // white-box (tests): its products as held beside it (time/products.hpp; of = 0: none yet)
  const Products &current_products() {
    state();
    return products_;
  }
  // the integrator once built (benchmarks time its solve: the floor of a step)
  const Integrator *integrator() const { return integrator_.get(); }
  const Counters &counters() const { return *counters_; }
  void field(int which, double *full);  // n_dofs values
  // The cells and FE nodes each rank owns (parallel/ownership.hpp; all of
  // them without a communicator).
  const Ownership &ownership();
  // This rank's nodes: their count, and a field's values at them (count *
  // dim, node-major) with their node numbers, ascending; either may be null.
  int64_t owned_node_count();
  void owned_field(int which, double *values, int64_t *nodes);
  // The whole field (n_dofs values) on `root` alone, each node's values from
  // the rank that owns it. Collective; the ranks agree on `which` and `root`
  // (ND_ERR_VALUE on every rank otherwise), then on the outcome.
  void gathered_field(int which, int root, double *full);
  // Runs `local` on every rank of the communicator, then makes its outcome
  // the ranks': a rank it failed on rethrows, the others fail with the worst
  // status. Collective (without a communicator: just `local`).
  void on_every_rank(const std::function<void()> &local);
  // The argument checks of a call that reads whole vectors (fields,
  // checkpoints): with a partial state it completes it, collectively, so
  // the ranks agree on the call (collective) and on the checks first
  // (refused on one rank, refused on all).
  void check_whole_read(const char *call, const std::function<void()> &checks);
  // The header every collective call of a problem on several ranks begins
  // with (parallel/communicator.hpp, agree_on_call): the ranks must be in the
  // same call, the call-th of each (ND_ERR_STATE on every rank otherwise, at
  // once, or after NITSCHEDYN_MPI_TIMEOUT on a rank left waiting), and what a rank
  // rebuilds (a factorization, collective with PETSc), every rank rebuilds.
  // `call` is the C function's name (one of kCollectiveCalls); returns
  // whether the ranks' digests agree. Nothing without a communicator.
  bool collective(const char *call, uint64_t digest = 0);
  int rank() const { return communicator_rank(def_.comm.get()); }
  int rank_count() const { return communicator_size(def_.comm.get()); }
  double scalar(int key);               // an ND_* scalar key
  // a contact scalar (the force, the applied force, the active points, the
  // deepest penetration, R) of one contact region's points alone
  double region_scalar(int region, int key);
  std::vector<double> contact_pressure();  // lambda_q
  // -phi_q/gamma_q: the pressure the last step applied (lambda_q before any step)
  std::vector<double> contact_pressure_applied();

  // Discretization, integrator, initial state: what the first step needs;
  // done once until the definition changes.
  void setup(const char *call = "nd_problem_setup");  // (call: the C function, for collective())
  // Advances one step; throws nd::Error (state untouched) on failure.
  // With a communicator both are collective, and the ranks agree: first that
  // their inputs are the same (ND_ERR_STATE on every rank otherwise), then on
  // the outcome, so that every rank takes the step or none does (with the
  // worst status of all ranks).
  void step();

 private:
  // one step of size def_.tau; with `attempt`, judged as an adaptive step
  // (its error estimate, its first touch), which throws Rejected to retry
  struct Attempt {
    bool may_land = true;   // the step may be cut to land at the first touch
    bool retried = false;   // a try of this step was rejected or failed
  };
  void step_once(const Attempt *attempt);
  // adaptive steps (problem/adaptive_step.cpp)
  void adaptive_step();
  // (from: the state the step started from, its references in the step's rows)
  void judge_step(const Attempt &attempt, const State &from, State &next, const Products &next_products);
  // the integrator of step size tau in use: kept, or built at the next
  // prepare(); the one in use kept for its size (kKeptSizes at most)
  void use_timestep(double tau);
  void changed(unsigned aspects);
  void prepare();  // setup() without the ranks' agreement
  void agree_on_inputs(const char *call);  // collective(call, inputs_digest()), ND_ERR_STATE if they differ
  // changed() without the definition's `given`: drops what depends on `aspects`
  void drop(unsigned aspects);
  uint64_t inputs_digest() const;
  Discretization &discretization_();
  Discretization &discretization_agreed();  // collective with split rows: discretization_() agreed by the ranks
  const std::vector<double> &constant_load_();
  Integrator &integrator_or_build();
  // the explicit schemes' highest frequency with every contact point active
  // or none (the larger), and the free motion's, a lower bound
  // (monitor/critical_step.hpp): estimated once per discretization
  void estimate_frequencies();
  double omega_max();
  double omega_free();
  const State &state();
  // a partial state's other rows gathered from their owners (collective;
  // nothing when the state is whole)
  void complete_state();
  StateSizes state_sizes();
  const std::shared_ptr<const std::vector<double>> &current_load();
  std::shared_ptr<const std::vector<double>> with_nodal(std::shared_ptr<const std::vector<double>> F_const,
                                                        const std::vector<double> &nodal);
  const std::vector<double> &clamped_load_();  // the load on the clamped DOFs (empty: none)
  // g_q with the planes where the definition has them (kept until a plane or
  // the discretization changes: a step copies them, not computes them)
  const std::vector<double> &current_gaps();
  std::vector<double> reaction_at_equilibrium(const State &s);
  // curved obstacles (none: normal, positions emptied): the state's frozen
  // normals (d's rows'), its obstacles' positions (at's) and its curved
  // points' gaps at U, where `at` places the obstacles now
  void curved_gaps(State &s, const Discretization &d, const TimeData &at);
  StepGeometry curved_geometry(const std::vector<double> &plane_gaps);
  double relinearised_nitsche_energy(const State &from, const std::vector<double> &gap_n);
  void require_region(int region, const char *what) const;

  std::shared_ptr<const Mesh> mesh_;
  Space space_;
  std::shared_ptr<const Ownership> ownership_;  // made with the communicator (null: not yet needed)
  uint64_t mesh_digest_;  // of the mesh and the space (inputs_digest)
  Definition def_;
  // the aspects changed since the ranks last agreed (collective()): what this
  // rank rebuilds, and so (with several ranks) every rank
  unsigned pending_ = 0;
  // derived, each dropped by changed() when an aspect it depends on changes
  std::unique_ptr<Discretization> disc_;
  std::vector<double> gaps_;  // current_gaps() of the discretization whose id gaps_of_ holds (0: none)
  uint64_t gaps_of_ = 0;
  std::shared_ptr<const std::vector<double>> load_;  // body force and tractions on the free DOFs
  // with the nodal forces: F^{n+1} (without any: load_ itself, not a copy)
  std::shared_ptr<const std::vector<double>> step_load_;
  std::unique_ptr<std::vector<double>> load_fixed_;  // clamped_load_()
  // the work counters (ND_STAT_*), since creation; a stable address the derived objects keep
  std::unique_ptr<Counters> counters_ = std::make_unique<Counters>();
  std::unique_ptr<Integrator> integrator_;
  // adaptive steps: the integrators of the last step sizes used (their A
  // factored), for the discretization whose id `of` holds; most recent first
  struct KeptIntegrator {
    double tau;
    uint64_t of;
    std::unique_ptr<Integrator> in;
  };
  std::vector<KeptIntegrator> kept_integrators_;
  // a new integrator since the last step: it may hold other rows and points
  // than the one that made a distributed state (another solver, another
  // Newton path), so the next step completes the state first
  bool integrator_new_ = false;
  std::unique_ptr<Factorization> spare_A_factor_;  // of a dropped integrator: A's pattern analysed
  // during a step's refresh of the contact rows: the kept integrator's factor,
  // whose ordering the new one reuses (A's pattern is the same)
  const Factorization *refresh_ordering_ = nullptr;
  bool obstacle_redefined_ = false;  // a new plane (not a motion): the state's gaps follow
  State state_;
  // state_'s products (time/products.hpp): a cache beside the state, reset
  // (replace_state) wherever state_ is replaced
  Products products_;
  // the state and products before state_ (values not read): the next step reuses their memory
  StateWithProducts spare_;
  void replace_state(State &&s, Products &&p = Products{});
  bool state_ready_ = false;
  bool initial_guarded_ = false;  // the initial state passed guard_initial_state
  bool setup_done_ = false;  // F^0 is fixed: a load set now is F^{n+1} (docs/design.md §8)
  // Before the first step a host sets f(0), then f(t^1), then steps: the
  // first value of each load and obstacle position is t^0's, a second one
  // t^1's (docs/design.md §8). given_ names what has a value (kind, region);
  // start_ holds t^0's values once a second value came.
  std::set<std::pair<int, int>> given_;
  std::unique_ptr<TimeData> start_;
  // before a setter changes the load or position `what`: fixes t^0's values
  // if this is its second value before the first step
  void giving(std::pair<int, int> what);
  Definition at_start() const;  // the definition with t^0's loads and positions
};

}  // namespace nd
