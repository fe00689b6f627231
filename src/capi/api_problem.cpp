// nd_problem_*: definition of a problem, checked argument by argument.
#include <cmath>
#include <string>

#include "capi/guard.hpp"
#include "capi/handles.hpp"
#include "contact/obstacle.hpp"
#include "linalg/factorization.hpp"

namespace {

void need_node_array(nd::Problem &pr, int64_t n, const char *name) {
  if (n != pr.space().n_nodes)
    nd::fail(ND_ERR_SIZE, std::string(name) + " has " + std::to_string(n) + " nodes; the problem has " +
                              std::to_string(pr.space().n_nodes));
}

void need_range(bool ok, int code, const std::string &what) {
  if (!ok) nd::fail(code, what);
}

nd::Material checked_material(const nd::Problem &pr, double young, double poisson, double density) {
  need_range(std::isfinite(young) && young > 0, ND_ERR_MATERIAL, "young must be positive and finite");
  need_range(std::isfinite(density) && density > 0, ND_ERR_MATERIAL, "density must be positive and finite");
  if (pr.space().dim > 1)  // in 1D sigma = E u_x: Poisson's ratio is not used
    need_range(std::isfinite(poisson) && poisson > -1 && poisson < 0.5, ND_ERR_MATERIAL,
               "poisson must lie in (-1, 1/2)");
  return nd::Material{young, poisson, density};
}

}  // namespace

extern "C" {

ND_EXPORT int nd_problem_create(nd_mesh m, int degree, nd_problem *out) {
  return nd::guarded("nd_problem_create", [&] {
    nd::need(out, "out");
    *out = nullptr;
    nd::need(m, "mesh");
    need_range(degree == 1 || degree == 2, ND_ERR_DEGREE, "degree is " + std::to_string(degree) + ", not 1 or 2");
    auto mesh = std::make_shared<const nd::Mesh>(m->mesh);  // the problem keeps its own copy
    *out = new nd_problem_s{nd::Problem(mesh, degree)};
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_material(nd_problem p, double young, double poisson, double density) {
  return nd::guarded("nd_problem_set_material", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.set_material(checked_material(pr, young, poisson, density));
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_material_region(nd_problem p, int cell_region, double young, double poisson,
                                             double density) {
  return nd::guarded("nd_problem_set_material_region", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_range(cell_region >= 1, ND_ERR_REGION,
               "cell_region is " + std::to_string(cell_region) + "; cell regions with a material are >= 1 "
               "(region 0, the cells in none, takes nd_problem_set_material's)");
    pr.set_material_region(cell_region, checked_material(pr, young, poisson, density));
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_dirichlet(nd_problem p, int region) {
  return nd::guarded("nd_problem_set_dirichlet", [&] {
    nd::problem_of(p).add_dirichlet(region);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_dirichlet_value(nd_problem p, int region, const double *u) {
  return nd::guarded("nd_problem_set_dirichlet_value", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(u, "u");
    nd::need_finite(u, pr.space().dim, "u");
    pr.set_dirichlet_value(region, u);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_dirichlet_nodal(nd_problem p, int64_t n, const double *u) {
  return nd::guarded("nd_problem_set_dirichlet_nodal", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_node_array(pr, n, "u");
    nd::need(u, "u");
    nd::need_finite(u, n * pr.space().dim, "u");
    pr.set_dirichlet_nodal(u);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_body_force(nd_problem p, const double *f) {
  return nd::guarded("nd_problem_set_body_force", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(f, "f");
    nd::need_finite(f, pr.space().dim, "f");
    pr.set_body_force(f);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_neumann(nd_problem p, int region, const double *g) {
  return nd::guarded("nd_problem_set_neumann", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(g, "g");
    nd::need_finite(g, pr.space().dim, "g");
    pr.add_neumann(region, g);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_contact_plane(nd_problem p, int region, const double *point,
                                           const double *normal) {
  return nd::guarded("nd_problem_set_contact_plane", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(point, "point");
    nd::need(normal, "normal");
    nd::need_finite(point, pr.space().dim, "point");
    nd::need_finite(normal, pr.space().dim, "normal");
    pr.set_contact_plane(region, point, normal);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_contact_pair(nd_problem p, int slave, int master) {
  return nd::guarded("nd_problem_set_contact_pair", [&] {
    nd::problem_of(p).set_contact_pair(slave, master);
    return ND_OK;
  });
}

namespace {
void need_inside(int inside) {
  need_range(inside == 0 || inside == 1, ND_ERR_VALUE,
             "inside is " + std::to_string(inside) + "; it must be 0 (the body outside) or 1 (inside the shell)");
}
}  // namespace

ND_EXPORT int nd_problem_add_contact_sphere(nd_problem p, int region, const double *center, double radius,
                                            int inside) {
  return nd::guarded("nd_problem_add_contact_sphere", [&] {
    nd::Problem &pr = nd::problem_of(p);
    const int d = pr.space().dim;
    nd::need(center, "center");
    nd::need_finite(center, d, "center");
    nd::need_finite(&radius, 1, "radius");
    need_inside(inside);
    pr.add_obstacle(region, nd::make_sphere(center, radius, inside == 1, d));
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_add_contact_cylinder(nd_problem p, int region, const double *point, const double *axis,
                                              double radius, int inside) {
  return nd::guarded("nd_problem_add_contact_cylinder", [&] {
    nd::Problem &pr = nd::problem_of(p);
    const int d = pr.space().dim;
    nd::need(point, "point");
    nd::need(axis, "axis");
    nd::need_finite(point, d, "point");
    nd::need_finite(axis, d, "axis");
    nd::need_finite(&radius, 1, "radius");
    need_inside(inside);
    pr.add_obstacle(region, nd::make_cylinder(point, axis, radius, inside == 1, d));
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_add_contact_distance(nd_problem p, int region, nd_distance_fn f, void *user) {
  return nd::guarded("nd_problem_add_contact_distance", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(reinterpret_cast<const void *>(f), "f");
    if (pr.space().dim < 2)
      nd::fail(ND_ERR_DIMENSION, "a distance callback needs a 2D or 3D mesh; in 1D the obstacle is a plane "
                                 "(nd_problem_set_contact_plane)");
    pr.add_obstacle(region, nd::make_distance(f, user, pr.space().dim));
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_move_obstacle(nd_problem p, int region, int index, const double *translation,
                                       const double *rotation) {
  return nd::guarded("nd_problem_move_obstacle", [&] {
    nd::Problem &pr = nd::problem_of(p);
    const int d = pr.space().dim;
    nd::need(translation, "translation");
    nd::need_finite(translation, d, "translation");
    if (rotation) nd::need_finite(rotation, d * d, "rotation");
    pr.move_obstacle(region, index, translation, rotation);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_nitsche(nd_problem p, double theta, double gamma0) {
  return nd::guarded("nd_problem_set_nitsche", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_range(std::isfinite(theta), ND_ERR_NITSCHE, "theta must be finite");
    need_range(std::isfinite(gamma0) && gamma0 >= 0, ND_ERR_NITSCHE,
               "gamma0 must be finite and positive, or 0 for an automatic choice");
    pr.set_nitsche(theta, gamma0);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_friction(nd_problem p, int region, int law, const double *params) {
  return nd::guarded("nd_problem_set_friction", [&] {
    nd::problem_of(p).set_friction(region, law, params);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_scheme(nd_problem p, int scheme, const double *params) {
  return nd::guarded("nd_problem_set_scheme", [&] {
    nd::Problem &pr = nd::problem_of(p);
    const int n = nd::scheme_parameter_count(scheme);  // ND_ERR_SCHEME if unknown
    std::vector<double> prm;
    if (n > 0) {
      nd::need(params, "params");
      prm.assign(params, params + n);
    }
    pr.set_scheme(scheme, prm);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_nodal_forces(nd_problem p, int64_t n, const double *f) {
  return nd::guarded("nd_problem_set_nodal_forces", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_node_array(pr, n, "f");
    nd::need(f, "f");
    nd::need_finite(f, n * pr.space().dim, "f");
    pr.set_nodal_forces(f);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_newton(nd_problem p, double rtol, double atol, int max_iter) {
  return nd::guarded("nd_problem_set_newton", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_range(std::isfinite(rtol) && rtol >= 0, ND_ERR_VALUE, "rtol must be finite and >= 0");
    need_range(std::isfinite(atol) && atol >= 0, ND_ERR_VALUE, "atol must be finite and >= 0");
    need_range(max_iter >= 1, ND_ERR_VALUE, "max_iter must be at least 1");
    pr.set_newton(nd::NewtonOptions{rtol, atol, max_iter});
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_mass_lumping(nd_problem p, int lumped) {
  return nd::guarded("nd_problem_set_mass_lumping", [&] {
    nd::problem_of(p).set_mass_lumping(lumped != 0);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_damping(nd_problem p, double alpha, double beta) {
  return nd::guarded("nd_problem_set_damping", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_range(std::isfinite(alpha) && alpha >= 0, ND_ERR_VALUE, "alpha must be >= 0 and finite");
    need_range(std::isfinite(beta) && beta >= 0, ND_ERR_VALUE, "beta must be >= 0 and finite");
    pr.set_damping(alpha, beta);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_plane_stress(nd_problem p, int on) {
  return nd::guarded("nd_problem_set_plane_stress", [&] {
    nd::problem_of(p).set_plane_stress(on != 0);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_mass_redistribution(nd_problem p, int on) {
  return nd::guarded("nd_problem_set_mass_redistribution", [&] {
    nd::problem_of(p).set_mass_redistribution(on != 0);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_linear_solver(nd_problem p, int solver) {
  return nd::guarded("nd_problem_set_linear_solver", [&] {
    nd::Problem &pr = nd::problem_of(p);
    if (const char *why = nd::linear_solver_unavailable(solver)) nd::fail(ND_ERR_KEY, std::string("solver ") + why);
    nd::need_member(nd::linear_solver_known(solver), ND_ERR_KEY, "solver", solver, "ND_SOLVER_*");
    pr.set_linear_solver(solver);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_comm_f(nd_problem p, int fortran_comm) {
  return nd::guarded("nd_problem_set_comm_f", [&] {
    nd::Problem &pr = nd::problem_of(p);
    pr.set_communicator(nd::communicator_from_fortran(fortran_comm));
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_distributed_state(nd_problem p, int on) {
  return nd::guarded("nd_problem_set_distributed_state", [&] {
    nd::problem_of(p).set_distributed_state(on != 0);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_timestep(nd_problem p, double tau) {
  return nd::guarded("nd_problem_set_timestep", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_range(std::isfinite(tau) && tau > 0, ND_ERR_TIMESTEP, "tau must be positive and finite");
    pr.set_timestep(tau);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_adaptive_timestep(nd_problem p, double tolerance, double tau_min, double tau_max) {
  return nd::guarded("nd_problem_set_adaptive_timestep", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_range(std::isfinite(tolerance) && std::isfinite(tau_min) && std::isfinite(tau_max), ND_ERR_NONFINITE,
               "tolerance, tau_min and tau_max must be finite");
    need_range(tolerance >= 0, ND_ERR_VALUE, "the tolerance must be positive (0: fixed steps)");
    if (tolerance > 0) {
      need_range(tau_min > 0, ND_ERR_TIMESTEP, "tau_min must be positive");
      need_range(tau_max >= tau_min, ND_ERR_TIMESTEP, "tau_max must be at least tau_min");
    }
    pr.set_adaptive_timestep(tolerance, tau_min, tau_max);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_initial_state(nd_problem p, int64_t n, const double *u0, const double *v0) {
  return nd::guarded("nd_problem_set_initial_state", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_node_array(pr, n, "u0/v0");
    if (u0) nd::need_finite(u0, n * pr.space().dim, "u0");
    if (v0) nd::need_finite(v0, n * pr.space().dim, "v0");
    pr.set_initial_state(u0, v0);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_guard(nd_problem p, int guard, double value) {
  return nd::guarded("nd_problem_set_guard", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_member(ND_IS_MEMBER_(ND_GUARD_LIST, guard), ND_ERR_KEY, "guard", guard, "ND_GUARD_*");
    pr.set_guard(guard, value);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_set_monitor(nd_problem p, nd_monitor_fn fn, void *userdata) {
  return nd::guarded("nd_problem_set_monitor", [&] {
    nd::problem_of(p);
    p->monitor = fn;
    p->userdata = userdata;
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_node_count(nd_problem p, int64_t *n_nodes) {
  return nd::guarded("nd_problem_get_node_count", [&] {
    nd::need(n_nodes, "n_nodes");
    *n_nodes = nd::problem_of(p).space().n_nodes;
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_node_coordinates(nd_problem p, int64_t n, double *coords) {
  return nd::guarded("nd_problem_get_node_coordinates", [&] {
    nd::Problem &pr = nd::problem_of(p);
    need_node_array(pr, n, "coords");
    nd::need(coords, "coords");
    const nd::Space &s = pr.space();
    for (int64_t node = 0; node < s.n_nodes; ++node) std::copy_n(s.node_x(node), s.dim, coords + node * s.dim);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_destroy(nd_problem *p) {
  return nd::guarded("nd_problem_destroy", [&] {
    if (p) {
      delete *p;
      *p = nullptr;
    }
    return ND_OK;
  });
}

}  // extern "C"
