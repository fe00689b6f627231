// nitschedyn(1): runs a scene file (TOML) through libnitschedyn's public C
// API only, and writes the energy/force history (CSV) and a ParaView series.
//   exit 0  success
//   exit 1  the library failed (nd_last_error()), or an output could not be written
//   exit 2  usage error, or the scene file is invalid (file:line:col: key and reason)
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "nitschedyn.h"
#include "scene.hpp"

namespace fs = std::filesystem;
using ndcli::Scene;
using ndcli::SceneError;

namespace {

// The library failed: exit status 1.
struct LibError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void call(int status, const std::string &what) {
  if (status < 0) throw LibError(what + ": " + nd_last_error());
}

// A call that takes values from the scene file: when the library refuses a
// value, the scene is wrong, and the message names where the value is written.
void scene_call(int status, const std::string &at, const std::string &what) {
  if (status >= 0) return;
  switch (status) {
  case ND_ERR_DIMENSION: case ND_ERR_SIZE: case ND_ERR_INDEX: case ND_ERR_NONFINITE: case ND_ERR_DEGREE:
  case ND_ERR_MATERIAL: case ND_ERR_NITSCHE: case ND_ERR_TIMESTEP: case ND_ERR_SCHEME: case ND_ERR_KEY:
  case ND_ERR_REGION: case ND_ERR_VALUE:
    throw SceneError(at + ": " + what + ": " + nd_last_error());
  default:
    throw LibError(what + ": " + nd_last_error());
  }
}

struct Mesh {
  nd_mesh m = nullptr;
  ~Mesh() { nd_mesh_destroy(&m); }
};
struct Problem {
  nd_problem p = nullptr;
  ~Problem() { nd_problem_destroy(&p); }
};

// The cells of m whose centroid lies in [lo, hi] (a degree-1 problem
// numbers its FE nodes as the mesh's vertices).
std::vector<int64_t> cells_in_box(nd_mesh m, int dim, const std::vector<double> &lo, const std::vector<double> &hi) {
  Problem tmp;
  call(nd_problem_create(m, 1, &tmp.p), "nd_problem_create");
  int64_t nc = 0, nn = 0;
  int per = 0;
  call(nd_problem_get_cells(tmp.p, &nc, &per, nullptr), "nd_problem_get_cells");
  call(nd_problem_get_node_count(tmp.p, &nn), "nd_problem_get_node_count");
  std::vector<int64_t> nodes(static_cast<size_t>(nc * per)), in;
  std::vector<double> x(static_cast<size_t>(nn * dim));
  call(nd_problem_get_cells(tmp.p, &nc, &per, nodes.data()), "nd_problem_get_cells");
  call(nd_problem_get_node_coordinates(tmp.p, nn, x.data()), "nd_problem_get_node_coordinates");
  for (int64_t c = 0; c < nc; ++c) {
    bool inside = true;
    for (int k = 0; k < dim; ++k) {
      double centroid = 0;
      for (int i = 0; i < per; ++i) centroid += x[nodes[c * per + i] * dim + k] / per;
      inside = inside && centroid >= lo[k] && centroid <= hi[k];
    }
    if (inside) in.push_back(c);
  }
  return in;
}

double scalar(nd_problem p, int key) {
  double x = 0;
  call(nd_get_scalar(p, key, &x), "nd_get_scalar");
  return x;
}

double region_scalar(nd_problem p, int region, int key) {
  double x = 0;
  call(nd_get_region_scalar(p, region, key, &x), "nd_get_region_scalar");
  return x;
}

struct Setup {
  int dim = 0;
  int64_t nodes = 0;
};

// Each obstacle's index among the obstacles added to its region (-1: a plane,
// moved by its point), for nd_problem_move_obstacle.
std::vector<int> added_indices(const Scene &s) {
  std::vector<int> index(s.obstacles.size(), -1);
  std::map<int, int> added;
  for (size_t i = 0; i < s.obstacles.size(); ++i)
    if (s.obstacles[i].shape != "plane") index[i] = added[ndcli::region_id(s, s.obstacles[i].region)]++;
  return index;
}

// The scene's values in time (tools/cli/time_value.hpp) at t, given to the
// library: every one at t = 0 as the problem is defined (the library's
// first value of each is t^0's), then before each step at t^{n+1} those that
// change (`all` false), as loads are given (nd_problem_set_nodal_forces(3)).
void give_time_values(const Scene &s, nd_problem p, const Setup &set, double t, bool all) {
  const int dim = set.dim;
  if (!s.body_force.empty() && (all || s.body_force.varies()))
    scene_call(nd_problem_set_body_force(p, s.body_force.at(t).data()), s.body_force_at, "loads.body_force");
  for (const auto &tr : s.tractions)
    if (all || tr.value.varies())
      scene_call(nd_problem_set_neumann(p, ndcli::region_id(s, tr.region), tr.value.at(t).data()), tr.at,
                 "loads.traction");
  bool nodal = false;
  for (const auto &l : s.nodal) nodal = nodal || all || l.value.varies();
  if (nodal) {  // every nodal load at once: the call replaces them all
    std::vector<double> f(static_cast<size_t>(set.nodes * dim), 0.0);
    for (const auto &l : s.nodal) {
      if (l.node >= set.nodes)
        throw SceneError(l.at + ": 'loads.nodal.node' is " + std::to_string(l.node) + "; the FE nodes are 0 to " +
                         std::to_string(set.nodes - 1));
      const std::vector<double> v = l.value.at(t);
      for (int k = 0; k < dim; ++k) f[static_cast<size_t>(l.node * dim + k)] += v[k];
    }
    scene_call(nd_problem_set_nodal_forces(p, set.nodes, f.data()), s.nodal.front().at, "loads.nodal");
  }
  for (const auto &m : s.motions)
    if (all || m.value.varies())
      scene_call(nd_problem_set_dirichlet_value(p, ndcli::region_id(s, m.region), m.value.at(t).data()), m.at,
                 "dirichlet.motion");
  const std::vector<int> added = added_indices(s);
  for (size_t i = 0; i < s.obstacles.size(); ++i) {
    const auto &o = s.obstacles[i];
    const bool moves = !o.velocity.empty() || o.position.varies() || o.rotation.varies();
    // (a plane is defined where it is at t = 0; an added obstacle is placed by a pose)
    if (!(all ? !o.position.empty() || !o.rotation.empty() : moves) || (all && o.shape == "plane")) continue;
    std::vector<double> shift(static_cast<size_t>(dim), 0.0);
    for (int k = 0; k < dim; ++k)
      shift[k] = !o.velocity.empty() ? o.velocity[k] * t : o.position.empty() ? 0.0 : o.position.at(t)[k];
    const int region = ndcli::region_id(s, o.region);
    const std::string key = !o.velocity.empty() ? "obstacle.velocity" : "obstacle.position";
    if (o.shape == "plane") {
      for (int k = 0; k < dim; ++k) shift[k] += o.point[k];
      scene_call(nd_problem_set_contact_plane(p, region, shift.data(), o.normal.data()), o.at, key);
      continue;
    }
    std::vector<double> R;  // about the origin (2D), about the z axis (3D)
    if (!o.rotation.empty()) {
      const double a = o.rotation.at(t)[0], c = std::cos(a), sn = std::sin(a);
      R = dim == 2 ? std::vector<double>{c, -sn, sn, c} : std::vector<double>{c, -sn, 0, sn, c, 0, 0, 0, 1};
      if (dim == 1) R = {1};  // (the library refuses the shapes of 1D with its reason)
    }
    scene_call(nd_problem_move_obstacle(p, region, added[i], shift.data(), R.empty() ? nullptr : R.data()), o.at,
               o.rotation.empty() ? key : "obstacle.rotation");
  }
}

// The problem of the scene, defined and set up (assembled, factorized, the
// initial acceleration computed: nd_problem_setup).
Setup build(const Scene &s, Problem &prob) {
  Setup out;
  Mesh mesh;
  if (!s.gmsh.empty()) {
    const int st = nd_mesh_read_gmsh(s.gmsh.c_str(), &mesh.m);
    if (st < 0) throw LibError(s.gmsh_at + ": reading the mesh: " + nd_last_error());
  } else if (s.generate == "interval") {
    scene_call(nd_mesh_create_interval(s.cells[0], s.lo[0], s.hi[0], &mesh.m), s.mesh_at, "[mesh]");
  } else if (s.generate == "rectangle") {
    scene_call(nd_mesh_create_rectangle_cells(s.cells[0], s.cells[1], s.lo.data(), s.hi.data(), s.cell_type, &mesh.m),
               s.mesh_at, "[mesh]");
  } else {
    scene_call(nd_mesh_create_box_cells(s.cells[0], s.cells[1], s.cells[2], s.lo.data(), s.hi.data(), s.cell_type,
                                        &mesh.m),
               s.mesh_at, "[mesh]");
  }
  call(nd_mesh_get_dimension(mesh.m, &out.dim), "nd_mesh_get_dimension");
  ndcli::check_dimension(s, out.dim);
  for (const auto &b : s.boxes)
    scene_call(nd_mesh_mark_boundary_box(mesh.m, b.id, b.lo.data(), b.hi.data()), b.at, "[regions] " + b.name);
  // every region the scene uses has facets
  auto facets = [&](const ndcli::RegionRef &r, const char *use) {
    const int id = ndcli::region_id(s, r);
    int64_t n = 0;
    call(nd_mesh_get_region_size(mesh.m, id, &n), "nd_mesh_get_region_size");
    if (n == 0)
      throw SceneError(r.at + ": region " + (r.name.empty() ? "" : "'" + r.name + "' = ") + std::to_string(id) +
                       " (" + use + ") has no facet in the mesh" +
                       (s.gmsh.empty() ? "" : " (no such Gmsh physical group, and no box of [regions] marks it)"));
    return id;
  };
  for (const auto &o : s.obstacles) facets(o.region, "obstacle.region");
  for (const auto &c : s.pairs) facets(c.slave, "contact_pair.slave"), facets(c.master, "contact_pair.master");
  for (const auto &t : s.tractions) facets(t.region, "loads.traction.region");
  for (const auto &c : s.clamped) facets(c, "dirichlet.regions");

  for (const auto &m : s.region_materials) {  // cells by box: into their region before the problem copies the mesh
    if (m.lo.empty()) continue;
    const std::vector<int64_t> in = cells_in_box(mesh.m, out.dim, m.lo, m.hi);
    if (in.empty()) throw SceneError(m.at + ": [[material]] of region " + std::to_string(m.region) + ": no cell's centroid lies in [lo, hi]");
    scene_call(nd_mesh_set_cell_region(mesh.m, m.region, static_cast<int64_t>(in.size()), in.data()), m.at, "[[material]]");
  }

  call(nd_problem_create(mesh.m, s.degree, &prob.p), "nd_problem_create");
  nd_problem p = prob.p;
  for (const auto &g : s.guards) scene_call(nd_problem_set_guard(p, g.id, g.value), g.at, g.key);
  if (s.plane_stress) scene_call(nd_problem_set_plane_stress(p, 1), s.material_at, "material.plane_stress");
  scene_call(nd_problem_set_material(p, s.young, s.poisson, s.density), s.material_at, "[material]");
  if (s.damping[0] != 0 || s.damping[1] != 0)
    scene_call(nd_problem_set_damping(p, s.damping[0], s.damping[1]), s.damping_at, "material.damping");
  for (const auto &m : s.region_materials)
    scene_call(nd_problem_set_material_region(p, m.region, m.young, m.poisson, m.density), m.at, "[[material]]");
  for (const auto &c : s.clamped) scene_call(nd_problem_set_dirichlet(p, ndcli::region_id(s, c)), c.at, "dirichlet");
  for (const auto &o : s.obstacles) {
    const int region = ndcli::region_id(s, o.region);
    if (o.shape == "sphere")
      scene_call(nd_problem_add_contact_sphere(p, region, o.center.data(), o.radius, o.inside ? 1 : 0), o.at,
                 "[obstacle]");
    else if (o.shape == "cylinder")
      scene_call(nd_problem_add_contact_cylinder(p, region, o.point.data(), o.axis.data(), o.radius, o.inside ? 1 : 0),
                 o.at, "[obstacle]");
    else {  // where it is at t = 0
      std::vector<double> point = o.point;
      const std::vector<double> shift = o.position.empty() ? std::vector<double>() : o.position.at(0);
      for (size_t k = 0; k < shift.size() && k < point.size(); ++k) point[k] += shift[k];
      scene_call(nd_problem_set_contact_plane(p, region, point.data(), o.normal.data()), o.at, "[obstacle]");
    }
    if (!o.friction.at.empty())
      scene_call(nd_problem_set_friction(p, region, o.friction.law, &o.friction.parameter), o.friction.at,
                 "obstacle.friction");
  }
  for (const auto &c : s.pairs) {
    scene_call(nd_problem_set_contact_pair(p, ndcli::region_id(s, c.slave), ndcli::region_id(s, c.master)), c.at,
               "[contact_pair]");
    if (!c.friction.at.empty())
      scene_call(nd_problem_set_friction(p, ndcli::region_id(s, c.slave), c.friction.law, &c.friction.parameter),
                 c.friction.at, "contact_pair.friction");
  }
  scene_call(nd_problem_set_nitsche(p, s.Theta, s.gamma0), s.nitsche_at.empty() ? s.file : s.nitsche_at, "[nitsche]");
  scene_call(nd_problem_set_scheme(p, s.scheme_id, s.params.data()), s.scheme_at.empty() ? s.file : s.scheme_at,
             "[scheme]");
  scene_call(nd_problem_set_timestep(p, s.tau), s.tau_at.empty() ? "--tau" : s.tau_at, "time.tau");
  if (s.tolerance != 0)
    scene_call(nd_problem_set_adaptive_timestep(p, s.tolerance, s.tau_min > 0 ? s.tau_min : 1e-6 * s.tau,
                                                s.tau_max > 0 ? s.tau_max : s.tau),
               s.tolerance_at, "time.tolerance");
  const std::string solver_at = s.solver_at.empty() ? s.file : s.solver_at;
  scene_call(nd_problem_set_linear_solver(p, s.solver_id), solver_at, "solver.linear");
  if (s.newton_given)
    scene_call(nd_problem_set_newton(p, s.newton_rtol, s.newton_atol, (int)s.newton_max_iter), solver_at,
               "solver.newton_*");
  if (s.mass_lumping) scene_call(nd_problem_set_mass_lumping(p, 1), solver_at, "solver.mass_lumping");
  if (s.mass_redistribution)
    scene_call(nd_problem_set_mass_redistribution(p, 1), solver_at, "solver.mass_redistribution");
  call(nd_problem_get_node_count(p, &out.nodes), "nd_problem_get_node_count");
  give_time_values(s, p, out, 0, true);  // loads, motions and poses at t = 0
  if (!s.u0.empty() || !s.v0.empty()) {  // uniform vectors at every node
    std::vector<double> u, v;
    for (int64_t i = 0; i < out.nodes; ++i)
      for (int k = 0; k < out.dim; ++k) {
        if (!s.u0.empty()) u.push_back(s.u0[k]);
        if (!s.v0.empty()) v.push_back(s.v0[k]);
      }
    scene_call(nd_problem_set_initial_state(p, out.nodes, u.empty() ? nullptr : u.data(), v.empty() ? nullptr : v.data()),
               s.u0.empty() ? s.v0_at : s.u0_at, "[initial]");
  }
  call(nd_problem_setup(p), "setting up the problem (nd_problem_setup)");
  return out;
}

// A progress bar on stderr: redrawn in place on a terminal; when forced
// (--progress) on something else, one line every 10 %.
class Progress {
 public:
  Progress(bool on, int64_t steps) : on_(on && steps > 0), tty_(isatty(STDERR_FILENO) != 0), steps_(steps) {}
  void update(int64_t k, double t) {
    if (!on_) return;
    // (100 * k overflows past 2^63 / 100; adaptive steps may take more than T/tau)
    const int percent = (int)std::min(100.0, 100.0 * (double)k / (double)steps_);
    if (tty_) {
      if (percent == last_ && k != steps_) return;
      last_ = percent;
      const int width = 30, full = width * percent / 100;
      std::fprintf(stderr, "\r[%s%s] %3d%%  step %" PRId64 "/%" PRId64 "  t = %-10.5g", std::string(full, '#').c_str(),
                   std::string(width - full, '.').c_str(), percent, k, steps_, t);
    } else {
      if (percent / 10 == last_ / 10 && last_ >= 0) return;
      last_ = percent;
      std::fprintf(stderr, "progress: %3d%%  step %" PRId64 "/%" PRId64 "  t = %g\n", percent, k, steps_, t);
    }
    std::fflush(stderr);
  }
  void finish() {
    if (on_ && tty_) std::fputs("\n", stderr);
    on_ = false;
  }
  ~Progress() { finish(); }

 private:
  bool on_, tty_;
  int64_t steps_;
  int last_ = -1;
};

struct File {
  std::FILE *f = nullptr;
  ~File() {
    if (f) std::fclose(f);
  }
};

void make_parent(const fs::path &p) {
  std::error_code ec;
  if (p.has_parent_path()) fs::create_directories(p.parent_path(), ec);
  if (ec) throw LibError("cannot create the directory " + p.parent_path().string() + ": " + ec.message());
}

struct Options {
  std::string scene, out, restart;
  double T = -1, tau = -1;
  int blas_threads = 1;
  bool quiet = false, progress = false, check = false, list_keys = false;
};

int run(const Options &opt) {
  call(nd_set_blas_threads(opt.blas_threads), "--blas-threads");
  Scene s = ndcli::read_scene(opt.scene);
  if (opt.tau > 0) s.tau = opt.tau, s.tau_given = true, s.tau_at = "--tau";
  if (opt.T >= 0) s.T = opt.T, s.T_given = true, s.T_at = "--T";
  if (!s.tau_given) throw SceneError(s.file + ": no 'time.tau' (required unless --tau is given)");
  if (!s.T_given) throw SceneError(s.file + ": no 'time.T' (required unless --T is given)");
  // (adaptive steps: T/tau for the progress and the frames; the run ends at T)
  const int64_t steps = ndcli::step_count(s);  // refused unless an int64_t holds it
  const bool adaptive = s.tolerance > 0;
  // the steps between ParaView frames (more than the run's: its first and last)
  const double frame_steps = s.interval / s.tau + 0.5;
  const int64_t every = s.interval <= 0 ? 1
                        : frame_steps < (double)steps ? std::max<int64_t>(1, (int64_t)frame_steps)
                                                      : std::max<int64_t>(1, steps);

  const auto t0 = std::chrono::steady_clock::now();
  Problem prob;
  const Setup su = build(s, prob);
  nd_problem p = prob.p;

  if (!opt.quiet) {
    const double gamma0 = scalar(p, ND_GAMMA0), limit = scalar(p, ND_GAMMA0_LIMIT);
    std::printf("%s%s%s: %dD, %c%d, %" PRId64 " nodes (%" PRId64 " unknowns), %s scheme, Theta = %g, gamma0 = %g (%s"
                "coercive up to %g), tau = %g, T = %g: %" PRId64 " steps\n",
                s.file.c_str(), s.title.empty() ? "" : ": ", ndcli::printable(s.title).c_str(), su.dim,
                s.cell_type ? 'Q' : 'P', s.degree,
                su.nodes, su.nodes * su.dim, s.scheme.c_str(), s.Theta, gamma0, s.gamma0 == 0 ? "automatic; " : "",
                limit, s.tau, steps * s.tau, steps);
    std::fflush(stdout);
  }
  if (opt.check) {
    std::printf("%s: the scene is valid and the problem is set up\n", s.file.c_str());
    return 0;
  }

  const fs::path out = opt.out.empty() ? fs::path() : fs::path(opt.out);
  File history;
  fs::path history_path;
  if (!s.history.empty()) {
    history_path = out / s.history;
    make_parent(history_path);
    history.f = std::fopen(history_path.c_str(), "w");
    if (!history.f) throw LibError("cannot write the history " + history_path.string());
    if (!s.title.empty())  // a comment before the header: python3 -m nitschedyn.plot titles the plot with it
      std::fprintf(history.f, "# title: %s\n", ndcli::printable(s.title).c_str());
    std::fputs("step,t,E,E_Theta,W,contact_force,active_points,max_penetration,newton_iterations,contact_force_applied,"
               "W_obstacle,W_prescribed,dissipation_friction,dissipation_damping,W_geometry",
               history.f);
    // each contact pair's own (nd_get_region_scalar on its slave region)
    for (const auto &c : s.pairs) {
      const int r = ndcli::region_id(s, c.slave);
      std::fprintf(history.f, ",pair%d_contact_force,pair%d_active_points,pair%d_dissipation_friction", r, r, r);
    }
    std::fputs("\n", history.f);
  }
  fs::path prefix;
  std::vector<std::string> frames;
  std::vector<double> times;
  if (!s.paraview.empty()) {
    prefix = out / s.paraview;
    make_parent(prefix);
  }

  // a restart continues the run from its step: the outputs hold this part
  int64_t first = 0;
  if (!opt.restart.empty()) {
    call(nd_problem_load_state_file(p, opt.restart.c_str()), "--restart " + opt.restart);
    const double step = scalar(p, ND_STEP_INDEX);
    if (!(step >= 0 && (adaptive || step <= (double)steps))) {
      std::ostringstream os;
      os.precision(17);
      os << "--restart " << opt.restart << ": the checkpoint is at step " << step
         << ", not within the scene's steps 0 to " << steps;
      throw SceneError(os.str());
    }
    first = (int64_t)step;
  }
  const fs::path checkpoint = s.checkpoint.empty() ? fs::path() : out / s.checkpoint;
  if (!checkpoint.empty()) make_parent(checkpoint);
  const size_t frame0 = (size_t)(first / every + (first % every != 0));  // first + every - 1 may overflow
  Progress bar(opt.progress || (!opt.quiet && isatty(STDERR_FILENO)), steps);
  const double E0 = scalar(p, ND_ENERGY_AUGMENTED);
  double max_force = 0, max_pen = 0, newton = 0;
  // the last step: the scene's count, or (adaptive) the first at T (to round-off)
  auto done = [&](int64_t k) { return adaptive ? scalar(p, ND_TIME) >= s.T * (1 - 1e-12) : k == steps; };
  int64_t last = steps;
  for (int64_t k = first;; ++k) {
    if (k > first) {
      // adaptive steps: the last one ends at T (a ladder from T - t down)
      const double now = scalar(p, ND_TIME);
      if (adaptive && now + scalar(p, ND_TIMESTEP) > s.T)
        call(nd_problem_set_adaptive_timestep(p, s.tolerance, std::min(s.tau_min > 0 ? s.tau_min : 1e-6 * s.tau, s.T - now),
                                              s.T - now),
             "the last adaptive step");
      // the values in time where they are at t^{n+1}: loads, motions, obstacles
      give_time_values(s, p, su, now + scalar(p, ND_TIMESTEP), false);
      const int st = nd_step(p);
      if (st < 0) {
        bar.finish();
        throw LibError("step " + std::to_string(k) + " from t = " + std::to_string(scalar(p, ND_TIME)) + ": " +
                       nd_last_error());
      }
      newton += scalar(p, ND_NEWTON_ITERATIONS);
      if (!checkpoint.empty() && (done(k) || (s.checkpoint_every > 0 && k % s.checkpoint_every == 0)))
        call(nd_problem_save_state_file(p, checkpoint.c_str()), "writing the checkpoint " + checkpoint.string());
    }
    const double t = scalar(p, ND_TIME), force = scalar(p, ND_CONTACT_FORCE), pen = scalar(p, ND_MAX_PENETRATION);
    max_force = std::max(max_force, force);
    max_pen = std::max(max_pen, pen);
    if (history.f) {
      std::fprintf(history.f, "%" PRId64 ",%.17g,%.17g,%.17g,%.17g,%.17g,%.0f,%.17g,%.0f,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g",
                   k, t,
                   scalar(p, ND_ENERGY_MECHANICAL), scalar(p, ND_ENERGY_AUGMENTED), scalar(p, ND_WORK), force,
                   scalar(p, ND_ACTIVE_POINTS), pen, k > 0 ? scalar(p, ND_NEWTON_ITERATIONS) : 0.0,
                   scalar(p, ND_CONTACT_FORCE_APPLIED), scalar(p, ND_WORK_OBSTACLE), scalar(p, ND_WORK_PRESCRIBED),
                   scalar(p, ND_DISSIPATION_FRICTION), scalar(p, ND_DISSIPATION_DAMPING), scalar(p, ND_WORK_GEOMETRY));
      for (const auto &c : s.pairs) {
        const int r = ndcli::region_id(s, c.slave);
        std::fprintf(history.f, ",%.17g,%.0f,%.17g", region_scalar(p, r, ND_CONTACT_FORCE),
                     region_scalar(p, r, ND_ACTIVE_POINTS), region_scalar(p, r, ND_DISSIPATION_FRICTION));
      }
      std::fputs("\n", history.f);
      if (std::ferror(history.f)) throw LibError("cannot write the history " + history_path.string());
    }
    if (!prefix.empty() && (k % every == 0 || done(k))) {
      char name[32];
      std::snprintf(name, sizeof name, "_%04zu.vtu", frame0 + frames.size());
      const fs::path vtu = prefix.string() + name;
      call(nd_problem_write_vtu(p, vtu.c_str()), "nd_problem_write_vtu");
      frames.push_back(vtu.filename().string());  // relative to the .pvd, which is beside it
      times.push_back(t);
    }
    bar.update(k, t);
    if (done(k)) {
      last = k;
      break;
    }
  }
  bar.finish();
  if (!prefix.empty()) {
    std::vector<const char *> names;
    for (const auto &f : frames) names.push_back(f.c_str());
    const std::string pvd = prefix.string() + ".pvd";
    call(nd_write_pvd(pvd.c_str(), (int64_t)names.size(), names.data(), times.data()), "nd_write_pvd");
  }
  if (history.f) {
    const bool bad = std::fclose(history.f) != 0;
    history.f = nullptr;
    if (bad) throw LibError("cannot write the history " + history_path.string());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %" PRId64 " steps to t = %g; E_Theta %.8g -> %.8g, W %.8g; max contact force %.6g, max "
              "penetration %.4e; mean Newton iterations %.3f; %.2f s\n",
              s.file.c_str(), last - first, scalar(p, ND_TIME), E0, scalar(p, ND_ENERGY_AUGMENTED), scalar(p, ND_WORK),
              max_force, max_pen, last > first ? newton / (double)(last - first) : 0.0, seconds);
  return 0;
}

// A CLI11 check: a finite number above (strict) or at least lo.
CLI::Validator number_at_least(double lo, bool strict) {
  return CLI::Validator(
      [lo, strict](std::string &text) -> std::string {
        char *end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(x) || x < lo || (strict && x == lo))
          return text + " is not " + (strict ? "a positive number" : "a number >= " + CLI::detail::to_string(lo));
        return std::string();
      },
      strict ? "POSITIVE" : "NUMBER>=0");
}

}  // namespace

int main(int argc, char **argv) {
  int major = 0, minor = 0, patch = 0;
  nd_version(&major, &minor, &patch);
  const std::string version = "nitschedyn " ND_VERSION_STRING " (libnitschedyn " + std::to_string(major) + "." +
                              std::to_string(minor) + "." + std::to_string(patch) + ")";
  CLI::App app{"Runs a dynamic contact scene (a TOML scene file) with libnitschedyn: writes the energy and "
               "contact-force history as CSV and a ParaView series.",
               "nitschedyn"};
  app.footer("Exit status: 0 success, 1 the library failed, 2 usage or scene error.\nSee nitschedyn(1) for the "
             "scene file.");
  Options opt;
  app.add_option("scene", opt.scene, "the scene file (TOML)");
  app.add_option("--T", opt.T, "final time (overrides time.T)")->check(number_at_least(0, false));
  app.add_option("--tau", opt.tau, "time step (overrides time.tau)")->check(number_at_least(0, true));
  app.add_option("--out", opt.out, "directory of the outputs (default: the current directory)");
  app.add_option("--restart", opt.restart, "resume from a checkpoint file ([checkpoint]) of the same scene");
  app.add_option("--blas-threads", opt.blas_threads,
                 "BLAS threads inside the library's calls (default 1; 0: as the environment sets them)")
      ->check(CLI::Range(0, 4096));
  app.add_flag("--quiet,-q", opt.quiet, "print the summary line only (and errors)");
  app.add_flag("--progress", opt.progress, "show progress on stderr even when it is not a terminal");
  app.add_flag("--check", opt.check, "read the scene and set the problem up, then stop");
  app.add_flag("--list-keys", opt.list_keys, "list the keys of the scene file")->group("");
  app.set_version_flag("--version", version);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError &e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (opt.list_keys) {
    for (const auto &k : ndcli::documented_keys()) std::printf("%s\n", k.c_str());
    return 0;
  }
  if (opt.scene.empty()) {
    std::fprintf(stderr, "nitschedyn: no scene file (usage: nitschedyn SCENE.toml [options]; see --help)\n");
    return 2;
  }
  try {
    return run(opt);
  } catch (const SceneError &e) {
    std::fflush(stdout);
    std::fprintf(stderr, "nitschedyn: %s\n", ndcli::printable(e.what()).c_str());
    return 2;
  } catch (const LibError &e) {
    std::fflush(stdout);
    std::fprintf(stderr, "nitschedyn: %s\n", ndcli::printable(e.what()).c_str());
    return 1;
  } catch (const std::exception &e) {
    std::fflush(stdout);
    std::fprintf(stderr, "nitschedyn: %s\n", ndcli::printable(e.what()).c_str());
    return 1;
  }
}
