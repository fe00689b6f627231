#include "problem/discretization.hpp"

#include "assembly/bulk.hpp"
#include "assembly/nitsche.hpp"
#include "solve/contact_law.hpp"

namespace nd {

std::unique_ptr<Discretization> discretize(const Space &space, const Definition &def) {
  require_complete(def.missing_for_operators());
  auto d = std::make_unique<Discretization>(DofMap(space, def.dirichlet), def.lumped);
  BulkOperators bulk = assemble_bulk(space, d->dofs, def.material);
  d->K = std::move(bulk.K);
  if (def.lumped) {
    d->M = d->K.zeros_like();
    for (int64_t i = 0; i < d->M.n; ++i) d->M.val[d->M.find(i, i)] = bulk.M_lumped[i];
    d->M_lumped = std::move(bulk.M_lumped);
  } else {
    d->M = std::move(bulk.M);
  }
  d->contact = assemble_contact(space, d->dofs, def.material, def.planes, def.gamma0);
  d->theta = def.theta;
  d->K_theta = assemble_k_theta(d->K, d->contact, def.theta);
  return d;
}

std::vector<double> constant_load(const Space &space, const Discretization &d, const Definition &def) {
  return assemble_load(space, d.dofs, def.has_body_force ? def.body_force : nullptr, def.neumann);
}

void Discretization::mass_solve(double *x, int solver) {
  if (lumped) {  // explicit steps with lumped mass: no solve at all
    for (size_t i = 0; i < M_lumped.size(); ++i) x[i] /= M_lumped[i];
    return;
  }
  if (!M_factor) {
    auto f = make_factorization(solver, M, Structure::SymmetricPositiveDefinite);
    f->factor(M, Structure::SymmetricPositiveDefinite);
    M_factor = std::move(f);  // kept only once factored: a failure leaves nothing half-built
  }
  M_factor->solve(x);
}

void Discretization::equilibrium_acceleration(State &s, int solver) {
  const size_t n = s.U.size();
  std::vector<double> rhs(n);
  K_theta.multiply(s.U.data(), rhs.data());
  ContactLaw law{&contact, theta};
  law.add_force(s.U.data(), 1.0, rhs.data(), nullptr);
  for (size_t i = 0; i < n; ++i) rhs[i] = (s.F.empty() ? 0.0 : s.F[i]) - rhs[i];
  mass_solve(rhs.data(), solver);
  s.A = std::move(rhs);
  s.A_valid = true;
}

}  // namespace nd
