#include "problem/problem.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {

namespace {
bool all_finite(const std::vector<double> &v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}
}  // namespace

void Operators::mass_solve(double *x, int solver) {
  if (lumped) {  // explicit steps with lumped mass: no solve at all
    for (size_t i = 0; i < M_lumped.size(); ++i) x[i] /= M_lumped[i];
    return;
  }
  if (!M_factor) {
    M_factor = make_factorization(solver, M, Structure::SymmetricPositiveDefinite);
    M_factor->factor(M, Structure::SymmetricPositiveDefinite);
  }
  M_factor->solve(x);
}

Problem::Problem(std::shared_ptr<const Mesh> mesh, int degree)
    : mesh_(std::move(mesh)), space_(mesh_, degree) {}

// ---- definition -------------------------------------------------------------

// Before the first step the state at t^0 (its load F^0 and acceleration A^0)
// is derived from the definition, so it is derived again after any change.
// Later, the state is the history and stays; a changed load enters as F^{n+1}.
void Problem::definition_changed(bool operators) {
  if (operators) {
    ops_.reset();
    step_op_.reset();
  }
  if (state_ready_ && state_.n == 0) state_ready_ = false;
}

void Problem::require_regions(int region, const char *what) const {
  auto it = mesh_->regions.find(region);
  if (it == mesh_->regions.end() || it->second.empty())
    fail(ND_ERR_REGION, std::string("region ") + std::to_string(region) + " (" + what +
                            ") has no facets in the mesh the problem was created from");
}

void Problem::set_material(const Material &m) {
  material_ = m;
  has_material_ = true;
  definition_changed(true);
}

void Problem::add_dirichlet(int region) {
  require_regions(region, "Dirichlet");
  if (state_ready_ && state_.n > 0)
    fail(ND_ERR_STATE, "the clamped boundary cannot change once stepping has started; "
                       "call nd_problem_set_initial_state first");
  dirichlet_.push_back(region);
  definition_changed(true);
}

void Problem::set_body_force(const double *f) {
  for (int k = 0; k < space_.dim; ++k) body_force_[k] = f[k];
  has_body_force_ = true;
  definition_changed(true);
}

void Problem::add_neumann(int region, const double *g) {
  require_regions(region, "Neumann");
  NeumannLoad nl{region, {0, 0, 0}};
  for (int k = 0; k < space_.dim; ++k) nl.g[k] = g[k];
  neumann_.push_back(nl);
  definition_changed(true);
}

void Problem::add_contact_plane(int region, const double *point, const double *normal) {
  require_regions(region, "contact");
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
  planes_.push_back(pl);
  definition_changed(true);
}

void Problem::set_nitsche(double theta, double gamma0) {
  theta_ = theta;
  gamma0_ = gamma0;
  has_nitsche_ = true;
  definition_changed(true);
}

void Problem::set_scheme(const SchemeSpec &s) {
  scheme_ = s;
  has_scheme_ = true;
  step_op_.reset();
}

void Problem::set_nodal_forces(const double *f) {
  nodal_.assign(f, f + space_.n_dofs());
  definition_changed(false);
}

void Problem::set_mass_lumping(bool lumped) {
  lumped_ = lumped;
  definition_changed(true);
}

void Problem::set_linear_solver(int solver) {
  solver_ = solver;
  if (ops_) ops_->M_factor.reset();
  step_op_.reset();
}

void Problem::set_timestep(double tau) {
  tau_ = tau;
  has_tau_ = true;
  step_op_.reset();
}

void Problem::set_initial_state(const double *u0, const double *v0) {
  const int64_t n = space_.n_dofs();
  u0_.assign(n, 0.0);
  v0_.assign(n, 0.0);
  if (u0) u0_.assign(u0, u0 + n);
  if (v0) v0_.assign(v0, v0 + n);
  state_ready_ = false;
}

// ---- derived operators --------------------------------------------------------

std::string Problem::missing() const {
  std::string m;
  auto add = [&](const char *what) { m += (m.empty() ? "" : ", ") + std::string(what); };
  if (!has_material_) add("the material (nd_problem_set_material)");
  if (!planes_.empty() && !has_nitsche_) add("the Nitsche parameters of the contact (nd_problem_set_nitsche)");
  return m;
}

Operators &Problem::build_operators() {
  if (ops_) return *ops_;
  const std::string m = missing();
  if (!m.empty()) fail(ND_ERR_INCOMPLETE, "the problem is incomplete: missing " + m);
  auto ops = std::make_unique<Operators>(DofMap(space_, dirichlet_), lumped_);
  BulkOperators bulk = assemble_bulk(space_, ops->dofs, material_);
  ops->K = std::move(bulk.K);
  if (lumped_) {
    ops->M = ops->K.zeros_like();
    for (int64_t i = 0; i < ops->M.n; ++i) ops->M.val[ops->M.find(i, i)] = bulk.M_lumped[i];
    ops->M_lumped = std::move(bulk.M_lumped);
  } else {
    ops->M = std::move(bulk.M);
  }
  ops->F_const = assemble_load(space_, ops->dofs, has_body_force_ ? body_force_ : nullptr, neumann_);
  ops->contact = assemble_contact(space_, ops->dofs, material_, planes_, gamma0_);
  ops->K_theta = ops->K;
  const ContactPoints &cp = ops->contact;
  if (theta_ != 0)  // Theta = 0 drops the s_q^T s_q term entirely
    for (size_t q = 0; q < cp.size(); ++q) {
      const SparseRow &s = cp.s[q];
      const double f = theta_ * cp.w[q] * cp.gamma[q];
      for (size_t i = 0; i < s.idx.size(); ++i)
        for (size_t j = 0; j < s.idx.size(); ++j)
          ops->K_theta.val[ops->K_theta.find(s.idx[i], s.idx[j])] -= f * s.val[i] * s.val[j];
    }
  ops_ = std::move(ops);
  return *ops_;
}

StepOperator &Problem::build_step_operator() {
  if (step_op_) return *step_op_;
  std::string m;
  if (!has_scheme_) m += "the time scheme (nd_problem_set_scheme)";
  if (!has_tau_) m += std::string(m.empty() ? "" : ", ") + "the time step (nd_problem_set_timestep)";
  if (!m.empty()) fail(ND_ERR_INCOMPLETE, "the problem is incomplete: missing " + m);
  Operators &ops = build_operators();
  auto so = std::make_unique<StepOperator>();
  if (!scheme_.is_explicit()) {
    so->coef = step_coefficients(scheme_, tau_);
    csr_combine(so->coef.c, ops.M, 1.0, ops.K_theta, so->A);
    so->A_factor = make_factorization(solver_, so->A, Structure::SymmetricPositiveDefinite);
    try {
      so->A_factor->factor(so->A, Structure::SymmetricPositiveDefinite);
    } catch (const Error &e) {
      if (e.code() != ND_ERR_INDEFINITE) throw;
      fail(ND_ERR_INDEFINITE, "c*M + K_Theta is not positive definite (" + std::string(e.what()) +
                                  "): with Theta = " + std::to_string(theta_) + " the step is not "
                                  "well posed; lower gamma0 or the time step (DESIGN §3, Props 3.4-3.6)");
    }
    if (!ops.contact.a.empty()) {
      so->T = so->A;
      so->T_factor = make_factorization(solver_, so->A, tangent_structure());
    }
  }
  step_op_ = std::move(so);
  return *step_op_;
}

std::vector<double> Problem::current_load() {
  Operators &ops = build_operators();
  if (nodal_.empty()) return ops.F_const;
  std::vector<double> F(static_cast<size_t>(ops.dofs.n_free), 0.0);
  ops.dofs.restrict_to_free(nodal_.data(), F.data());
  for (size_t i = 0; i < ops.F_const.size(); ++i) F[i] += ops.F_const[i];
  return F;
}

// M A = F - K_Theta U - N(U)  (Remark 3.2, and every explicit step)
void Problem::equilibrium_acceleration(State &s) {
  Operators &ops = build_operators();
  const size_t n = s.U.size();
  std::vector<double> rhs(n);
  ops.K_theta.multiply(s.U.data(), rhs.data());
  ContactLaw law{&ops.contact, theta_, nullptr};
  law.add_force(s.U.data(), 1.0, rhs.data(), nullptr);
  for (size_t i = 0; i < n; ++i) rhs[i] = (s.F.empty() ? 0.0 : s.F[i]) - rhs[i];
  ops.mass_solve(rhs.data(), solver_);
  s.A = std::move(rhs);
  s.A_valid = true;
}

const State &Problem::state() {
  if (!state_ready_) {
    Operators &ops = build_operators();
    const int64_t n = ops.dofs.n_free;
    State s;
    s.U.assign(n, 0.0);
    s.V.assign(n, 0.0);
    s.A.assign(n, 0.0);
    if (!u0_.empty()) ops.dofs.restrict_to_free(u0_.data(), s.U.data());
    if (!v0_.empty()) ops.dofs.restrict_to_free(v0_.data(), s.V.data());
    s.F = current_load();
    state_ = std::move(s);
    state_ready_ = true;
  }
  return state_;
}

// ---- stepping --------------------------------------------------------------------

void Problem::setup() {
  build_operators();
  build_step_operator();
  state();
  if (!scheme_.is_hybrid() && !state_.A_valid) equilibrium_acceleration(state_);
}

void Problem::step() {
  setup();
  Operators &ops = build_operators();  // built by setup(): these only fetch them
  StepOperator &so = build_step_operator();
  const State &old = state_;
  State next;
  next.t = old.t + tau_;
  next.n = old.n + 1;
  const size_t n = old.U.size();
  std::vector<double> F_new = current_load();
  if (F_new.empty() && !old.F.empty()) F_new.assign(n, 0.0);  // nodal forces withdrawn
  // an empty load vector means no load; both ends of the step need one if either has
  const std::vector<double> F_old = !F_new.empty() && old.F.empty() ? std::vector<double>(n, 0.0) : old.F;
  next.F = F_new;
  predict_displacement(scheme_, tau_, old, next.U);
  if (scheme_.is_explicit()) {
    next.last_iterations = 0;
    equilibrium_acceleration(next);
    explicit_update(scheme_, tau_, old, next);
  } else {
    std::vector<double> r, KtU;
    if (scheme_.is_hybrid()) {
      KtU.resize(n);
      ops.K_theta.multiply(old.U.data(), KtU.data());
    }
    implicit_rhs(scheme_, tau_, ops.M, old, F_old, F_new, KtU, r);
    if (ops.contact.a.empty()) {  // no contact: one solve with the cached factor
      next.U = r;
      so.A_factor->solve(next.U.data());
      next.last_iterations = 1;
    } else {
      std::vector<double> Pn;
      ContactLaw law{&ops.contact, theta_, nullptr};
      if (scheme_.is_hybrid()) {
        Pn.resize(ops.contact.size());
        for (size_t q = 0; q < Pn.size(); ++q) Pn[q] = law.P(q, old.U.data());
        law.Pn = &Pn;
      }
      NewtonSystem sys{&so.A, so.A_factor.get(), so.T_factor.get(), &so.T,
                       tangent_structure(),
                       &ops.M, so.coef.c, so.coef.kappa, &law};
      const NewtonResult res = newton_solve(sys, r, newton_, next.U);
      if (!res.converged)
        fail(ND_ERR_NEWTON, "Newton did not converge in " + std::to_string(res.iterations) +
                                " iterations at t = " + std::to_string(next.t) + " (residual " +
                                std::to_string(res.residual) + ", tolerance " +
                                std::to_string(res.tolerance) + "); the step was not taken");
      next.last_iterations = res.iterations;
    }
    implicit_update(scheme_, tau_, old, next);
  }
  if (!all_finite(next.U) || !all_finite(next.V) || !all_finite(next.A))
    fail(ND_ERR_NONFINITE_STATE, "the step to t = " + std::to_string(next.t) +
                                     " produced non-finite values; the step was not taken");
  next.W = old.W;
  if (!F_new.empty())  // trapezoidal work of the loads
    for (size_t i = 0; i < n; ++i) next.W += 0.5 * (F_new[i] + F_old[i]) * (next.U[i] - old.U[i]);
  next.total_iterations = old.total_iterations + next.last_iterations;
  state_ = std::move(next);
}

// ---- monitors ----------------------------------------------------------------------

void Problem::field(int which, double *full) {
  const State &s = state();
  if (which == ND_FIELD_ACCELERATION && !s.A_valid) equilibrium_acceleration(state_);
  const std::vector<double> &v = which == ND_FIELD_DISPLACEMENT ? s.U : which == ND_FIELD_VELOCITY ? s.V : s.A;
  build_operators().dofs.extend_to_full(v.data(), full);
}

std::vector<double> Problem::contact_pressure() {
  const State &s = state();
  Operators &ops = build_operators();
  ContactLaw law{&ops.contact, theta_, nullptr};
  std::vector<double> lam(ops.contact.size());
  for (size_t q = 0; q < lam.size(); ++q) {
    const double P = law.P(q, s.U.data());
    lam[q] = P > 0 ? -P / ops.contact.gamma[q] : 0.0;
  }
  return lam;
}

bool is_scalar_key(int key) {
#define ND_KEY_CASE_(name, value, text) \
  case name:                            \
    return true;
  switch (key) { ND_SCALAR_LIST(ND_KEY_CASE_) }
#undef ND_KEY_CASE_
  return false;
}

double Problem::scalar(int key) {
  if (!is_scalar_key(key)) fail(ND_ERR_KEY, "key " + std::to_string(key) + " is not an ND_* scalar key");
  switch (key) {
    case ND_TIME:
      return state().t;
    case ND_STEP_INDEX:
      return static_cast<double>(state().n);
    case ND_NEWTON_ITERATIONS:
      return state().last_iterations;
    case ND_NEWTON_ITERATIONS_TOTAL:
      return static_cast<double>(state().total_iterations);
    case ND_WORK:
      return state().W;
    case ND_TIMESTEP:
      return tau_;
    default:
      break;
  }
  const State &s = state();
  Operators &ops = build_operators();
  const int64_t n = static_cast<int64_t>(s.U.size());
  const ContactPoints &cp = ops.contact;
  ContactLaw law{&cp, theta_, nullptr};
  if (key == ND_ENERGY_MECHANICAL || key == ND_ENERGY_AUGMENTED) {
    std::vector<double> y(n);
    ops.M.multiply(s.V.data(), y.data());
    double E = 0.5 * dot(n, s.V.data(), y.data());
    ops.K.multiply(s.U.data(), y.data());
    E += 0.5 * dot(n, s.U.data(), y.data());
    if (key == ND_ENERGY_MECHANICAL) return E;
    return E - theta_ * scalar(ND_ENERGY_NITSCHE);
  }
  double acc = 0;
  for (size_t q = 0; q < cp.size(); ++q) {
    const double P = law.P(q, s.U.data()), Pp = P > 0 ? P : 0;
    switch (key) {
      case ND_ENERGY_NITSCHE: {
        const double sn = cp.s[q].dot(s.U.data());
        acc += 0.5 * cp.w[q] * (cp.gamma[q] * sn * sn - Pp * Pp / cp.gamma[q]);
        break;
      }
      case ND_CONTACT_FORCE:
        acc += cp.w[q] * Pp / cp.gamma[q];
        break;
      case ND_ACTIVE_POINTS:
        acc += P > 0 ? 1 : 0;
        break;
      default:  // ND_MAX_PENETRATION
        acc = std::max(acc, cp.a[q].dot(s.U.data()) - cp.gap[q]);
        break;
    }
  }
  return acc;
}

}  // namespace nd
