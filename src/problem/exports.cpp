#include "problem/exports.hpp"

#include <algorithm>
#include <string>

#include "assembly/bulk.hpp"
#include "assembly/redistribution.hpp"
#include "common/error.hpp"
#include "problem/integrator.hpp"
#include "solve/clamped_coupling.hpp"
#include "time/scheme.hpp"

namespace nd {

const Discretization &whole_operators(Problem &p, const char *what) {
  const Discretization &d = p.discretization();
  if (d.rows_split)
    fail(ND_ERR_STATE, std::string(what) + ": the operators are split over the ranks (a distributed solver); "
                                           "without a communicator, or with a serial solver, they are whole");
  return d;
}

namespace {
// The HRZ diagonal: the scheme's when it lumps, else the same lumping of the
// element masses it assembles (redistributed ones included), on the free DOFs
std::vector<double> lumped_diagonal(Problem &p, const Discretization &d) {
  if (d.lumped) return d.M_lumped;
  const Definition &def = p.definition();
  std::vector<char> on_contact;
  if (def.redistributed) on_contact = contact_nodes(p.space(), def.planes);
  return assemble_bulk(p.space(), d.dofs, materials_of(p.space(), def), def.redistributed ? &on_contact : nullptr)
      .M_lumped;
}

Csr diagonal(const std::vector<double> &m) {
  const int64_t n = static_cast<int64_t>(m.size());
  std::vector<std::vector<int64_t>> rows(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) rows[i] = {i};
  Csr D = csr_from_rows(std::move(rows));
  D.val = m;
  return D;
}
}  // namespace

Csr exported_matrix(Problem &p, int which) {
  const Discretization &d = whole_operators(p, "the matrices");
  Csr out;
  switch (which) {
    case ND_MATRIX_MASS:
      return d.M;
    case ND_MATRIX_STIFFNESS:
      return d.K;
    case ND_MATRIX_NITSCHE:
      csr_combine(1.0, d.K_theta, -1.0, d.K, out);
      return out;
    case ND_MATRIX_LUMPED_MASS:
      return diagonal(lumped_diagonal(p, d));
    case ND_MATRIX_STEP: {
      const Definition &def = p.definition();
      require_complete(def.missing_for_step());
      const std::unique_ptr<TimeScheme> scheme = make_scheme(def.scheme, def.scheme_params);
      if (scheme->is_explicit())
        fail(ND_ERR_STATE, "the scheme set is explicit: it has no step matrix c M + K_Theta (theta = 0 or "
                           "Newmark beta = 0); set an implicit scheme");
      // the integrator's own combination (make_integrator): the same bits as the A a step factors
      step_matrix(d, *scheme, def.tau, out);
      return out;
    }
    case ND_MATRIX_DAMPING:  // alpha M + beta K, zeros on their pattern when off
      if (d.damped()) return d.C;
      return d.K.zeros_like();
    default:
      fail(ND_ERR_KEY, "which " + std::to_string(which) + " is not an ND_MATRIX_* value");
  }
}

void exported_dof_map(Problem &p, int64_t *node, int *component) {
  const Discretization &d = p.discretization();
  const int dim = p.space().dim;
  for (int64_t dof = 0, m = static_cast<int64_t>(d.dofs.free.size()); dof < m; ++dof) {
    const int64_t r = d.dofs.free[dof];
    if (r < 0) continue;
    if (node) node[r] = dof / dim;
    if (component) component[r] = static_cast<int>(dof % dim);
  }
}

std::vector<double> exported_load(Problem &p) {
  const Discretization &d = p.discretization();
  const std::vector<double> &F = p.current_state().load();
  if (F.empty()) return std::vector<double>(static_cast<size_t>(d.dofs.n_free), 0.0);
  return F;
}

bool is_momentum_key(int key) { return key >= ND_MOMENTUM_X && key <= ND_ANGULAR_MOMENTUM_Z; }

double momentum(Problem &p, int key) {
  const Discretization &d = whole_operators(p, "the momentum");
  const State &s = p.current_state();
  const Space &sp = p.space();
  const int dim = sp.dim;
  // M V on every DOF of the space: the free rows, and the clamped rows of a
  // coupled (non-diagonal) mass
  std::vector<double> MV(static_cast<size_t>(d.dofs.n_free), 0.0), full(static_cast<size_t>(sp.n_dofs()), 0.0);
  d.M.multiply(s.V.data(), MV.data());
  // prescribed motion: the clamped DOFs' velocity V_c, in M's clamped columns
  const bool moving = d.clamped && !s.Vc.empty();
  const ClampedMean at_Vc{moving ? std::vector<double>(s.Vc.size(), 0.0) : std::vector<double>(), s.Vc, {}};
  if (moving) subtract_clamped_coupling(d, at_Vc, -1.0, MV.data());  // + M_fc V_c
  d.dofs.extend_to_full(MV.data(), full.data());
  if (d.clamped && (!d.lumped || moving)) {
    std::vector<double> MVc(d.clamped->dofs.size(), 0.0);
    if (!d.lumped) d.clamped->M.multiply(s.V.data(), MVc.data());
    if (moving) add_clamped_block(d, at_Vc, MVc);  // + M_cc V_c
    for (size_t r = 0; r < MVc.size(); ++r) full[d.clamped->dofs[r]] = MVc[r];
  }
  double L[3] = {0, 0, 0}, H[3] = {0, 0, 0};
  for (int64_t node = 0; node < sp.n_nodes; ++node) {
    double x[3] = {0, 0, 0}, m[3] = {0, 0, 0};
    std::copy_n(sp.node_x(node), dim, x);
    std::copy_n(&full[node * dim], dim, m);
    for (int a = 0; a < 3; ++a) L[a] += m[a];
    H[0] += x[1] * m[2] - x[2] * m[1];
    H[1] += x[2] * m[0] - x[0] * m[2];
    H[2] += x[0] * m[1] - x[1] * m[0];
  }
  return key <= ND_MOMENTUM_Z ? L[key - ND_MOMENTUM_X] : H[key - ND_ANGULAR_MOMENTUM_X];
}

}  // namespace nd
