#include "problem/problem.hpp"

#include <algorithm>
#include <cmath>

#include <functional>
#include <limits>
#include <new>
#include <string>

#include "common/format.hpp"
#include "common/hash.hpp"
#include "monitor/critical_step.hpp"
#include "monitor/energies.hpp"
#include "solve/friction.hpp"
#include "solve/products.hpp"
#include "monitor/guards.hpp"
#include "common/atomic_file.hpp"
#include "linalg/blas_threads.hpp"
#include "problem/checkpoint.hpp"
#include "parallel/agreement.hpp"
#include "parallel/ownership.hpp"
#include "parallel/share.hpp"
#include "problem/forces.hpp"
#include "solve/clamped_coupling.hpp"
#include "contact/obstacles.hpp"

namespace nd {

// What each derived object depends on; the setters only name their aspect.
constexpr unsigned kDiscretizationDeps = kMaterial | kDirichlet | kContact | kNitsche | kLumping | kDamping;
constexpr unsigned kLoadDeps = kDiscretizationDeps | kLoads;
constexpr unsigned kMassFactorDeps = kDiscretizationDeps | kSolver;
constexpr unsigned kIntegratorDeps = kDiscretizationDeps | kScheme | kTimestep | kSolver;
// Before the first step the state at t^0 (its load F^0 and acceleration A^0)
// is derived from the definition; later the state is the history and stays
// (a changed load enters as F^{n+1}); new initial values always replace it.
constexpr unsigned kInitialStateDeps = kLoadDeps | kNodal | kObstacle | kMotion | kInitial;

namespace {
// a full vector's (n_dofs) values at the clamped DOFs, in ClampedRows order
std::vector<double> clamped_values(const Discretization &d, const std::vector<double> &full) {
  std::vector<double> c(d.clamped->dofs.size());
  for (size_t r = 0; r < c.size(); ++r) c[r] = full[d.clamped->dofs[r]];
  return c;
}

// the mesh and the space, for the ranks' agreement (Problem::inputs_digest)
uint64_t mesh_digest(const Mesh &m, const Space &s) {
  Hash h;
  h.value(s.dim), h.value(s.degree);
  h.vec(m.coords), h.vec(m.cells);
  if (m.cell_type) h.value(m.cell_type);  // (simplices: the digest as before)
  if (!m.cell_region.empty()) h.vec(m.cell_region);  // (none: the digest of a mesh without them)
  for (const auto &[region, facets] : m.regions) {
    h.value(region);
    for (int64_t f : facets) h.value(f);
  }
  return h.h;
}

// An explicit step the energy guards refused, above the critical step with
// every contact point active: the cause, in the guard's message
[[noreturn]] void explain_explicit_refusal(const Discretization &d, const TimeScheme &scheme, double tau) {
  try {
    throw;
  } catch (const Error &e) {
    const double limit = scheme.stability_limit();
    if ((e.code() != ND_ERR_ENERGY_GROWTH && e.code() != ND_ERR_PENETRATION) || !std::isfinite(limit) ||
        !(d.omega_max > 0) || !(tau * d.omega_max > limit))
      throw;
    throw Error(e.code(), std::string(e.what()) + " (the explicit step " + num(tau) +
                              " is above its critical step with every contact point active, " +
                              num(limit / d.omega_max) + " (nd_problem_estimate_critical_timestep): the active " +
                              "points' penalty makes it unstable; lower the time step or raise gamma0)");
  }
}

}  // namespace

Problem::Problem(std::shared_ptr<const Mesh> mesh, int degree)
    : mesh_(std::move(mesh)), space_(mesh_, degree), mesh_digest_(mesh_digest(*mesh_, space_)) {}

void Problem::changed(unsigned aspects) {
  def_.given |= aspects;
  pending_ |= aspects;
  drop(aspects);
  if (aspects & kContact) obstacle_redefined_ = true;
  // once t^0's loads are fixed (set up, or a second value given) a load is
  // F^{n+1} of the next step, also at n = 0
  const unsigned initial = kInitialStateDeps & ~(setup_done_ || start_ ? kLoads | kNodal | kObstacle | kMotion : 0u);
  if ((aspects & kInitial) || ((aspects & initial) && state_.n == 0)) {
    state_ready_ = false;
    setup_done_ = false;
  }
  if (!state_ready_ || (aspects & (kGuards | kDiscretizationDeps))) initial_guarded_ = false;
}

// (caches only: each is made again from the definition, the same)
void Problem::drop(unsigned aspects) {
  // (the operators hold a rank's rows only with a distributed solver on several ranks)
  if ((aspects & kDiscretizationDeps) || (disc_ && (aspects & kSolver) && disc_->rows_split != splits_rows(def_)))
    disc_.reset();
  if (disc_ && (aspects & kMassFactorDeps)) disc_->M_factor.reset();
  if (aspects & kLoadDeps) load_.reset();
  if (aspects & (kLoadDeps | kNodal)) {
    load_fixed_.reset();
    step_load_.reset();
  }
  if (aspects & (kContact | kObstacle)) gaps_of_ = 0;
  if (aspects & kIntegratorDeps) {
    // a new tau or scheme refactors A = c M + K_Theta on the same pattern:
    // its symbolic analysis is kept for the next integrator
    if (integrator_ && integrator_->A_factor) spare_A_factor_ = std::move(integrator_->A_factor);
    integrator_.reset();
    kept_integrators_.clear();
  }
  if (aspects & (kDiscretizationDeps | kSolver)) spare_A_factor_.reset();
}

// ---- definition -------------------------------------------------------------

void Problem::require_region(int region, const char *what) const {
  auto it = mesh_->regions.find(region);
  if (it == mesh_->regions.end() || it->second.empty())
    fail(ND_ERR_REGION, "region " + std::to_string(region) + " (" + what +
                            ") has no facets in the mesh the problem was created from");
}

void Problem::set_material(const Material &m) {
  const bool plane_stress = def_.material.plane_stress;  // (its own call)
  def_.material = m;
  def_.material.plane_stress = plane_stress;
  changed(kMaterial);
}

void Problem::set_plane_stress(bool on) {
  if (on && space_.dim != 2) fail(ND_ERR_DIMENSION, "plane stress is a 2D model; this mesh is " +
                                                        std::to_string(space_.dim) + "D");
  def_.material.plane_stress = on;
  changed(kMaterial);
}

void Problem::set_damping(double alpha, double beta) {
  def_.damping_alpha = alpha;
  def_.damping_beta = beta;
  changed(kDamping);
}

void Problem::set_material_region(int cell_region, const Material &m) {
  const std::vector<int> &of = mesh_->cell_region;
  if (std::find(of.begin(), of.end(), cell_region) == of.end())
    fail(ND_ERR_REGION, "cell region " + std::to_string(cell_region) +
                            " has no cells in the mesh the problem was created from (nd_mesh_set_cell_region, "
                            "or a physical group of cells in a Gmsh file)");
  def_.region_materials[cell_region] = m;
  // a region's material does not give the default one, which stays required
  const unsigned had_default = def_.given & kMaterial;
  changed(kMaterial);
  def_.given = (def_.given & ~kMaterial) | had_default;
}

void Problem::add_dirichlet(int region) {
  require_region(region, "Dirichlet");
  if (state_ready_ && state_.n > 0)
    fail(ND_ERR_STATE, "the clamped boundary cannot change once stepping has started; "
                       "set the initial state again first");
  def_.dirichlet.push_back(region);
  changed(kDirichlet);
}

// what giving() keys a load or a position by: (kind, region)
// (an added obstacle's pose: kObstaclePose + its index in Definition::obstacles)
// (a clamped region's prescribed displacement: kPrescribedRegion, its region;
// the nodal form: kPrescribedNodes)
enum TimeDataKind { kBodyForce, kNodalForces, kTraction, kObstaclePosition, kPrescribedNodes, kPrescribedRegion,
                    kObstaclePose };

void Problem::giving(std::pair<int, int> what) {
  const bool before_first_step = !setup_done_ && !(state_ready_ && state_.n > 0);
  if (!before_first_step || start_) return;
  if (given_.count(what)) {
    start_ = std::make_unique<TimeData>(def_);  // the values so far are t^0's
  } else {
    given_.insert(what);
  }
}

// a region's plane replaced, or added
static void put_plane(std::vector<ContactPlane> &planes, const ContactPlane &pl) {
  auto it = std::find_if(planes.begin(), planes.end(), [&](const ContactPlane &x) { return x.region == pl.region; });
  if (it == planes.end()) planes.push_back(pl);
  else *it = pl;
}

Definition Problem::at_start() const {
  Definition d = def_;
  if (start_) static_cast<TimeData &>(d) = *start_;
  return d;
}

void Problem::set_body_force(const double *f) {
  giving({kBodyForce, 0});
  std::copy(f, f + space_.dim, def_.body_force);
  def_.has_body_force = true;
  changed(kLoads);
}

void Problem::add_neumann(int region, const double *g) {
  require_region(region, "Neumann");
  NeumannLoad nl{region, {0, 0, 0}};
  std::copy(g, g + space_.dim, nl.g);
  giving({kTraction, region});
  // a region's traction is set, not added: it replaces the previous one
  auto it = std::find_if(def_.neumann.begin(), def_.neumann.end(), [&](const NeumannLoad &x) { return x.region == region; });
  if (it != def_.neumann.end())
    *it = nl;
  else
    def_.neumann.push_back(nl);
  changed(kLoads);
}

void Problem::set_contact_plane(int region, const double *point, const double *normal) {
  require_region(region, "contact");
  ContactPlane pl{region, {0, 0, 0}, {0, 0, 0}};
  // scale by the largest component first, so that the length neither
  // overflows nor underflows for any finite non-zero normal
  double big = 0;
  for (int k = 0; k < space_.dim; ++k) big = std::max(big, std::fabs(normal[k]));
  if (!(big > 0)) fail(ND_ERR_VALUE, "normal has zero length");
  double len = 0;
  for (int k = 0; k < space_.dim; ++k) len += (normal[k] / big) * (normal[k] / big);
  len = std::sqrt(len);
  for (int k = 0; k < space_.dim; ++k) {
    pl.point[k] = point[k];
    pl.normal[k] = normal[k] / big / len;
  }
  auto it = std::find_if(def_.planes.begin(), def_.planes.end(), [&](const ContactPlane &x) { return x.region == region; });
  if (it != def_.planes.end() && std::equal(pl.normal, pl.normal + 3, it->normal)) {
    giving({kObstaclePosition, region});
    *it = pl;  // a prescribed translation: the rows stay, the gaps follow the point
    changed(kObstacle);
    return;
  }
  // another obstacle, not a motion: it holds from t^0 on
  given_.insert({kObstaclePosition, region});
  const bool replaced = it != def_.planes.end();
  const size_t at = 3 * static_cast<size_t>(it - def_.planes.begin());
  if (start_) put_plane(start_->planes, pl);
  put_plane(def_.planes, pl);
  // (friction: and the state's point of it, so that no slip is counted for it)
  if (replaced && state_ready_ && def_.has_friction() && state_.positions.size() >= at + 3)
    std::copy(pl.point, pl.point + 3, state_.positions.begin() + static_cast<std::ptrdiff_t>(at));
  changed(kContact);
}

void Problem::add_obstacle(int region, std::shared_ptr<const Shape> shape) {
  require_region(region, "contact");
  const Obstacle o{region, std::move(shape), Pose{}};
  // a new obstacle, not a motion: it holds from t^0 on
  given_.insert({kObstaclePose + static_cast<int>(def_.obstacles.size()), region});
  if (start_) start_->obstacles.push_back(o);
  def_.obstacles.push_back(o);
  changed(kContact);
}

void Problem::set_contact_pair(int slave, int master) {
  require_region(slave, "contact");
  require_region(master, "contact");
  const ContactPair pair{slave, master};
  auto it = std::find_if(def_.pairs.begin(), def_.pairs.end(), [&](const ContactPair &x) { return x.slave == slave; });
  if (it != def_.pairs.end()) *it = pair;
  else def_.pairs.push_back(pair);
  changed(kContact);
}

void Problem::move_obstacle(int region, int index, const double *translation, const double *rotation) {
  const int d = space_.dim;
  int seen = -1;
  size_t at = def_.obstacles.size();
  for (size_t i = 0; i < def_.obstacles.size() && at == def_.obstacles.size(); ++i)
    if (def_.obstacles[i].region == region && ++seen == index) at = i;
  if (at == def_.obstacles.size())
    fail(ND_ERR_INDEX, "index " + std::to_string(index) + ": region " + std::to_string(region) + " has " +
                           std::to_string(seen + 1) + " added obstacle(s) (indices from 0, in the order added; "
                           "its plane moves with nd_problem_set_contact_plane)");
  Pose pose;
  for (int k = 0; k < d; ++k) pose.t[k] = translation[k];
  if (rotation) {
    for (int i = 0; i < d; ++i)
      for (int k = 0; k < d; ++k) pose.R[i * 3 + k] = rotation[i * d + k];
    // a rotation: R^T R = I and det R = +1, to round-off
    double worst = 0;
    for (int i = 0; i < d; ++i)
      for (int k = 0; k < d; ++k) {
        double rr = 0;
        for (int j = 0; j < d; ++j) rr += pose.R[j * 3 + i] * pose.R[j * 3 + k];
        worst = std::max(worst, std::fabs(rr - (i == k ? 1 : 0)));
      }
    const double *R = pose.R;
    const double det = d == 2 ? R[0] * R[4] - R[1] * R[3]
                              : R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                                    R[2] * (R[3] * R[7] - R[4] * R[6]);
    if (!(worst <= kRotationTolerance) || !(det > 0))
      fail(ND_ERR_VALUE, "rotation is not a rotation matrix (R^T R = I to " + num(worst) + ", det " + num(det) +
                             "): give a proper orthogonal " + std::to_string(d) + "x" + std::to_string(d) +
                             " matrix, row-major");
  }
  giving({kObstaclePose + static_cast<int>(at), region});
  def_.obstacles[at].pose = pose;
  changed(kObstacle);
}

void Problem::set_dirichlet_value(int region, const double *u) {
  if (std::find(def_.dirichlet.begin(), def_.dirichlet.end(), region) == def_.dirichlet.end())
    fail(ND_ERR_REGION, "region " + std::to_string(region) +
                            " is not clamped: give it to nd_problem_set_dirichlet first (only clamped DOFs move)");
  giving({kPrescribedRegion, region});
  const int d = space_.dim;
  if (def_.prescribed.empty()) def_.prescribed.assign(static_cast<size_t>(space_.n_dofs()), 0.0);
  for (int64_t f : mesh_->regions.at(region))
    for (int64_t node : space_.facet_nodes(mesh_->boundary[f]))
      for (int k = 0; k < d; ++k) def_.prescribed[node * d + k] = u[k];
  changed(kMotion);
}

void Problem::set_dirichlet_nodal(const double *u) {
  giving({kPrescribedNodes, 0});
  def_.prescribed.assign(u, u + space_.n_dofs());
  changed(kMotion);
}

void Problem::set_nitsche(double theta, double gamma0) {
  def_.theta = theta;
  def_.gamma0 = gamma0;
  changed(kNitsche);
}

void Problem::set_friction(int region, int law, const double *params) {
  require_region(region, "contact");
  int n_params = 0;
  if (!law_registered(law, &n_params))
    fail(ND_ERR_KEY, "law " + std::to_string(law) + " is not one of ND_FRICTION_LIST (ND_FRICTION_NONE, "
                     "ND_FRICTION_TRESCA, ND_FRICTION_COULOMB)");
  if (n_params > 0 && !params) fail(ND_ERR_NULL, "params is NULL; this law takes " + std::to_string(n_params) + " value");
  if (law != kFrictionNone && space_.dim < 2)
    fail(ND_ERR_DIMENSION, "friction needs a tangent plane: 2D or 3D (this mesh is 1D)");
  make_law(law, params, space_.dim);  // (its parameters checked: ND_ERR_VALUE)
  const double parameter = n_params > 0 ? params[0] : 0.0;
  auto it = std::find_if(def_.friction.begin(), def_.friction.end(),
                         [&](const Definition::Friction &f) { return f.region == region; });
  if (it == def_.friction.end()) def_.friction.push_back({region, law, parameter});
  else *it = {region, law, parameter};
  if (law == kFrictionNone && it == def_.friction.end()) def_.friction.pop_back();  // (nothing to remember)
  changed(kNitsche);
}

void Problem::set_scheme(int scheme, const std::vector<double> &params) {
  make_scheme(scheme, params);  // checks the id and the parameters
  const double fraction = automatic_gamma0_fraction(def_);
  def_.scheme = scheme;
  def_.scheme_params = params;
  // (an automatic gamma0 that depends on the scheme: the operators again)
  changed(kScheme | (def_.gamma0 == 0 && automatic_gamma0_fraction(def_) != fraction ? kNitsche : 0u));
}

void Problem::set_nodal_forces(const double *f) {
  giving({kNodalForces, 0});
  def_.nodal.assign(f, f + space_.n_dofs());
  changed(kNodal);
}

void Problem::set_newton(const NewtonOptions &o) {
  def_.newton = o;
  changed(kNewton);
}

void Problem::set_mass_lumping(bool lumped) {
  def_.lumped = lumped;
  changed(kLumping);
}

void Problem::set_distributed_state(bool on) {
  if (setup_done_)
    fail(ND_ERR_STATE, "the problem is set up (nd_problem_setup, a step or a loaded checkpoint): the state's layout "
                       "is chosen before, on every rank");
  def_.distributed_state = on;
}

void Problem::set_mass_redistribution(bool on) {
  def_.redistributed = on;
  changed(kLumping);  // the mass aspect
}

void Problem::set_linear_solver(int solver) {
  def_.solver = solver;
  changed(kSolver);
}

void Problem::set_timestep(double tau) {
  state_.control.tau_next = 0;  // (adaptive steps: the next step tries tau)
  def_.tau_given = tau;
  // (the same size again, as a host's loop sets it before each step: its
  // step operator stays factored)
  if (tau == def_.tau && (def_.given & kTimestep)) return;
  def_.tau = tau;
  changed(kTimestep);
}

void Problem::set_adaptive_timestep(double tolerance, double tau_min, double tau_max) {
  const bool was_on = def_.adaptive.on();
  def_.adaptive = AdaptiveOptions{tolerance, tau_min, tau_max};
  state_.control.tau_next = 0;
  changed(kAdaptive);
  // (a step size is given: tau_max's, unless nd_problem_set_timestep gives
  // another; turned off, the steps take the size it gave again)
  if (tolerance > 0 && !(def_.given & kTimestep)) set_timestep(tau_max);
  if (!(tolerance > 0) && was_on && def_.tau != def_.tau_given) set_timestep(def_.tau_given);
}

void Problem::set_initial_state(const double *u0, const double *v0) {
  const int64_t n = space_.n_dofs();
  def_.u0.assign(n, 0.0);
  def_.v0.assign(n, 0.0);
  if (u0) def_.u0.assign(u0, u0 + n);
  if (v0) def_.v0.assign(v0, v0 + n);
  if (state_ready_ && state_.n > 0) {  // a new run: its first values are t^0's again
    given_.clear();
    start_.reset();
  }
  changed(kInitial);
}

void Problem::set_guard(int guard, double value) {
  Guards &g = def_.guards;
  const bool on = value != 0;
  auto need_factor = [&](double lo) {
    if (!(value == 0 || (value >= lo && std::isfinite(value))))
      fail(ND_ERR_VALUE, "the guard's value is " + num(value) + "; it must be 0 (off) or a finite number >= " + num(lo));
  };
  switch (guard) {
    case ND_GUARD_ENERGY:
      need_factor(1);
      g.energy = value;
      break;
    case ND_GUARD_PENETRATION:
      need_factor(0);
      g.penetration = value;
      break;
    case ND_GUARD_CRITICAL_TIMESTEP:
      g.critical_timestep = on;
      break;
    case ND_GUARD_UNSTABLE_SCHEME:
      g.unstable_scheme = on;
      break;
    case ND_GUARD_COERCIVITY:
      g.coercivity = on;
      break;
    case ND_GUARD_INITIAL_PENETRATION:
      g.initial_penetration = on;
      break;
    case ND_GUARD_ENERGY_BALANCE:
      need_factor(0);
      g.balance = value;
      break;
    default:
      fail(ND_ERR_KEY, "guard " + std::to_string(guard) + " is not an ND_GUARD_* value");
  }
  changed(kGuards);
}

// ---- derived objects ------------------------------------------------------------

Discretization &Problem::discretization_() {
  require_blas_buffer();  // (before any BLAS call: the element eigenproblems of the assembly are the first)
  // operators split over other ranks (another communicator) are made again
  if (disc_ && disc_->rows_split && disc_->geometry.row_end >= 0 && disc_->geometry.comm != def_.comm) disc_.reset();
  if (!disc_) {
    // curved obstacles: the rows hold the state's frozen normals (a step's
    // refresh gives its own), unless the obstacles were redefined since
    // (and a pair's points their state's pairings)
    const std::vector<double> *frozen =
        state_ready_ && !obstacle_redefined_ && !state_.normal.empty() ? &state_.normal : nullptr;
    const std::vector<double> *pairing = frozen && !state_.pairing.empty() ? &state_.pairing : nullptr;
    disc_ = discretize(space_, def_, counters_.get(), splits_rows(def_) ? &ownership() : nullptr, frozen, pairing);
  }
  DofGeometry &g = disc_->geometry;
  if (g.row_end < 0 || g.comm != def_.comm) {
    g.comm = def_.comm;  // the factorizations' ranks
    g.row_of.reset();
    g.row_begin = 0, g.row_end = disc_->dofs.n_free;
    g.own_rows_only = false;
    g.forget_coordinates();  // (located again below for these rows)
    disc_->rows.reset();
    disc_->own_columns_.reset();
    disc_->contact.share.reset();
    const Ownership &own = ownership();
    if (!own.node_owner.empty()) {
      // a row (free DOF) belongs to its node's rank: the rank computes its row
      // of the step's products, and owns it in the distributed matrix, where
      // the rows are numbered rank after rank, each rank's in their order;
      // a contact point belongs to its cell's rank (parallel/share.hpp)
      const std::vector<int64_t> &free = disc_->dofs.free;
      std::vector<int> row_owner(static_cast<size_t>(disc_->dofs.n_free));
      for (int64_t dof = 0; dof < space_.n_dofs(); ++dof)
        if (free[dof] >= 0) row_owner[free[dof]] = own.node_owner[dof / space_.dim];
      disc_->rows = make_share(def_.comm, row_owner, counters_.get());
      const Share &rows = *disc_->rows;
      g.row_begin = rows.first[own.rank], g.row_end = rows.first[own.rank + 1];
      auto row_of = std::make_shared<std::vector<int64_t>>(static_cast<size_t>(disc_->dofs.n_free));
      for (size_t k = 0; k < rows.order.size(); ++k) (*row_of)[rows.order[k]] = static_cast<int64_t>(k);
      g.row_of = std::move(row_of);
      g.own_rows_only = disc_->rows_split;  // GAMG reads the coordinates of the rank's rows only
      const ContactPoints &cp = disc_->contact;
      std::vector<int> point_owner(cp.size());
      for (size_t q = 0; q < cp.size(); ++q) point_owner[q] = own.cell_owner[space_.mesh->boundary[cp.facet[q]].cell];
      disc_->contact.share = make_share(def_.comm, point_owner, counters_.get());
    }
  }
  // where the unknowns sit: built for the solver that reads it (GAMG), and
  // dropped when another is chosen
  if (linear_solver_reads_coordinates(def_.solver) != g.located) {
    if (g.located) g.forget_coordinates();
    else locate_unknowns(space_, disc_->dofs, g);
  }
  // another obstacle (not a motion of this one): its gaps hold from t^n on
  if (obstacle_redefined_ && state_ready_) {
    state_.gap = disc_->contact.gap;
    obstacle_redefined_ = false;
    curved_gaps(state_, *disc_, def_);
  }
  obstacle_redefined_ = false;
  return *disc_;
}

const std::vector<double> &Problem::clamped_load_() {
  Discretization &d = discretization_();
  if (!load_fixed_)
    load_fixed_ = std::make_unique<std::vector<double>>(d.clamped ? clamped_load(space_, *d.clamped, def_)
                                                                  : std::vector<double>());
  return *load_fixed_;
}

const std::vector<double> &Problem::current_gaps() {
  const Discretization &d = discretization_();
  if (gaps_of_ != d.id) {
    gaps_ = contact_gaps(d.contact, def_.planes);
    gaps_of_ = d.id;
  }
  return gaps_;
}

const std::vector<double> &Problem::constant_load_() {
  if (!load_) load_ = std::make_shared<const std::vector<double>>(constant_load(space_, discretization_(), def_));
  return *load_;
}

Integrator &Problem::integrator_or_build() {
  if (integrator_) return *integrator_;
  Discretization &d = discretization_();
  // several ranks: each assembles its own cells' part of A, unless the
  // operators hold its rows already (then A's own rows are whole)
  std::function<Csr(double)> own_part;
  if (linear_solver_distributes(def_.solver) && !d.rows_split && !ownership().node_owner.empty())
    own_part = [&](double c) { return assemble_own_step_matrix(space_, d, def_, *ownership_, c); };
  // (adaptive steps: A's pattern analysed for another size, its ordering reused)
  const Factorization *like = refresh_ordering_;
  for (const KeptIntegrator &k : kept_integrators_)
    if (!like && k.of == d.id && k.in->A_factor) like = k.in->A_factor.get();
  integrator_ = make_integrator(d, def_, std::move(spare_A_factor_), own_part, like);
  integrator_new_ = true;
  return *integrator_;
}

// F: the body force and tractions F_const with the nodal forces (without
// any: F_const itself, not a copy)
std::shared_ptr<const std::vector<double>> Problem::with_nodal(std::shared_ptr<const std::vector<double>> F_const,
                                                               const std::vector<double> &nodal) {
  if (nodal.empty()) return F_const;
  count(counters_.get(), &Counters::load_assemblies);
  auto F = std::make_shared<std::vector<double>>(static_cast<size_t>(discretization_().dofs.n_free), 0.0);
  disc_->dofs.restrict_to_free(nodal.data(), F->data());
  for (size_t i = 0; i < F_const->size(); ++i) (*F)[i] += (*F_const)[i];
  return F;
}

// built once per change of a load, not every step (docs/design.md §4)
const std::shared_ptr<const std::vector<double>> &Problem::current_load() {
  if (!step_load_) {
    constant_load_();
    step_load_ = with_nodal(load_, def_.nodal);
  }
  return step_load_;
}

const State &Problem::state() {
  if (!state_ready_) {
    Discretization &d = discretization_();
    const int64_t n = d.dofs.n_free;
    State s;
    s.U.assign(n, 0.0);
    s.V.assign(n, 0.0);
    s.A.assign(n, 0.0);
    if (!def_.u0.empty()) d.dofs.restrict_to_free(def_.u0.data(), s.U.data());
    if (!def_.v0.empty()) d.dofs.restrict_to_free(def_.v0.data(), s.V.data());
    const std::vector<double> &motion0 = start_ ? start_->prescribed : def_.prescribed;
    if (d.clamped && !motion0.empty()) {  // prescribed motion: the supports at t^0, at the initial velocity
      s.Uc = clamped_values(d, motion0);
      s.Vc = def_.v0.empty() ? std::vector<double>(s.Uc.size(), 0.0) : clamped_values(d, def_.v0);
      s.Ac.assign(s.Uc.size(), 0.0);
    }
    if (start_) {  // t^0's loads and positions, not the next step's
      const Definition d0 = at_start();
      s.F = with_nodal(std::make_shared<const std::vector<double>>(constant_load(space_, d, d0)), d0.nodal);
      if (d.clamped) s.F_fixed = clamped_load(space_, *d.clamped, d0);
      s.gap = contact_gaps(d.contact, d0.planes);
      curved_gaps(s, d, d0);
    } else {
      s.F = current_load();
      s.F_fixed = clamped_load_();
      s.gap = current_gaps();
      curved_gaps(s, d, def_);
    }
    start_slip(d, s);  // friction: no traction stored at t^0
    replace_state(std::move(s));
    state_ready_ = true;
  }
  return state_;
}

void Problem::curved_gaps(State &s, const Discretization &d, const TimeData &at) {
  if (at.obstacles.empty() && def_.pairs.empty()) {
    s.normal.clear(), s.positions.clear(), s.pairing.clear();
    // friction: where the planes are, for the slip's shift (obstacle_slip)
    if (d.contact.m > 1) s.positions = positions(at.planes, at.obstacles);
    return;
  }
  // the rows' normals, the obstacles where `at` places them now, g = g^n
  s.normal = d.contact.normal;
  s.pairing = d.contact.pairing;
  s.positions = positions(at.planes, at.obstacles);
  const StepPlaces here{at.planes, at.obstacles, s.t, &def_.pairs, &s.pairing};
  s.gap = step_geometry(space_, d.dofs, d.contact, here, here, s.U, s.normal, s.gap, s.gap, false).gap;
}

void Problem::complete_state() {
  if (!state_ready_ || !state_.partial) return;
  const Share *rows = discretization_().rows.get();
  if (!rows) fail(ND_ERR_INTERNAL, "a partial state without the ranks' rows");
  std::vector<double *> fields{state_.U.data(), state_.V.data()};
  if (state_.A_valid) fields.push_back(state_.A.data());
  gather(*rows, fields);  // (the held rows keep their bits: the owners' values)
  PointValues &points = products_.points;
  if (points.partial) {  // each rank's own points are right (their sums stay the step's)
    const Share *owners = discretization_().contact.share.get();
    if (!owners) fail(ND_ERR_INTERNAL, "a distributed state's points without their ranks");
    gather(*owners, {points.P.data(), points.un.data(), state_.phi.data()});
    points.partial = false;
  }
  state_.partial = false;
}

// ---- stepping --------------------------------------------------------------------

void Problem::setup(const char *call) {
  agree_on_inputs(call);
  prepare();
}

void Problem::prepare() {
  require_complete(def_.missing_for_step());  // everything missing, in one message
  // (friction on several ranks: every rank evaluates every point, which a
  // distributed state, right at the rank's points' DOFs only, cannot)
  if (def_.has_friction() && def_.distributed_state && splits_rows(def_))
    fail(ND_ERR_STATE, "friction with a distributed state is not supported yet (nd_problem_set_distributed_state): "
                       "step a problem with friction with the state whole on every rank");
  for (const ContactPair &pair : def_.pairs) {
    if (communicator_size(def_.comm.get()) > 1)
      fail(ND_ERR_STATE, "contact pairs on several MPI ranks are not supported yet: step a problem with a contact "
                         "pair in one process");
    for (const ContactPlane &pl : def_.planes)
      if (pl.region == pair.slave)
        fail(ND_ERR_STATE, "region " + std::to_string(pair.slave) + " is a contact pair's slave and has a plane: a "
                           "region's points meet one master surface or rigid obstacles, not both (yet)");
    if (curved_region(pair.slave, def_.obstacles))
      fail(ND_ERR_STATE, "region " + std::to_string(pair.slave) + " is a contact pair's slave and has an obstacle: a "
                         "region's points meet one master surface or rigid obstacles, not both (yet)");
  }
  for (const Definition::Friction &f : def_.friction)
    if (f.law != kFrictionNone && curved_region(f.region, def_.obstacles))
      fail(ND_ERR_STATE, "friction on a region with a sphere, cylinder or distance obstacle is not supported yet "
                         "(region " + std::to_string(f.region) + "; a refresh of the frozen normals turns the tangent "
                         "basis, in which the slip references have no exact expression): friction needs the region's "
                         "plane alone, which may move");
  require_blas_buffer();  // ND_ERR_NOMEM, not OpenBLAS's endless retry (linalg/blas_threads.hpp)
  Discretization &d = discretization_agreed();
  Integrator &in = integrator_or_build();
  // a step that reads whole vectors (an explicit scheme, a solver that does
  // not split the rows), or a new integrator's first, has the state whole
  // (collective: on every rank)
  if (in.held.empty() || integrator_new_) complete_state();
  integrator_new_ = false;
  if (def_.guards.unstable_scheme && in.scheme->always_unstable())
    fail(ND_ERR_UNSTABLE, "the scheme amplifies every undamped oscillation, whatever the time step "
                          "(theta-scheme with theta < 1/2, Newmark with gamma < 1/2): choose theta >= 1/2 or "
                          "gamma >= 1/2, or allow it with the unstable-scheme guard for a study");
  if (def_.guards.coercivity) check_coercivity(d, def_.solver, in.A_factor.get());
  // An explicit step above the free motion's critical step grows whatever
  // the contact does: refused. Between it and the critical step with every
  // contact point active (the estimate nd_problem_estimate_critical_timestep
  // gives) it is stable or not by the active set the run reaches, which
  // only the steps know: the energy guards watch it, and their message
  // names the estimate (docs/design.md §3b.4).
  const double limit = in.scheme->stability_limit();
  if (def_.guards.critical_timestep && std::isfinite(limit) && def_.tau * omega_free() > limit)
    fail(ND_ERR_UNSTABLE, "the time step " + num(def_.tau) + " exceeds the scheme's critical step of the free motion " +
                              num(limit / omega_free()) + " (" + num(limit) + "/omega, the highest frequency with " +
                              "no contact point active): every run grows. Lower the time step (below " +
                              num(limit / omega_max()) + " with every contact point active, " +
                              "nd_problem_estimate_critical_timestep), use an implicit scheme, or raise gamma0 "
                              "(a softer penalty); the critical-timestep guard allows it for a study");
  state();
  // friction set (or its points changed) since the state was made: no traction stored from here
  if (d.contact.m > 1 ? state_.slip.size() != d.contact.size() * static_cast<size_t>(d.contact.m - 1)
                      : !state_.slip.empty()) {
    start_slip(d, state_);
    products_.of = 0;
  }
  // (and the planes where they are now, from which the next step's move)
  if (d.contact.m > 1 && state_.positions.size() != positions(def_.planes, def_.obstacles).size())
    state_.positions = positions(def_.planes, def_.obstacles);
  // Remark 3.2 (equilibrium_acceleration assigns A only once it is computed)
  if (in.scheme->uses_acceleration() && !state_.A_valid) {
    complete_state();
    products_.MA.clear();  // (dropped first: a throw below leaves none of the old A's)
    d.equilibrium_acceleration(state_, def_.solver, !in.scheme->is_explicit(), true);
  }
  // the products the first step's right-hand side reads (each step leaves
  // its own), and the initial energy of the guard (of a whole state)
  if (!products_current(d, state_, products_, in.scheme->uses_acceleration())) {
    complete_state();
    compute_products(d, state_, products_);
  }
  if (state_.n == 0 && !initial_guarded_) guard_initial_state(d, def_.guards, state_, products_);
  initial_guarded_ = true;  // checked once, not again at every step
  setup_done_ = true;
}

// The gaps of the next step and the frozen normals after the refresh rule,
// the obstacles where the state had them at t^n and where the definition
// has them at t^{n+1} (contact/obstacles.hpp)
StepGeometry Problem::curved_geometry(const std::vector<double> &plane_gaps) {
  std::vector<ContactPlane> planes_n = def_.planes;
  std::vector<Obstacle> obstacles_n = def_.obstacles;
  place(planes_n, obstacles_n, state_.positions);
  const State &s = state_;
  const double tau = def_.tau;  // (t^{n+1} as advance computes it)
  const double t_new = s.tau_ref != tau ? s.t + tau : s.t_ref + static_cast<double>(s.n + 1 - s.n_ref) * tau;
  StepGeometry geo =
      step_geometry(space_, disc_->dofs, disc_->contact, {def_.planes, def_.obstacles, t_new, &def_.pairs, &s.pairing},
                    {planes_n, obstacles_n, s.t}, s.U, s.normal, plane_gaps, s.gap, true);
  count(counters_.get(), &Counters::normal_refreshes, geo.refreshed);
  return geo;
}

// R at the state's U with the current discretization's rows and the gaps
// a step starts from (g_q^n of its re-linearisation): the Nitsche energy
// the state has in the step's geometry
double Problem::relinearised_nitsche_energy(const State &from, const std::vector<double> &gap_n) {
  State at;
  at.U = from.U, at.gap = gap_n, at.slip = from.slip, at.phi = from.phi;
  return nitsche_energy(*disc_, at, Products{});  // (no products: a pass over the points)
}

void Problem::step() {
  if (def_.adaptive.on()) return adaptive_step();
  step_once(nullptr);
  count(counters_.get(), &Counters::steps_accepted);
}

void Problem::step_once(const Attempt *attempt) {
  agree_on_inputs("nd_step");
  StateWithProducts next;
  // a refresh of the curved points' normals makes the operators again; a
  // failed step gives the old ones back, with the state they belong to
  std::unique_ptr<Discretization> kept_disc;
  std::unique_ptr<Integrator> kept_integrator;
  std::vector<KeptIntegrator> kept_sizes;  // (declared after kept_disc: destroyed before it)
  auto body = [&] {
    // where the step starts: the state, or (friction, new rows) a copy with
    // its slip references carried to the new rows; the state keeps its own
    State carried;
    const State *from = &state_;
    prepare();
    const std::vector<double> *gap = &current_gaps();
    StepGeometry geo;
    const bool curved = def_.curved();
    double relinearised = 0;  // E_Theta at U^n with this step's rows and gaps, less with the state's
    if (curved) {
      geo = curved_geometry(*gap);
      if (def_.theta != 0) complete_state();  // (a distributed state: R reads every point)
      const double R_old = def_.theta != 0 ? nitsche_energy(*disc_, state_, products_) : 0;
      // new rows: A refactored, the columns dropped
      if (geo.normal != disc_->contact.normal || geo.pairing != disc_->contact.pairing) {
        kept_disc = std::move(disc_);
        kept_integrator = std::move(integrator_);
        kept_sizes.swap(kept_integrators_);  // (of kept_disc: of no use with the new rows)
        // (only the contact rows and K_Theta change)
        disc_ = with_normals(space_, def_, *kept_disc, geo.normal, geo.pairing.empty() ? nullptr : &geo.pairing);
        // friction: the references in the new rows, the tractions held (R's change to W_geometry below)
        if (disc_->contact.m > 1 && !state_.slip.empty()) {
          carried = state_;
          carried.slip = transport_slip(kept_disc->contact, disc_->contact, state_.U, state_.slip);
          from = &carried;
        }
        refresh_ordering_ = kept_integrator && kept_integrator->A_factor ? kept_integrator->A_factor.get() : nullptr;
        prepare();
        refresh_ordering_ = nullptr;
      }
      gap = &geo.gap;
      if (def_.theta != 0) relinearised = -def_.theta * (relinearised_nitsche_energy(*from, geo.gap_old) - R_old);
    }
    const std::vector<double> motion =
        disc_->clamped && !def_.prescribed.empty() ? clamped_values(*disc_, def_.prescribed) : std::vector<double>();
    const bool friction = disc_->contact.m > 1;
    const std::vector<double> shift =
        friction ? obstacle_slip(disc_->contact, space_.dim, state_.positions, def_.planes) : std::vector<double>();
    StepData data{current_load(), clamped_load_(), *gap, curved ? &geo.gap_old : nullptr, &motion};
    data.slip_shift = &shift;
    next = advance(*integrator_, *disc_, def_, *from, products_, data, std::move(spare_));
    State &s = next.state;
    if (curved) s.normal = std::move(geo.normal), s.pairing = std::move(geo.pairing);
    else s.normal.clear(), s.pairing.clear();
    if (curved || friction) s.positions = positions(def_.planes, def_.obstacles);
    else s.positions.clear();
    s.W_geometry += relinearised;
    try {
      guard_step(*disc_, def_.guards, *from, s, next.products, def_.scheme != ND_SCHEME_GENERALIZED_ALPHA);
    } catch (...) {
      explain_explicit_refusal(*disc_, *integrator_->scheme, def_.tau);
    }
    if (attempt) judge_step(*attempt, *from, s, next.products);
  };
  try {
    // every rank commits the step or none does (one reference captured:
    // the std::function holds it without allocating)
    nd::on_every_rank(def_.comm.get(), std::ref(body), "the step", "no rank took it");
  } catch (...) {
    refresh_ordering_ = nullptr;
    if (kept_disc) {
      disc_ = std::move(kept_disc), integrator_ = std::move(kept_integrator);
      kept_integrators_.swap(kept_sizes);
    }
    throw;
  }
  // the old state's and products' memory serves the next step's
  spare_.state = std::move(state_), spare_.products = std::move(products_);
  replace_state(std::move(next.state), std::move(next.products));
}

void Problem::replace_state(State &&s, Products &&p) {
  state_ = std::move(s);
  products_ = std::move(p);
}

// With split rows each rank assembles its own rows of the operators alone,
// so a rank may fail where the others do not (an overflow in its cells):
// where the ranks go on into collective calls, they agree on the assembly
// first. Whole operators are the same on every rank (and the calls that read
// them need not be collective).
Discretization &Problem::discretization_agreed() {
  if (!splits_rows(def_)) return discretization_();
  Discretization *d = nullptr;
  nd::on_every_rank(def_.comm.get(), [&] { d = &discretization_(); }, "the assembly of the operators",
                    "no rank went on");
  return *d;
}

void Problem::check_whole_read(const char *call, const std::function<void()> &checks) {
  if (!(state_ready_ && state_.partial)) return checks();
  collective(call);
  on_every_rank(checks);
}

void Problem::on_every_rank(const std::function<void()> &local) {
  nd::on_every_rank(def_.comm.get(), local, "the call", "no rank went on");
}

// What a step reads that the caller gives: the mesh, the definition and the
// state at t^n; the ranks of a communicator must give the same. Raw inputs
// only: nothing here may fail on one rank before the ranks compare.
uint64_t Problem::inputs_digest() const {
  Hash h;
  h.value(mesh_digest_);
  const Definition &d = def_;
  h.value(d.given);
  for (double x : {d.material.young, d.material.poisson, d.material.density, d.theta, d.gamma0, d.tau,
                   d.newton.rtol, d.newton.atol, d.guards.energy, d.guards.penetration, d.guards.balance, d.damping_alpha,
                   d.damping_beta})
    h.value(x);
  for (const Definition::Friction &f : d.friction) h.value(f.region), h.value(f.law), h.value(f.parameter);
  h.value(uint8_t{d.material.plane_stress});
  for (int x : {d.scheme, d.solver, d.newton.max_iter, static_cast<int>(d.tangent), int(d.lumped),
                int(d.redistributed), int(d.guards.critical_timestep),
                int(d.guards.unstable_scheme), int(d.guards.coercivity), int(d.guards.initial_penetration)})
    h.value(x);
  h.vec(d.dirichlet);
  for (const auto &[region, m] : d.region_materials)
    h.value(region), h.value(m.young), h.value(m.poisson), h.value(m.density);
  auto time_data = [&h](const TimeData &t) {
    h.value(int(t.has_body_force));
    h.bytes(t.body_force, sizeof t.body_force);
    for (const NeumannLoad &l : t.neumann) h.value(l.region), h.bytes(l.g, sizeof l.g);
    for (const ContactPlane &p : t.planes)
      h.value(p.region), h.bytes(p.point, sizeof p.point), h.bytes(p.normal, sizeof p.normal);
    for (const Obstacle &o : t.obstacles) {
      h.value(o.region);
      o.shape->fingerprint(h);
      h.bytes(o.pose.R, sizeof o.pose.R), h.bytes(o.pose.t, sizeof o.pose.t);
    }
    h.vec(t.nodal);
    h.vec(t.prescribed);
  };
  time_data(d);
  h.value(start_ != nullptr);
  if (start_) time_data(*start_);
  h.vec(d.scheme_params);
  h.vec(d.u0), h.vec(d.v0);
  h.value(state_ready_);
  if (state_ready_) h.value(state_.t), h.value(state_.n), h.value(state_.partial);
  // (a partial state differs between ranks off their rows; the steps that
  // made it were agreed)
  if (state_ready_ && !state_.partial) h.vec(state_.U), h.vec(state_.V);
  if (state_ready_) h.vec(state_.normal), h.vec(state_.positions);
  h.value(d.distributed_state);
  return h.h;
}

namespace {
// The C functions that call collective(): a call's number in the header is
// its index (a new one is appended: the ranks of one job run one build).
constexpr const char *kCollectiveCalls[] = {
    "nd_problem_setup", "nd_step", "nd_problem_set_state", "nd_get_field_gathered",
    "nd_problem_estimate_critical_timestep", "nd_get_field", "nd_get_contact_pressure",
    "nd_get_contact_pressure_applied", "nd_problem_get_state_size", "nd_problem_save_state",
    "nd_problem_save_state_file", "nd_problem_write_vtu"};
constexpr int kCollectiveCallCount = static_cast<int>(sizeof kCollectiveCalls / sizeof kCollectiveCalls[0]);
// What a rank rebuilds over the ranks when these aspects changed: the
// discretization (rows split with PETSc), its mass factor, the integrator.
constexpr unsigned kRebuildAspects = kIntegratorDeps | kMassFactorDeps;
}  // namespace

bool Problem::collective(const char *call, uint64_t digest) {
  const Communicator *c = def_.comm.get();
  if (communicator_size(c) <= 1) return true;
  int id = 0;
  while (id < kCollectiveCallCount && std::string_view(kCollectiveCalls[id]) != call) ++id;
  if (id == kCollectiveCallCount) fail(ND_ERR_INTERNAL, std::string("collective call ") + call + " has no number");
  const CallAgreement a = agree_on_call(c, {id, digest, pending_ & kRebuildAspects}, call);
  if (!a.same_call) {
    const auto name = [](int k) { return k >= 0 && k < kCollectiveCallCount ? kCollectiveCalls[k] : "another call"; };
    fail(ND_ERR_STATE, "rank " + std::to_string(rank()) +
                           ": the ranks are not in the same collective call on this problem (" +
                           (a.call_min != a.call_max ? std::string(name(a.call_min)) + " on some ranks, " +
                                                           name(a.call_max) + " on others"
                                                     : std::string("a call more or fewer on some ranks")) +
                           ", the problem's collective call #" + std::to_string(a.sequence) +
                           "): every rank makes the same collective calls in the same order; nothing was done on "
                           "any rank");
  }
  if (!a.same_digest) return false;  // (what a rank changed waits for an agreed call)
  // a rank that changed an aspect rebuilds its factorizations, collectively:
  // the others rebuild theirs (the same, from the same definition) with it
  drop(a.rebuild & ~pending_);
  pending_ = 0;
  return true;
}

void Problem::agree_on_inputs(const char *call) {
  if (!collective(call, inputs_digest()))
    fail(ND_ERR_STATE, "the ranks' problems differ (definition, loads or state at t^n): every rank must make the "
                       "same calls with the same values (a call refused on some ranks only is the usual cause: see "
                       "their errors); nothing was done on any rank");
}

void Problem::set_communicator(CommunicatorPtr comm) {
  // every rank takes part in the collectives below, then all fail or none does
  const Communicator *c = comm.get();
  nd::on_every_rank(
      c,
      [&] {
        if (setup_done_)
          fail(ND_ERR_STATE, "the problem is set up (nd_problem_setup, a step or a loaded checkpoint): the "
                             "communicator is given before, on every rank");
      },
      "taking the communicator", "no rank took it");
  if (!same_on_all_ranks(c, mesh_digest_))
    fail(ND_ERR_STATE, "the ranks' meshes differ (vertices, cells, regions or degree): every rank creates the problem "
                       "from the same mesh; no rank took the communicator");
  // the cells and nodes of each rank: partitioned now (collective), kept until another communicator
  std::shared_ptr<const Ownership> own = partition_mesh(space_, c);
  def_.comm = std::move(comm);
  ownership_ = std::move(own);
  changed(kSolver);  // every factorization is made again over the new ranks
}

// Both estimates at once: with Theta != 1 the contact tangent's symmetric
// part may be indefinite, so that every point active can lower the highest
// frequency below the free motion's; the critical step is the smaller one's.
void Problem::estimate_frequencies() {
  Discretization &d = discretization_agreed();
  if (d.omega_max > 0 && d.omega_free > 0) return;
  const CriticalStep all = estimate_omega_max(d, def_.solver);
  const CriticalStep free = d.contact.size() > 0 ? estimate_omega_max(d, def_.solver, false) : all;
  d.omega_max = std::max(all.omega_max, free.omega_max);
  d.omega_free = free.omega_low;
}

double Problem::omega_max() {
  estimate_frequencies();
  return disc_->omega_max;
}

double Problem::omega_free() {
  estimate_frequencies();
  return disc_->omega_free;
}

double Problem::critical_timestep() {
  if (splits_rows(def_)) collective("nd_problem_estimate_critical_timestep");  // (it solves over the ranks)
  double limit = 2;  // the central difference's
  if (def_.given & kScheme) {
    const double l = make_scheme(def_.scheme, def_.scheme_params)->stability_limit();
    if (std::isfinite(l)) limit = l;
  }
  return limit / omega_max();
}

void Problem::overwrite_state(const double *u, const double *v) {
  setup("nd_problem_set_state");
  complete_state();
  Discretization &d = *disc_;
  State s = state_;
  if (u) d.dofs.restrict_to_free(u, s.U.data());
  if (v) d.dofs.restrict_to_free(v, s.V.data());
  s.A_valid = false;
  s.reaction.clear();  // no step led here: the equilibrium's, on demand
  s.phi.clear();
  carry_slip(d, state_, s);  // (friction: the tangential traction stays)
  if (integrator_->scheme->uses_acceleration()) d.equilibrium_acceleration(s, def_.solver);
  Products ps;
  compute_products(d, s, ps);  // the next step's, and the energy (setup() made state_'s)
  const double dE = mechanical_energy(d, s, ps) - mechanical_energy(d, state_, products_);
  s.guard.E0 += dE;
  s.guard.budget += dE;
  // the energy balance starts again from the new state (its first state
  // out of contact): a state set by the caller is not a step's
  s.guard.balance = s.guard.balance_low = std::numeric_limits<double>::quiet_NaN();
  s.guard.exchange = 0;
  s.guard.in_contact = false;
  replace_state(std::move(s), std::move(ps));
  initial_guarded_ = false;  // at n = 0 the next step checks the new initial state, as before
}

std::vector<unsigned char> Problem::save_state() {
  state();
  complete_state();
  // (a set-up redefined since the state was made has no operators yet:
  // made again here, as every other reader does)
  const Discretization &d = discretization_();
  return encode_state(state_, state_fingerprint(space_, d), definition_print(def_, d), state_sizes());
}

StateSizes Problem::state_sizes() {
  Discretization &d = discretization_();
  return {d.dofs.n_free, d.clamped ? static_cast<int64_t>(d.clamped->dofs.size()) : 0,
          static_cast<int64_t>(d.contact.size()),
          def_.obstacles.empty() ? 0 : static_cast<int64_t>(positions(def_.planes, def_.obstacles).size()),
          static_cast<int64_t>(d.contact.size()) * (d.contact.m - 1),
          d.contact.m > 1 ? static_cast<int64_t>(3 * friction_regions(d.contact).size()) : 0,
          d.contact.m > 1 && def_.obstacles.empty() ? static_cast<int64_t>(3 * def_.planes.size()) : 0,
          !def_.pairs.empty(), static_cast<int64_t>(mesh_->boundary.size()), def_.adaptive.on()};
}

void Problem::load_state(const unsigned char *buf, int64_t nbytes) {
  Discretization &d = discretization_();
  State s;
  decode_state(buf, nbytes, state_fingerprint(space_, d), definition_print(def_, d), state_sizes(), s);
  // curved obstacles: the operators are made again with the checkpoint's normals
  const bool other_rows =
      (!s.normal.empty() && s.normal != d.contact.normal) || (!s.pairing.empty() && s.pairing != d.contact.pairing);
  replace_state(std::move(s));  // (no products: the set-up makes them)
  state_ready_ = true;
  if (other_rows) disc_.reset(), integrator_.reset(), kept_integrators_.clear();
  setup_done_ = state_.n > 0;
  // the checkpoint holds F^n: at n = 0 the loads given now are t^1's
  if (state_.n == 0 && !start_) start_ = std::make_unique<TimeData>(def_);
  initial_guarded_ = false;
}

void Problem::save_state_file(const char *path) { write_file_atomically(path, save_state()); }

void Problem::load_state_file(const char *path) {
  // a file larger than any checkpoint of this problem is refused from its header
  const int64_t max_size = max_state_size(state_sizes());
  uint64_t size = 0;
  const std::vector<unsigned char> bytes = read_file_prefix(path, static_cast<uint64_t>(max_size), size);
  if (size > static_cast<uint64_t>(max_size))
    refuse_oversized_state(bytes.data(), std::min<int64_t>(kStateHeaderSize, max_size),
                           state_fingerprint(space_, discretization_()), size, static_cast<uint64_t>(max_size));
  if (bytes.empty()) fail(ND_ERR_FORMAT, std::string("'") + path + "' is empty");
  load_state(bytes.data(), static_cast<int64_t>(bytes.size()));
}

// ---- monitors ----------------------------------------------------------------------

std::vector<double> Problem::reaction_at_equilibrium(const State &s) {
  Discretization &d = discretization_();
  State e = s;  // Remark 3.2: M A = F - K_Theta U - N(U) at this state
  if (!e.A_valid) d.equilibrium_acceleration(e, def_.solver);
  const ContactLaw law = state_contact_law(d, e);
  std::vector<double> phi(d.contact.size());
  for (size_t q = 0; q < phi.size(); ++q) {
    double slope;
    law.law(q, law.P(q, e.U.data()), phi[q], slope);
  }
  std::vector<double> R = clamped_residual(d, e.A, e.U, phi, e.F_fixed);
  if (!e.Uc.empty()) add_clamped_block(d, ClampedMean{e.Uc, e.Ac, {}}, R);  // (as clamped_residual: no C term)
  return R;
}

namespace {
// the state's vector of a field (U, V or A; nullptr: another field)
const std::vector<double> *state_vector(const State &s, int which) {
  return which == ND_FIELD_DISPLACEMENT ? &s.U
         : which == ND_FIELD_VELOCITY   ? &s.V
         : which == ND_FIELD_ACCELERATION ? &s.A
                                          : nullptr;
}
}  // namespace

void Problem::field(int which, double *full) {
  const State &s = state();
  if (which == ND_FIELD_CONTACT_FORCE) {
    complete_state();  // (a distributed state holds the rank's points only)
    contact_force_field(discretization_(), s, full);
    return;
  }
  if (which == ND_FIELD_REACTION) {
    Discretization &d = discretization_();
    std::fill(full, full + space_.n_dofs(), 0.0);
    if (!d.clamped) return;
    if (s.reaction.empty()) complete_state();  // (a step made it; else the whole state's equilibrium)
    const std::vector<double> R = s.reaction.empty() ? reaction_at_equilibrium(s) : s.reaction;
    for (size_t r = 0; r < R.size(); ++r) full[d.clamped->dofs[r]] = R[r];
    return;
  }
  complete_state();  // whole vectors: collective when the state is partial
  if (which == ND_FIELD_ACCELERATION && !s.A_valid) {
    products_.MA.clear();  // (U and V stay: of the products only M A changes, products_current)
    discretization_().equilibrium_acceleration(state_, def_.solver);
  }
  const Discretization &d = discretization_();
  d.dofs.extend_to_full(state_vector(s, which)->data(), full);
  // prescribed motion: the clamped DOFs where the supports have taken them
  const std::vector<double> &c = which == ND_FIELD_DISPLACEMENT ? s.Uc : which == ND_FIELD_VELOCITY ? s.Vc : s.Ac;
  if (d.clamped && c.size() == d.clamped->dofs.size())
    for (size_t r = 0; r < c.size(); ++r) full[d.clamped->dofs[r]] = c[r];
}

const Ownership &Problem::ownership() {
  if (!ownership_) ownership_ = partition_mesh(space_, def_.comm.get());
  return *ownership_;
}

int64_t Problem::owned_node_count() { return static_cast<int64_t>(ownership().nodes.size()); }

void Problem::owned_field(int which, double *values, int64_t *nodes) {
  const std::vector<int64_t> &own = ownership().nodes;
  const int d = space_.dim;
  if (values) {
    std::vector<double> full(static_cast<size_t>(space_.n_dofs()));
    const State &s = state();
    const std::vector<double> *v = state_vector(s, which);
    if (s.partial && v && (v != &s.A || s.A_valid))  // this rank's rows are right: no message
      discretization_().dofs.extend_to_full(v->data(), full.data());
    else if (s.partial && which == ND_FIELD_CONTACT_FORCE)  // from the points the rank holds (all of its nodes')
      contact_force_field(discretization_(), s, full.data(),
                          integrator_ && integrator_->points ? &integrator_->points->points : nullptr);
    else
      field(which, full.data());
    for (size_t k = 0; k < own.size(); ++k) std::copy_n(&full[own[k] * d], d, &values[k * d]);
  }
  if (nodes) std::copy(own.begin(), own.end(), nodes);
}

void Problem::gathered_field(int which, int root, double *full) {
  const Communicator *c = def_.comm.get();
  Hash h;
  h.value(which), h.value(root);
  if (!same_on_all_ranks(c, h.h))
    fail(ND_ERR_VALUE, "the ranks asked for different fields or roots: every rank makes the same call");
  if (rank_count() == 1) return field(which, full);
  const int d = space_.dim;
  std::vector<double> mine;
  on_every_rank([&] {  // the field may need a solve over the ranks (the acceleration)
    mine.resize(static_cast<size_t>(owned_node_count() * d));
    owned_field(which, mine.data(), nullptr);
  });
  gather_items(*make_share(def_.comm, ownership().node_owner), root, d, mine.data(), full);
}

std::vector<double> Problem::contact_pressure() {
  const State &s = state();
  complete_state();  // a distributed state's points: collective
  return nd::contact_pressure(discretization_(), s, products_);
}

std::vector<double> Problem::contact_pressure_applied() {
  const State &s = state();
  complete_state();
  if (s.phi.empty()) return contact_pressure();  // no step yet: the state's own
  const ContactPoints &cp = discretization_().contact;
  std::vector<double> lam(cp.size());
  for (size_t q = 0; q < lam.size(); ++q) lam[q] = -s.phi[q] / cp.gamma[q];
  return lam;
}

namespace {
// the ND_STAT_* keys and the counters they read
struct StatKey {
  int key;
  int64_t Counters::*field;
};
constexpr StatKey kStatKeys[] = {
    {ND_STAT_FACTORIZATIONS, &Counters::factorizations},
    {ND_STAT_SYMBOLIC_ANALYSES, &Counters::symbolic_analyses},
    {ND_STAT_SOLVES, &Counters::solves},
    {ND_STAT_MATRIX_ASSEMBLIES, &Counters::matrix_assemblies},
    {ND_STAT_LOAD_ASSEMBLIES, &Counters::load_assemblies},
    {ND_STAT_TANGENT_UPDATES, &Counters::tangent_updates},
    {ND_STAT_CONTACT_EVALUATIONS, &Counters::contact_evaluations},
    {ND_STAT_SPMV, &Counters::spmv},
    {ND_STAT_POINT_EVALUATIONS, &Counters::point_evaluations},
    {ND_STAT_POINT_EVALUATIONS_OWN, &Counters::own_point_evaluations},
    {ND_STAT_CONTACT_BOUNDS, &Counters::contact_bounds},
    {ND_STAT_MATRIX_ENTRIES_OWN, &Counters::matrix_entries},
    {ND_STAT_VALUES_RECEIVED, &Counters::values_received},
    {ND_STAT_POINT_VALUES_RECEIVED, &Counters::point_values_received},
    {ND_STAT_KRYLOV_ITERATIONS, &Counters::krylov_iterations},
    {ND_STAT_PREDICTED_STEPS, &Counters::predicted_steps},
    {ND_STAT_LAGGED_STEPS, &Counters::lagged_steps},
    {ND_STAT_FACTOR_MODIFICATIONS, &Counters::factor_modifications},
    {ND_STAT_FACTOR_MODIFIED_ENTRIES, &Counters::factor_modified_entries},
    {ND_STAT_NORMAL_REFRESHES, &Counters::normal_refreshes},
    {ND_STAT_STEPS_ACCEPTED, &Counters::steps_accepted},
    {ND_STAT_STEPS_REJECTED, &Counters::steps_rejected},
};
}  // namespace

double Problem::region_scalar(int region, int key) {
  const Discretization &d = discretization_();
  if (std::find(d.contact.region.begin(), d.contact.region.end(), region) == d.contact.region.end())
    fail(ND_ERR_REGION, "region " + std::to_string(region) +
                            " has no contact points (a region with a plane or an obstacle, or a pair's slave region)");
  const bool friction_key = key == ND_DISSIPATION_FRICTION || key == ND_SLIDING_POINTS || key == ND_STICKING_POINTS;
  const bool tangential_key = key == ND_CONTACT_FORCE_TANGENTIAL_X || key == ND_CONTACT_FORCE_TANGENTIAL_Y ||
                              key == ND_CONTACT_FORCE_TANGENTIAL_Z;
  if (key != ND_CONTACT_FORCE && key != ND_CONTACT_FORCE_APPLIED && key != ND_ACTIVE_POINTS &&
      key != ND_MAX_PENETRATION && key != ND_ENERGY_NITSCHE && !friction_key && !tangential_key)
    fail(ND_ERR_KEY, "key " + std::to_string(key) + " is not a scalar of a contact region's points (ND_CONTACT_FORCE, "
                     "ND_CONTACT_FORCE_APPLIED, ND_ACTIVE_POINTS, ND_MAX_PENETRATION, ND_ENERGY_NITSCHE, "
                     "ND_DISSIPATION_FRICTION, ND_SLIDING_POINTS, ND_STICKING_POINTS, ND_CONTACT_FORCE_TANGENTIAL_X/Y/Z)");
  complete_state();  // (a distributed state: every point's values)
  const State &s = state();
  if (tangential_key) return tangential_resultant(d, s, region)[key - ND_CONTACT_FORCE_TANGENTIAL_X];
  if (friction_key) {
    if (d.contact.m <= 1) return 0.0;  // (frictionless: as nd_get_scalar's)
    if (s.by_region.empty())
      fail(ND_ERR_STATE, "the contact regions' friction values are unknown: the state was loaded from a checkpoint "
                         "older than version 12 with several contact regions (nd_get_scalar has the problem's)");
    const std::vector<int> regions = friction_regions(d.contact);
    const size_t slot = static_cast<size_t>(std::find(regions.begin(), regions.end(), region) - regions.begin());
    if (3 * slot + 2 >= s.by_region.size()) fail(ND_ERR_INTERNAL, "the state has no friction values for the region");
    return s.by_region[3 * slot + (key == ND_DISSIPATION_FRICTION ? 0 : key == ND_SLIDING_POINTS ? 1 : 2)];
  }
  const PointSums t = region_sums(d, s, products_, region);
  switch (key) {
    case ND_CONTACT_FORCE:
      return t.force;
    case ND_CONTACT_FORCE_APPLIED:
      return t.force_applied;
    case ND_ACTIVE_POINTS:
      return t.active;
    case ND_MAX_PENETRATION:
      return t.penetration;
    default:
      return t.nitsche;
  }
}

double Problem::scalar(int key) {
  for (const StatKey &k : kStatKeys)
    if (k.key == key) return static_cast<double>(counters_.get()->*k.field);
  // the clock and the counters of a state not made yet are the initial
  // state's (all zero): read without building the operators, which may fail
  static const State kInitial;
  const State &c = state_ready_ ? state_ : kInitial;
  switch (key) {
    case ND_TIME:
      return c.t;
    case ND_STEP_INDEX:
      return static_cast<double>(c.n);
    case ND_NEWTON_ITERATIONS:
      return c.last_iterations;
    case ND_NEWTON_ITERATIONS_TOTAL:
      return static_cast<double>(c.total_iterations);
    case ND_WORK:
      return c.W;
    case ND_WORK_OBSTACLE:
      return c.W_obstacle;
    case ND_DISSIPATION_FRICTION:
      return c.D_friction;
    case ND_SLIDING_POINTS:
      return static_cast<double>(c.sliding);
    case ND_STICKING_POINTS:
      return static_cast<double>(c.sticking);
    case ND_DISSIPATION_DAMPING:
      return c.D_damping;
    case ND_WORK_PRESCRIBED:
      return c.W_prescribed;
    case ND_WORK_GEOMETRY:
      return c.W_geometry;
    case ND_TIMESTEP:  // (adaptive: the size the next step tries)
      return def_.adaptive.on() && c.control.tau_next > 0 ? c.control.tau_next : def_.tau;
    case ND_TIMESTEP_LAST:
      return c.n > 0 ? (c.control.tau_last > 0 ? c.control.tau_last : c.tau_ref) : 0.0;
    case ND_ERROR_ESTIMATE:
      return c.control.ratio;
    case ND_PARTITION_KIND: {  // (made when the communicator was given: no message)
      const std::string &method = ownership().method;
      return method == "one rank" ? 0 : method == "slabs" ? 2 : 1;
    }
    case ND_GAMMA0:
      return discretization_().gamma0;
    case ND_GAMMA0_LIMIT: {
      const Discretization &d = discretization_();
      return d.theta > 0 ? d.gamma0_limit / d.theta : std::numeric_limits<double>::infinity();
    }
    default:
      break;
  }
  const State &s = state();
  const Discretization &d = discretization_();
  switch (key) {
    case ND_ENERGY_MECHANICAL:
      return mechanical_energy(d, s, products_);
    case ND_ENERGY_NITSCHE:
      return nitsche_energy(d, s, products_);
    case ND_ENERGY_AUGMENTED:
      return mechanical_energy(d, s, products_) - d.theta * nitsche_energy(d, s, products_);
    case ND_CONTACT_FORCE:
      return contact_force(d, s, products_);
    case ND_CONTACT_FORCE_APPLIED:
      return contact_force_applied(d, s, products_);
    case ND_ACTIVE_POINTS:
      return static_cast<double>(active_points(d, s, products_));
    case ND_MAX_PENETRATION:
      return max_penetration(d, s, products_);
    case ND_CONTACT_FORCE_TANGENTIAL_X:
    case ND_CONTACT_FORCE_TANGENTIAL_Y:
    case ND_CONTACT_FORCE_TANGENTIAL_Z:
      return tangential_resultant(d, s)[key - ND_CONTACT_FORCE_TANGENTIAL_X];
    default:
      fail(ND_ERR_KEY, "key " + std::to_string(key) + " is not an ND_* scalar key");
  }
}

}  // namespace nd
