// pair_search - what the pairing of two bodies costs in a contact step
// (docs/performance.md, "Two bodies"): the upper ball of
// examples/meshes/two_balls_hH.msh (P1, hybrid, Theta = 1, automatic gamma0,
// tau = 0.05, gravity 0.1) falls onto the lower one, clamped on its lower
// hemisphere. Each step is timed through the public API; a contact step is
// one that starts or ends with an active point. At the last contact state
// the pairing's work of a step is timed alone, white-box: the master
// surface built where U places it and every slave point projected on it
// (contact/pairing.hpp), as a step's start does. Prints the mean contact
// step, the pairing's time and its share, the steps that paired anew, and
// the mean contact step of the upper ball dropped on the plane z = 0 instead
// (the same mesh and unknowns).
//
//   pair_search MESH_DIR [h=4] [T=12]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "contact/obstacles.hpp"
#include "contact/pairing.hpp"
#include "fem/facet.hpp"
#include "fem/space.hpp"
#include "mesh/mesh.hpp"

#define BENCH_NAME "pair_search"
#include "step_timing.h"

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: pair_search MESH_DIR [h=4] [T=12]\n");
    return 2;
  }
  const std::string h = argc > 2 ? argv[2] : "4";
  const double T = argc > 3 ? std::atof(argv[3]) : 12, tau = 0.05;
  const std::string mesh = std::string(argv[1]) + "/two_balls_h" + h + ".msh";
  const int steps = static_cast<int>(T / tau + 0.5);
  // pair: the upper ball on the lower one; else on the plane z = 0 (the
  // lower ball untouched): the same mesh and unknowns, a rigid obstacle
  auto run = [&](bool pair, double &total, int &contact_steps, double &repairing_steps) {
    nd_mesh m;
    nd_problem p;
    CHECK(nd_mesh_read_gmsh(mesh.c_str(), &m));
    CHECK(nd_problem_create(m, 1, &p));
    CHECK(nd_mesh_destroy(&m));
    const double g[3] = {0, 0, -0.1}, origin[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    CHECK(nd_problem_set_material(p, 50, 0.25, 1));
    CHECK(nd_problem_set_body_force(p, g));
    CHECK(nd_problem_set_dirichlet(p, 4));
    if (pair) CHECK(nd_problem_set_contact_pair(p, 1, 2));
    else CHECK(nd_problem_set_contact_plane(p, 1, origin, up));
    CHECK(nd_problem_set_nitsche(p, 1, 0));
    CHECK(nd_problem_set_scheme(p, ND_SCHEME_HYBRID, nullptr));
    CHECK(nd_problem_set_timestep(p, tau));
    CHECK(nd_problem_setup(p));
    total = 0, repairing_steps = 0, contact_steps = 0;
    for (int k = 0; k < steps; ++k) {
      const double before = scalar(p, ND_ACTIVE_POINTS), repaired = scalar(p, ND_STAT_NORMAL_REFRESHES);
      const double t0 = now();
      CHECK(nd_step(p));
      const double dt = now() - t0;
      if (before > 0 || scalar(p, ND_ACTIVE_POINTS) > 0) total += dt, ++contact_steps;
      if (scalar(p, ND_STAT_NORMAL_REFRESHES) > repaired) ++repairing_steps;
    }
    return p;
  };
  double plane_total = 0, plane_repairing = 0, total = 0, repairing_steps = 0;
  int plane_contact = 0, contact_steps = 0;
  nd_problem plane = run(false, plane_total, plane_contact, plane_repairing);
  CHECK(nd_problem_destroy(&plane));
  nd_problem p = run(true, total, contact_steps, repairing_steps);
  int64_t nodes = 0;
  CHECK(nd_problem_get_node_count(p, &nodes));
  std::vector<double> u(static_cast<size_t>(3 * nodes));
  CHECK(nd_get_field(p, ND_FIELD_DISPLACEMENT, nodes, u.data()));

  // the same discretization, white-box: the slave points where u places them
  auto mesh_ptr = std::make_shared<const nd::Mesh>(nd::read_gmsh(mesh.c_str()));
  const nd::Space sp(mesh_ptr, 1);
  const nd::DofMap dofs(sp, {4});
  std::vector<double> U(static_cast<size_t>(dofs.n_free));
  dofs.restrict_to_free(u.data(), U.data());
  std::vector<double> y;
  std::vector<double> phi(static_cast<size_t>(sp.basis.n));
  for (int64_t b : mesh_ptr->regions.at(1)) {
    const nd::Facet &f = mesh_ptr->boundary[b];
    for (const nd::FacetPoint &fp : nd::facet_quadrature(*mesh_ptr, f, 2)) {
      sp.basis.values(fp.xi, phi.data());
      const int64_t *cell = sp.nodes_of(f.cell);
      for (int c = 0; c < 3; ++c) {
        double at = fp.x[c];
        for (int i = 0; i < sp.basis.n; ++i) at += phi[i] * u[cell[i] * 3 + c];
        y.push_back(at);
      }
    }
  }
  const size_t n = y.size() / 3;
  std::vector<int64_t> hint(n, -1);
  {  // the pairings a step starts from (its hints)
    const nd::MasterSurface s(sp, dofs, 2, U.data());
    for (size_t q = 0; q < n; ++q) hint[q] = s.project(&y[3 * q]).facet;
  }
  const int repeat = 20;
  double searched = 0;
  int64_t found = 0;
  const double t0 = now();
  for (int r = 0; r < repeat; ++r) {
    const nd::MasterSurface s(sp, dofs, 2, U.data());
    const double reach = nd::kPairReach * s.bucket();
    for (size_t q = 0; q < n; ++q) found += s.project(&y[3 * q], reach, hint[q]).facet >= 0;
  }
  searched = (now() - t0) / repeat;
  const double step = contact_steps ? total / contact_steps : 0;
  const double plane_step = plane_contact ? plane_total / plane_contact : 0;
  std::printf("two_balls_h%s: %zu slave points (%lld within reach), %d contact steps of %.3f ms, pairing %.3f ms "
              "(%.1f %% of a contact step); %g of %d steps paired anew; on the plane z = 0: %d contact steps of "
              "%.3f ms (the pair's %.1fx)\n",
              h.c_str(), n, static_cast<long long>(found / repeat), contact_steps, 1e3 * step, 1e3 * searched,
              100 * searched / step, repairing_steps, steps, plane_contact, 1e3 * plane_step,
              plane_step > 0 ? step / plane_step : 0.0);
  CHECK(nd_problem_destroy(&p));
  return 0;
}
