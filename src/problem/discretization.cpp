#include "problem/discretization.hpp"

#include "contact/obstacles.hpp"

#include <atomic>
#include <cstdint>

#include <algorithm>
#include <cmath>

#include "assembly/bulk.hpp"
#include "assembly/coercivity.hpp"
#include "common/format.hpp"
#include "assembly/nitsche.hpp"
#include "assembly/redistribution.hpp"
#include "linalg/pcg.hpp"
#include "parallel/share.hpp"
#include "problem/forces.hpp"
#include "solve/contact_law.hpp"

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
// (solve/predictor_check.hpp; its residual holds (omega tau)^2/2 times that
// error). The few more iterations this costs bring the first predicted
// step well within kPredictorRoundOffs.
constexpr double kMassCgTarget = 1e-16;
constexpr int kMassCgMaxIterations = 300;

// The scheme's mass (consistent, or lumped on K's pattern) and K, of a part
// of the cells or rows, each with its mass redistributed from the contact
// nodes when the definition asks for it.
BulkOperators mass_and_stiffness(const Space &space, const DofMap &dofs, const Definition &def,
                                 const std::vector<char> *on_contact, const AssemblyPart &part) {
  BulkOperators bulk = assemble_bulk(space, dofs, def.material, def.redistributed ? on_contact : nullptr, part);
  if (def.lumped) {
    bulk.M = bulk.K.zeros_like();
    for (int64_t i = 0; i < bulk.M.n; ++i)
      if (const int64_t k = bulk.M.find(i, i); k >= 0) bulk.M.val[k] = bulk.M_lumped[i];
  }
  return bulk;
}
}  // namespace

bool splits_rows(const Definition &def) {
  return communicator_size(def.comm.get()) > 1 && linear_solver_distributes(def.solver) && !def.lumped &&
         !def.redistributed;
}

void locate_unknowns(const Space &space, const DofMap &dofs, DofGeometry &g) {
  const bool own = g.own_rows_only;
  if (own && (!g.row_of || g.row_end < g.row_begin))
    fail(ND_ERR_INTERNAL, "the coordinates of a rank's rows, without its rows");
  const int64_t m = own ? g.row_end - g.row_begin : dofs.n_free;  // the unknowns described
  g.dim = space.dim;
  g.x.assign(static_cast<size_t>(m * space.dim), 0.0);
  g.component.assign(static_cast<size_t>(m), 0);
  for (int64_t dof = 0; dof < space.n_dofs(); ++dof) {
    const int64_t r = dofs.free[dof];
    if (r < 0) continue;
    const int64_t k = own ? (*g.row_of)[r] - g.row_begin : r;  // its place among those described
    if (k < 0 || k >= m) continue;
    std::copy_n(space.node_x(dof / space.dim), space.dim, &g.x[k * space.dim]);
    g.component[k] = static_cast<int>(dof % space.dim);
  }
  g.located = true;
}

const Share *own_rows_of(const Discretization &d, bool in_step) {
  return in_step || d.rows_split ? d.rows.get() : nullptr;
}

namespace {
// The contact points with each one's normal: a plane region's plane's, a
// curved point's frozen (given) or nearest obstacle's at x_q, the obstacles
// where the definition places them (t = 0)
ContactPoints contact_points(const Space &space, const DofMap &dofs, const Definition &def, double gamma0,
                             const std::vector<double> *frozen) {
  // without frozen normals: the obstacles as defined (no pose), so that the
  // normals, and gamma0* from them, depend on the definition alone (a restart
  // makes the same)
  std::vector<Obstacle> defined = def.obstacles;
  for (Obstacle &o : defined) o.pose = Pose{};
  const std::vector<int> regions = contact_regions(def.planes, def.obstacles);
  std::vector<int> plane_of(regions.size(), -1);
  for (size_t r = 0; r < regions.size(); ++r)
    if (!curved_region(regions[r], def.obstacles))
      for (size_t ip = 0; ip < def.planes.size(); ++ip)
        if (def.planes[ip].region == regions[r]) plane_of[r] = static_cast<int>(ip);
  size_t q = 0;  // (normal_of is called for each point in turn)
  ContactPoints cp = assemble_contact(
      space, dofs, def.material, regions, plane_of,
      [&](size_t r, const double *x, double *nu) {
        if (plane_of[r] >= 0) {
          for (int k = 0; k < space.dim; ++k) nu[k] = def.planes[plane_of[r]].normal[k];
        } else if (frozen) {
          if (frozen->size() < 3 * (q + 1)) fail(ND_ERR_INTERNAL, "fewer frozen normals than contact points");
          for (int k = 0; k < space.dim; ++k) nu[k] = (*frozen)[3 * q + k];
        } else {
          const Nearest n = nearest(regions[r], def.planes, defined, space.dim, 0.0, x);
          for (int k = 0; k < space.dim; ++k) nu[k] = n.nu[k];
        }
        ++q;
      },
      gamma0);
  cp.gap = contact_gaps(cp, def.planes);
  return cp;
}
}  // namespace

std::unique_ptr<Discretization> discretize(const Space &space, const Definition &def, Counters *counters,
                                           const Ownership *own, const std::vector<double> *frozen) {
  require_complete(def.missing_for_operators());
  auto d = std::make_unique<Discretization>(DofMap(space, def.dirichlet), def.lumped);
  d->counters = counters;
  std::vector<char> own_rows;  // per free DOF: of one of own's nodes
  AssemblyPart part;
  if (own && !own->node_owner.empty()) {
    own_rows.assign(static_cast<size_t>(d->dofs.n_free), 0);
    for (int64_t dof = 0; dof < space.n_dofs(); ++dof)
      if (const int64_t r = d->dofs.free[dof]; r >= 0) own_rows[r] = own->node_owner[dof / space.dim] == own->rank;
    part.rows = &own_rows;
    d->rows_split = true;
  }
  count(counters, &Counters::matrix_assemblies, 2);  // M and K in one pass
  std::vector<char> on_contact;
  if (def.redistributed) {
    on_contact = contact_nodes(space, contact_regions(def.planes, def.obstacles));
    d->massless.assign(static_cast<size_t>(d->dofs.n_free), 0);
    for (int64_t node = 0; node < space.n_nodes; ++node)
      for (int a = 0; a < space.dim; ++a) {
        const int64_t r = d->dofs.free[node * space.dim + a];
        if (on_contact[node] && r >= 0) d->massless[r] = 1;
      }
    if (std::find(d->massless.begin(), d->massless.end(), 1) == d->massless.end()) d->massless.clear();
  }
  d->geometry.dim = space.dim;  // (where the unknowns sit: locate_unknowns, for the solver that reads it)
  BulkOperators bulk = mass_and_stiffness(space, d->dofs, def, &on_contact, part);
  d->K = std::move(bulk.K);
  d->M = std::move(bulk.M);
  if (def.lumped) d->M_lumped = std::move(bulk.M_lumped);
  const bool automatic = def.gamma0 == 0;
  d->contact_law = def.contact_law_given ? def.contact_law_given : make_law(def.contact_law);
  // (the passes hold one value per point: laws with more come with friction, issue 56)
  if (d->contact_law->traits().m != 1)
    fail(ND_ERR_INTERNAL, std::string("the contact law ") + d->contact_law->name() + " has " +
                              std::to_string(d->contact_law->traits().m) + " values per point; the passes hold one");
  d->contact = contact_points(space, d->dofs, def, automatic ? 1.0 : def.gamma0, nullptr);
  d->gamma0_limit = gamma0_limit(space, d->dofs, def.material, d->contact);
  if (frozen) d->contact = contact_points(space, d->dofs, def, automatic ? 1.0 : def.gamma0, frozen);
  d->theta = def.theta;
  d->gamma0 = def.gamma0;
  if (automatic && d->contact.size() > 0) {
    if (!(d->gamma0_limit > 0 && std::isfinite(d->gamma0_limit)))
      fail(ND_ERR_NITSCHE, "no automatic gamma0: the coercivity limit is " + num(d->gamma0_limit));
    d->gamma0 = kAutomaticGamma0Fraction * d->gamma0_limit / std::max(def.theta, 1.0);
    for (size_t q = 0; q < d->contact.size(); ++q) d->contact.gamma[q] = d->gamma0 * d->contact.h[q];
  }
  set_bounds(d->contact);
  require_shared_index_lists(d->contact);
  count(counters, &Counters::matrix_assemblies);
  try {
    d->K_theta = assemble_k_theta(d->K, d->contact, def.theta);
  } catch (const Error &e) {  // overflow: a gamma0 far too large, or units to rescale
    const std::string safe = safe_gamma0(d->theta, d->gamma0_limit);
    if (e.code() != ND_ERR_NITSCHE || safe.empty()) throw;
    fail(ND_ERR_NITSCHE, std::string(e.what()) + "; gamma0 = " + num(d->gamma0) + ", and " + safe);
  }
  if (counters)
    counters->matrix_entries = static_cast<int64_t>(d->M.val.size() + d->K.val.size() + d->K_theta.val.size());
  if (!d->rows_split) d->node_blocks = make_node_blocks(d->K, d->M, space.dim);
  if (d->dofs.n_free < space.n_dofs())
    d->clamped = std::make_unique<ClampedRows>(
        clamped_rows(space, d->dofs, def.material, def.redistributed ? &on_contact : nullptr));
  return d;
}

std::unique_ptr<Discretization> with_normals(const Space &space, const Definition &def, const Discretization &from,
                                             const std::vector<double> &frozen) {
  auto d = std::make_unique<Discretization>(from.dofs, from.lumped);
  d->counters = from.counters;
  d->M = from.M, d->M_lumped = from.M_lumped, d->massless = from.massless, d->K = from.K;
  d->theta = from.theta, d->gamma0 = from.gamma0, d->gamma0_limit = from.gamma0_limit;
  d->contact_law = from.contact_law;
  d->rows_split = from.rows_split;
  d->geometry.dim = space.dim;
  d->node_blocks = from.node_blocks;  // (K and M by nodes: the same)
  if (from.clamped) d->clamped = std::make_unique<ClampedRows>(*from.clamped);
  // the rows with the frozen normals; gamma as the first discretization has it
  d->contact = contact_points(space, d->dofs, def, d->gamma0, &frozen);
  for (size_t q = 0; q < d->contact.size(); ++q) d->contact.gamma[q] = from.contact.gamma[q];
  set_bounds(d->contact);
  require_shared_index_lists(d->contact);
  count(d->counters, &Counters::matrix_assemblies);
  d->K_theta = assemble_k_theta(d->K, d->contact, d->theta);
  if (d->counters)
    d->counters->matrix_entries = static_cast<int64_t>(d->M.val.size() + d->K.val.size() + d->K_theta.val.size());
  return d;
}

Csr assemble_own_step_matrix(const Space &space, const Discretization &d, const Definition &def, const Ownership &own,
                             double c) {
  std::vector<char> cells(static_cast<size_t>(space.mesh->n_cells)), points(d.contact.size());
  for (int64_t cell = 0; cell < space.mesh->n_cells; ++cell) cells[cell] = own.owns_cell(cell);
  for (size_t q = 0; q < points.size(); ++q) points[q] = own.owns_cell(space.mesh->boundary[d.contact.facet[q]].cell);
  const std::vector<char> on_contact =
      def.redistributed ? contact_nodes(space, contact_regions(def.planes, def.obstacles)) : std::vector<char>();
  BulkOperators bulk = mass_and_stiffness(space, d.dofs, def, &on_contact, AssemblyPart{&cells, nullptr});
  count(d.counters, &Counters::matrix_assemblies);
  add_nitsche_terms(bulk.K, d.contact, d.theta, &points);
  Csr &A = bulk.K;  // A = c M + K_Theta, as csr_combine forms the whole one
  for (size_t k = 0; k < A.val.size(); ++k) A.val[k] = c * bulk.M.val[k] + 1.0 * A.val[k];
  return std::move(A);
}

std::vector<double> constant_load(const Space &space, const Discretization &d, const Definition &def) {
  if (def.has_body_force || !def.neumann.empty()) count(d.counters, &Counters::load_assemblies);
  return assemble_load(space, d.dofs, def.has_body_force ? def.body_force : nullptr, def.neumann);
}

void check_coercivity(Discretization &d, int solver, const Factorization *A_factor) {
  if (d.coercive || !(d.theta > 0) || d.theta * d.gamma0 <= d.gamma0_limit) {
    d.coercive = true;
    return;
  }
  // K_Theta's kernel (rigid motions of a free body) is lifted by delta M,
  // far above round-off and far below any eigenvalue of the Nitsche term
  // that matters for growth in time.
  // (of every rank's rows: collective when they are split)
  double kmax = 0, mmax = 0;
  const RowSet held = own_rows(own_rows_of(d, false));
  for (int64_t r = 0, m = held.size(d.K.n); r < m; ++r) {
    const int64_t i = held[r];
    kmax = std::max(kmax, d.K.val[d.K.find(i, i)]);
    mmax = std::max(mmax, d.M.val[d.M.find(i, i)]);
  }
  if (d.rows_split) {
    const Communicator *comm = d.rows->comm.get();
    kmax = max_over_ranks(comm, kmax), mmax = max_over_ranks(comm, mmax);
  }
  Csr A;
  count(d.counters, &Counters::matrix_assemblies);
  csr_combine(1.0, d.K_theta, 1e-10 * kmax / mmax, d.M, A);
  // a solver that does not certify it (GAMG) hands the check to a direct
  // one: CHOLMOD on each rank's whole matrix, or MUMPS over split rows
  const int checker = linear_solver_certifies_definiteness(solver) ? solver
                      : d.rows_split                                 ? ND_SOLVER_PETSC_MUMPS
                                                                     : ND_SOLVER_AUTO;
  auto f = make_factorization(checker, A, Structure::SymmetricPositiveDefinite, d.counters, &d.geometry, A_factor);
  try {
    f->factor(A, Structure::SymmetricPositiveDefinite);
  } catch (const Error &e) {
    if (e.code() != ND_ERR_INDEFINITE) throw;
    fail(ND_ERR_NOT_COERCIVE, "K_Theta = K - Theta sum_q w_q gamma_q s_q s_q^T: " + std::string(e.what()) +
                                  "; the free motion would grow exponentially. With Theta = " + num(d.theta) +
                                  ", gamma0 = " + num(d.gamma0) + " exceeds the coercivity limit: gamma0 <= " +
                                  num(d.gamma0_limit / d.theta) +
                                  " is safe (element bound), and gamma0 = 0 chooses one automatically");
  }
  d.coercive = true;
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

void Discretization::equilibrium_acceleration(State &s, int solver, bool once, bool in_step, PointValues *at_U) {
  // U and V stay: of the products only M A changes (products_current);
  // dropped first, so that a throw below leaves none of the old A's
  s.products.MA.clear();
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
  // split operators: the mass solve is distributed and reads this rank's rows only
  if (share && !rows_split) gather(*share, {rhs.data()});
  ContactLaw law{&contact, theta, nullptr, nullptr, nullptr, counters};
  law.point_law = contact_law.get();
  law.local = !in_step;
  if (!s.gap.empty()) law.gap = s.gap.data();
  if (at_U && contact.size() > 0) {
    law.P_all(s.U.data(), at_U->P, &at_U->un);
    law.add_force_from(at_U->P, 1.0, rhs.data(), nullptr);
  } else {
    law.add_force(s.U.data(), 1.0, rhs.data(), nullptr);
  }
  const std::vector<double> &F = s.load();
  for (size_t i = 0; i < n; ++i) rhs[i] = (F.empty() ? 0.0 : F[i]) - rhs[i];
  mass_solve(rhs.data(), solver, once);
  s.A = std::move(rhs);
  s.A_valid = true;
}

}  // namespace nd
