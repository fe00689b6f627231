#include "problem/discretization.hpp"

#include "contact/obstacles.hpp"
#include "contact/pairing.hpp"

#include <cstdint>

#include <algorithm>
#include <map>
#include <memory>
#include <cmath>

#include "assembly/bulk.hpp"
#include "assembly/coercivity.hpp"
#include "common/format.hpp"
#include "assembly/nitsche.hpp"
#include "assembly/redistribution.hpp"
#include "mesh/cell_shape.hpp"
#include "mesh/geometry.hpp"
#include "parallel/share.hpp"
#include "problem/forces.hpp"
#include "solve/contact_law.hpp"

namespace nd {

namespace {

// The scheme's mass (consistent, or lumped on K's pattern) and K, of a part
// of the cells or rows, each with its mass redistributed from the contact
// nodes when the definition asks for it.
BulkOperators mass_and_stiffness(const Space &space, const DofMap &dofs, const Definition &def,
                                 const std::vector<char> *on_contact, const AssemblyPart &part) {
  BulkOperators bulk =
      assemble_bulk(space, dofs, materials_of(space, def), def.redistributed ? on_contact : nullptr, part);
  if (def.lumped) {
    bulk.M = bulk.K.zeros_like();
    for (int64_t i = 0; i < bulk.M.n; ++i)
      if (const int64_t k = bulk.M.find(i, i); k >= 0) bulk.M.val[k] = bulk.M_lumped[i];
  }
  return bulk;
}
}  // namespace

CellMaterials materials_of(const Space &space, const Definition &def) {
  // (plane stress is the 2D model's, every region's: nd_problem_set_plane_stress)
  std::map<int, Material> regions = def.region_materials;
  for (auto &[region, m] : regions) m.plane_stress = def.material.plane_stress;
  return cell_materials(def.material, regions, space.mesh->cell_region);
}

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

namespace {
// cp.friction: whether each point's region has a frictional law (with friction)
void mark_friction(const Definition &def, ContactPoints &cp) {
  if (cp.m == 1) return cp.friction.clear();
  cp.friction.assign(cp.size(), 0);
  for (size_t q = 0; q < cp.size(); ++q)
    for (const Definition::Friction &f : def.friction)
      if (f.region == cp.region[q] && f.law != kFrictionNone) cp.friction[q] = 1;
}

// The law of every point: its region's (contact/laws.cpp)
std::shared_ptr<const PointLaw> point_laws(const Definition &def, const ContactPoints &cp, int dim) {
  std::vector<std::pair<int, std::shared_ptr<const PointLaw>>> by_region;
  for (const Definition::Friction &f : def.friction)
    if (f.law != kFrictionNone) by_region.emplace_back(f.region, make_law(f.law, &f.parameter, dim));
  return laws_by_point(cp.region, by_region);
}

// The contact points with each one's normal: a plane region's plane's, a
// curved point's frozen (given) or nearest obstacle's at x_q, the obstacles
// where the definition places them (t = 0); a pair's point with its frozen
// pairing (given with the normals) or its projection on the master surface
// in the reference configuration, its rows holding the master's side
ContactPoints contact_points(const Space &space, const DofMap &dofs, const Definition &def, double gamma0,
                             const std::vector<double> *frozen, const std::vector<double> *pairing) {
  // without frozen normals: the obstacles as defined (no pose), so that the
  // normals, and gamma0* from them, depend on the definition alone (a restart
  // makes the same)
  std::vector<Obstacle> defined = def.obstacles;
  for (Obstacle &o : defined) o.pose = Pose{};
  const std::vector<int> regions = contact_regions(def.planes, def.obstacles, def.pairs);
  std::vector<int> plane_of(regions.size(), -1);
  for (size_t r = 0; r < regions.size(); ++r)
    if (!curved_region(regions[r], def.obstacles) && pair_of(regions[r], def.pairs) < 0)
      for (size_t ip = 0; ip < def.planes.size(); ++ip)
        if (def.planes[ip].region == regions[r]) plane_of[r] = static_cast<int>(ip);
  std::vector<std::unique_ptr<MasterSurface>> surfaces(def.pairs.size());
  std::vector<double> paired;  // the pairings, kPairingValues per point
  size_t q = 0;  // (normal_of is called for each point in turn)
  ContactPoints cp = assemble_contact(
      space, dofs, materials_of(space, def), regions, plane_of,
      [&](size_t r, int64_t b, const double *x, double *nu) {
        const int pair = pair_of(regions[r], def.pairs);
        double at[kPairingValues] = {-1, 0, 0, 0};
        if (plane_of[r] >= 0) {
          for (int k = 0; k < space.dim; ++k) nu[k] = def.planes[plane_of[r]].normal[k];
        } else if (frozen) {
          if (frozen->size() < 3 * (q + 1)) fail(ND_ERR_INTERNAL, "fewer frozen normals than contact points");
          for (int k = 0; k < space.dim; ++k) nu[k] = (*frozen)[3 * q + k];
          if (pair >= 0) {
            if (!pairing || pairing->size() < kPairingValues * (q + 1))
              fail(ND_ERR_INTERNAL, "fewer pairings than contact points");
            std::copy_n(&(*pairing)[kPairingValues * q], kPairingValues, at);
          }
        } else if (pair >= 0) {
          auto &surface = surfaces[static_cast<size_t>(pair)];
          if (!surface) surface = std::make_unique<MasterSurface>(space, dofs, def.pairs[pair].master, nullptr);
          Projection p;
          if (def.pairs[pair].slave != def.pairs[pair].master) {
            p = surface->project(x);
          } else {
            // a region paired with itself: its points meet the sides facing
            // them within the steps' reach (contact/obstacles.cpp); one with
            // none starts unpaired, as if facing an opposed facet (its rows
            // without a master side, its gap that reach)
            const OwnFacet own{b, space.mesh->cell_diameter(space.mesh->boundary[b].cell)};
            p = surface->project(x, kPairReach * surface->bucket(), -1, &own);
            if (p.facet < 0) {
              if (!facet_normal(space, dofs, b, nullptr, p.nu))
                fail(ND_ERR_INTERNAL, "a facet of a region paired with itself has no normal");
              for (double &c : p.nu) c = -c;
            }
          }
          for (int k = 0; k < space.dim; ++k) nu[k] = p.nu[k];
          at[0] = static_cast<double>(p.facet);
          std::copy_n(p.bary, kPairingValues - 1, at + 1);
        } else {
          const Nearest n = nearest(regions[r], def.planes, defined, space.dim, 0.0, x);
          for (int k = 0; k < space.dim; ++k) nu[k] = n.nu[k];
        }
        paired.insert(paired.end(), at, at + kPairingValues);
        ++q;
      },
      gamma0, def.has_friction());
  if (!def.pairs.empty()) {
    cp.pairing = std::move(paired);
    for (size_t p = 0; p < cp.size(); ++p) {
      const double *at = &cp.pairing[kPairingValues * p];
      if (at[0] < 0) continue;
      const int64_t facet = static_cast<int64_t>(at[0]);
      if (facet >= static_cast<int64_t>(space.mesh->boundary.size()))
        fail(ND_ERR_INTERNAL, "a pairing's facet is out of range");
      double xi[3] = {0, 0, 0};
      facet_point_reference(*space.mesh, space.mesh->boundary[facet], at + 1, xi);
      append_counterpart(space, dofs, cp, p, space.mesh->boundary[facet].cell, xi);
    }
  }
  cp.gap = contact_gaps(cp, def.planes);
  mark_friction(def, cp);
  return cp;
}
}  // namespace

namespace {
// sum_K E_K |K| over every cell of the mesh (each rank the whole mesh): a
// simplex |det J|/dim!, a quadrilateral or hexahedron |det J| at its centre
// (exact for a bilinear quadrilateral, whose det J is affine)
// (and |Omega| into *volume_out)
double stiffness_volume(const Space &space, const CellMaterials &mat, double *volume_out) {
  const Mesh &m = *space.mesh;
  const int dim = m.dim;
  const double factorial = dim == 1 ? 1 : dim == 2 ? 2 : 6;
  const double *corners[8];
  double J[9], sum = 0, total = 0;
  const double centre[3] = {0.5, 0.5, 0.5};
  for (int64_t c = 0; c < m.n_cells; ++c) {
    const int64_t *v = m.cell(c);
    for (int i = 0; i < m.cell_vertices(c); ++i) corners[i] = m.x(v[i]);
    double volume;
    if (m.simplicial(c)) {
      simplex_jacobian(dim, corners, J);
      volume = std::fabs(determinant(dim, J)) / factorial;
    } else {
      cube::jacobian(dim, corners, centre, J);
      volume = std::fabs(determinant(dim, J));
    }
    sum += mat.of(c).young * volume;
    total += volume;
  }
  *volume_out = total;
  return sum;
}

// min(h_q, L/8), L = |Omega| / |Gamma_C| (|Gamma_C| = sum_q w_q, a point's
// weight 1 in 1D): the penetration guard's lengths (docs/design.md §3b.5)
std::vector<double> penetration_lengths(const ContactPoints &cp, double volume) {
  double area = 0;
  for (double w : cp.w) area += w;
  const double body = area > 0 ? volume / area / kPenetrationBodyDivisor : 0;
  std::vector<double> length(cp.size());
  for (size_t q = 0; q < cp.size(); ++q) length[q] = std::min(cp.h[q], body);
  return length;
}

// C = alpha M + beta K with the scheme's mass, on their shared pattern
void set_damping(Discretization &d, const Definition &def) {
  d.damping_alpha = def.damping_alpha, d.damping_beta = def.damping_beta;
  if (def.damping_alpha == 0 && def.damping_beta == 0) return;
  if (d.rows_split)
    fail(ND_ERR_STATE, "Rayleigh damping is not available yet with a distributed solver on several ranks "
                       "(the rows split over the ranks)");
  if (def.damping_beta != 0 && !d.massless.empty())
    fail(ND_ERR_STATE, "stiffness-proportional damping (beta > 0) with mass redistribution: the massless DOFs "
                       "would carry beta K V without an equation for V; use alpha only, or no redistribution");
  count(d.counters, &Counters::matrix_assemblies);
  csr_combine(def.damping_alpha, d.M, def.damping_beta, d.K, d.C);
}
}  // namespace


std::unique_ptr<Discretization> discretize(const Space &space, const Definition &def, Counters *counters,
                                           const Ownership *own, const std::vector<double> *frozen,
                                           const std::vector<double> *pairing) {
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
    on_contact = contact_nodes(space, contact_node_regions(def.planes, def.obstacles, def.pairs));
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
  d->contact = contact_points(space, d->dofs, def, automatic ? 1.0 : def.gamma0, nullptr, nullptr);
  d->contact_law = def.contact_law_given ? def.contact_law_given : point_laws(def, d->contact, space.dim);
  d->gamma0_limit = gamma0_limit(space, d->dofs, materials_of(space, def), d->contact);
  double volume = 0;
  d->stiffness_volume = stiffness_volume(space, materials_of(space, def), &volume);
  if (frozen) d->contact = contact_points(space, d->dofs, def, automatic ? 1.0 : def.gamma0, frozen, pairing);
  d->theta = def.theta;
  d->gamma0 = def.gamma0;
  if (automatic && d->contact.size() > 0) {
    if (!(d->gamma0_limit > 0 && std::isfinite(d->gamma0_limit)))
      fail(ND_ERR_NITSCHE, "no automatic gamma0: the coercivity limit is " + num(d->gamma0_limit));
    d->gamma0 = automatic_gamma0_fraction(def) * d->gamma0_limit;
    for (size_t q = 0; q < d->contact.size(); ++q) d->contact.gamma[q] = d->gamma0 * d->contact.gamma_length[q];
  }
  set_bounds(d->contact);
  require_shared_index_lists(d->contact);
  d->penetration_length = penetration_lengths(d->contact, volume);
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
  set_damping(*d, def);
  if (d->dofs.n_free < space.n_dofs())
    d->clamped = std::make_unique<ClampedRows>(
        clamped_rows(space, d->dofs, materials_of(space, def), def.redistributed ? &on_contact : nullptr));
  return d;
}

double automatic_gamma0_fraction(const Definition &def) {
  if (def.theta <= 0 && def.scheme == ND_SCHEME_HYBRID) return kAutomaticGamma0SkewHybrid;
  return kAutomaticGamma0Fraction / std::max(def.theta, 1.0);
}

std::unique_ptr<Discretization> with_normals(const Space &space, const Definition &def, const Discretization &from,
                                             const std::vector<double> &frozen, const std::vector<double> *pairing) {
  auto d = std::make_unique<Discretization>(from.dofs, from.lumped);
  d->counters = from.counters;
  d->M = from.M, d->M_lumped = from.M_lumped, d->massless = from.massless, d->K = from.K;
  d->theta = from.theta, d->gamma0 = from.gamma0, d->gamma0_limit = from.gamma0_limit;
  d->stiffness_volume = from.stiffness_volume, d->penetration_length = from.penetration_length;
  d->contact_law = from.contact_law;
  d->rows_split = from.rows_split;
  d->geometry.dim = space.dim;
  d->node_blocks = from.node_blocks;  // (K and M by nodes: the same)
  d->damping_alpha = from.damping_alpha, d->damping_beta = from.damping_beta, d->C = from.C;
  if (from.clamped) d->clamped = std::make_unique<ClampedRows>(*from.clamped);
  // the rows with the frozen normals; gamma as the first discretization has it
  d->contact = contact_points(space, d->dofs, def, d->gamma0, &frozen, pairing);
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
      def.redistributed ? contact_nodes(space, contact_node_regions(def.planes, def.obstacles, def.pairs)) : std::vector<char>();
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

}  // namespace nd
