// The 2D disk of docs/design.md §7 (dropped on a plane, impact at t = 10) on the
// committed meshes, P1/P2, hybrid and Newmark (1/4, 1/2), and with mass
// redistribution and the applied force (issue 16) the hybrid and the explicit
// central difference (Newmark (0, 1/2), lumped mass, tau = 0.9 of its critical
// step rounded down to a divisor of 2), against the finest run: displacement
// at t = 12 and t = 14 in L2 and in the energy norm, and the contact force
// history in L2(0, T), versus the wall time of the steps.
//
// Two references: the hybrid P2 on the finest mesh of the ladder with half its
// step (every error column), and, for the contact force of the redistributed
// model, the explicit redistributed P2 one mesh finer (disk_h0.5.msh in the
// full plan; the finest mesh of the ladder in the quick plan): the column
// e_force_l2_red of every run. d_force_coarser needs no reference: the
// difference ||F_2h - F_h|| / ||F_h|| in L2(0, T) to the same curve's run on
// the next coarser mesh. Histories on different time grids are compared at
// the coarser run's times, the finer one interpolated linearly in time.
//
// The runs go through the public API (examples/drop_scene.c); only the
// comparison of fields on different meshes uses the library's internals
// (the P1/P2 basis on a cell), so the meshes need not be nested: every
// quadrature point of the reference mesh is located in the coarse mesh and
// the coarse field evaluated there (outside the coarse polygon, near the
// curved boundary, the nearest cell's polynomial is extended).
//
// With --cells quadrilateral the same disk meshed in quadrilaterals
// (examples/meshes/disk_quad_h*.msh), Q1/Q2, the hybrid scheme alone, against
// its own finest run (Q2); a last row compares the triangles' reference (P2,
// h = 1 or 2 as the plan's) with it, status simplex-reference: the two
// discretizations' limits must agree to their errors.
//
// With --body ball the 3D ball of the same scene, in tetrahedra
// (examples/meshes/ball_h*.msh) and hexahedra (ball_hex_h*.msh) in one
// study, the hybrid scheme alone, against one reference for both: P2
// tetrahedra at h = 2 (h = 4 in the quick plan) with half its step (a finer
// 3D reference does not fit the machine: P2 at h = 1 has 660,000 unknowns,
// Q2 hexahedra at h = 2 need tens of GB). Rows P1 and Q1 at h = 4 and 2
// (full plan; P1 also at h = 1), P2 and Q2 at h = 4 (full plan), so that the
// two families' rates are measured the same way on the same ladder.
//
//   disk_study --plan quick|full --out DIR [--repeat K] [--cells simplex|quadrilateral] [--body disk|ball]
// writes DIR/disk.csv (a row per run) and DIR/disk_force.csv (histories),
// DIR/disk_quad.csv and DIR/disk_quad_force.csv, or DIR/ball.csv and
// DIR/ball_force.csv.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "drop_scene.h"
#include "fem/simplex.hpp"
#include "fem/space.hpp"
#include "mesh/mesh.hpp"
#include "nitschedyn.h"

namespace {

constexpr double kLambda = 20, kMu = 20;  // the scene's Lame coefficients
constexpr double kGamma0 = 1e-3;          // safe for P1 and P2 (docs/design.md §7)
constexpr double kTauOverH = 1.0 / 40;    // tau tied to h: 0.1 at h = 4
constexpr double kT = 14, kSnap1 = 12, kSnap2 = 14;
// the explicit step: kCflFraction of the critical step, rounded down so that
// kTauDivides / tau is an integer (2 divides kSnap1, kSnap2 and kT)
constexpr double kCflFraction = 0.9, kTauDivides = 2;

// the mesh family of the study: "disk" (triangles), "disk_quad"
// (quadrilaterals) or "ball" (tetrahedra; the ball study's runs in
// hexahedra have the family "ball_hex")
std::string g_family = "disk";

int dimension(const std::string &family) { return family.compare(0, 4, "ball") == 0 ? 3 : 2; }
bool tensor_cells(const std::string &family) { return family == "disk_quad" || family == "ball_hex"; }

struct Spec {
  std::string scheme;  // "hybrid", "newmark(0.25,0.5)", "hybrid+redistributed" or "explicit+redistributed"
  int degree;
  double h, tau;  // explicit: tau <= 0, chosen from the critical step
  bool reference;
  std::string family = g_family;
  std::string label() const {
    char b[128];
    std::snprintf(b, sizeof b, "%s %s%d h=%g%s%s", scheme.c_str(), tensor_cells(family) ? "Q" : "P", degree, h,
                  reference ? " (reference)" : "", family == "disk" && g_family != "disk" ? " (triangles)" : "");
    return b;
  }
};

struct Run {
  Spec spec;
  std::unique_ptr<nd::Space> space;  // for evaluating the fields
  std::vector<double> u1, u2;        // full nodal displacements at kSnap1, kSnap2
  std::vector<double> force;         // ND_CONTACT_FORCE (redistributed: _APPLIED) at every time level
  int64_t unknowns = 0, steps = 0;
  double setup_s = 0, loop_s = 0, newton = 0;
  double tau_c = 0;  // the critical step estimate (explicit runs)
  int repeats = 0;
  std::string status = "ok";
};

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string mesh_path(double h, const std::string &family = g_family) {
  char b[512];
  std::snprintf(b, sizeof b, "%s/%s_h%g.msh", ND_MESH_DIR, family.c_str(), h);
  return b;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// One pass over the steps; with keep = true also the fields and the force.
// Returns an empty string or the error.
std::string march(Run &r, bool keep, double &setup_s, double &loop_s) {
  const Spec &s = r.spec;
  // "+redistributed": mass redistribution, and the force the step applied
  const bool redistributed = s.scheme.find("+redistributed") != std::string::npos;
  const bool hybrid = s.scheme.compare(0, 6, "hybrid") == 0;
  // the central difference: Newmark (0, 1/2) with the lumped mass
  const bool expl = s.scheme.compare(0, 8, "explicit") == 0;
  const double nm[2] = {expl ? 0.0 : 0.25, 0.5};
  nd_problem p = nullptr;
  double t0 = now();
  const int dim = dimension(s.family);
  int st = drop_scene_create(dim, mesh_path(s.h, s.family).c_str(), s.degree, hybrid ? ND_SCHEME_HYBRID : ND_SCHEME_NEWMARK,
                             nm, 1.0, kGamma0, expl ? 1.0 : s.tau, ND_SOLVER_AUTO, &p);
  if (st == ND_OK && expl) st = nd_problem_set_mass_lumping(p, 1);
  if (st == ND_OK && redistributed) st = nd_problem_set_mass_redistribution(p, 1);
  if (st == ND_OK && expl) {  // the step from the critical one, everything else set (counted in the set-up)
    st = nd_problem_estimate_critical_timestep(p, &r.tau_c);
    if (st == ND_OK) {
      r.spec.tau = kTauDivides / std::ceil(kTauDivides / (kCflFraction * r.tau_c));
      st = nd_problem_set_timestep(p, r.spec.tau);
    }
  }
  if (st == ND_OK) st = nd_problem_setup(p);
  setup_s = now() - t0;
  loop_s = 0;
  std::string error;
  int64_t n_nodes = 0;
  if (st == ND_OK) st = nd_problem_get_node_count(p, &n_nodes);
  const double tau = s.tau > 0 ? s.tau : 2 * kT;  // no estimate (a failed set-up): no steps
  const int64_t n1 = std::llround(kSnap1 / tau), n2 = std::llround(kSnap2 / tau);
  r.steps = std::llround(kT / tau);
  if (keep) {
    r.force.assign(r.steps + 1, 0.0);
    r.newton = 0;
    r.unknowns = dim * n_nodes;
  }
  for (int64_t n = 0; st == ND_OK && n <= r.steps; ++n) {
    if (n > 0) {
      t0 = now();
      st = nd_step(p);
      loop_s += now() - t0;
      if (st != ND_OK) break;
    }
    if (!keep) continue;
    double f = 0, it = 0;
    if (st == ND_OK) st = nd_get_scalar(p, redistributed ? ND_CONTACT_FORCE_APPLIED : ND_CONTACT_FORCE, &f);
    if (st == ND_OK && n > 0) st = nd_get_scalar(p, ND_NEWTON_ITERATIONS, &it);
    r.force[n] = f;
    r.newton += it;
    if (st == ND_OK && (n == n1 || n == n2)) {
      std::vector<double> &u = n == n1 ? r.u1 : r.u2;
      u.resize(static_cast<size_t>(dim * n_nodes));
      st = nd_get_field(p, ND_FIELD_DISPLACEMENT, n_nodes, u.data());
    }
  }
  if (st != ND_OK) error = nd_last_error();
  if (keep && error.empty()) {  // the evaluation space; its nodes must be the problem's
    auto mesh = std::make_shared<const nd::Mesh>(nd::read_gmsh(mesh_path(s.h, s.family).c_str()));
    r.space = std::make_unique<nd::Space>(mesh, s.degree);
    std::vector<double> x(static_cast<size_t>(dim * n_nodes));
    nd_problem_get_node_coordinates(p, n_nodes, x.data());
    bool same = r.space->n_nodes == n_nodes;
    for (int64_t i = 0; same && i < n_nodes; ++i)
      for (int d = 0; d < dim; ++d) same = same && r.space->node_x(i)[d] == x[dim * i + d];
    if (!same) error = "the evaluation space differs from the run's";
  }
  nd_problem_destroy(&p);
  return error;
}

void run(Run &r, int repeat) {
  std::vector<double> setup(1), loop(1);
  std::string err = march(r, true, setup[0], loop[0]);
  for (int k = 1; err.empty() && k < repeat; ++k) {
    double s, l;
    err = march(r, false, s, l);
    setup.push_back(s);
    loop.push_back(l);
  }
  if (!err.empty()) {
    for (char &c : err)
      if (c == ',' || c == '"' || c == '\n') c = ';';
    r.status = err;
  }
  r.repeats = static_cast<int>(loop.size());
  r.setup_s = median(setup);
  r.loop_s = median(loop);
  std::fprintf(stderr, "%-46s %6lld unknowns %5lld steps (tau %.6g)  setup %.3f s  loop %.3f s  %s\n",
               r.spec.label().c_str(), static_cast<long long>(r.unknowns), static_cast<long long>(r.steps), r.spec.tau,
               r.setup_s, r.loop_s, r.status.c_str());
}

// ---- fields on non-nested meshes --------------------------------------------------

// Finds, for a point, the cell of a 2D or 3D mesh that contains it (or,
// outside the mesh, the one it is least outside of) through a uniform grid
// of buckets.
class Locator {
 public:
  explicit Locator(const nd::Mesh &m) : m_(m), dim_(m.dim) {
    double hi[3] = {-1e300, -1e300, -1e300};
    for (int d = 0; d < 3; ++d) lo_[d] = 1e300, size_[d] = 1;
    for (int64_t v = 0; v < m.n_vertices; ++v)
      for (int d = 0; d < dim_; ++d) lo_[d] = std::min(lo_[d], m.x(v)[d]), hi[d] = std::max(hi[d], m.x(v)[d]);
    // about two cells a bucket
    const int nb = std::max(1, static_cast<int>(std::pow(static_cast<double>(m.n_cells) / 2, 1.0 / dim_)));
    for (int d = 0; d < dim_; ++d) size_[d] = (hi[d] - lo_[d]) / nb * (1 + 1e-9);
    nb_ = nb;
    buckets_.resize(static_cast<size_t>(std::pow(nb, dim_) + 0.5));
    box_.resize(static_cast<size_t>(2 * dim_ * m.n_cells));
    for (int64_t c = 0; c < m.n_cells; ++c) {
      int clo[3] = {0, 0, 0}, chi[3] = {0, 0, 0};
      for (int d = 0; d < dim_; ++d) {
        double a = 1e300, b = -1e300;
        for (int k = 0; k < m.cell_vertices(c); ++k) a = std::min(a, m.x(m.cell(c)[k])[d]), b = std::max(b, m.x(m.cell(c)[k])[d]);
        clo[d] = index(a, d), chi[d] = index(b, d);
        const double margin = 1e-9 * (b - a);
        box_[2 * (dim_ * c + d)] = a - margin, box_[2 * (dim_ * c + d) + 1] = b + margin;
      }
      for (int i = clo[0]; i <= chi[0]; ++i)
        for (int j = clo[1]; j <= chi[1]; ++j)
          for (int k = clo[2]; k <= chi[2]; ++k) buckets_[bucket(i, j, k)].push_back(c);
    }
  }
  // cell and reference coordinates xi of x in it
  int64_t find(const double *x, double *xi) const {
    // first the cells of x's bucket whose box holds x (a point inside the mesh)
    int b0[3] = {0, 0, 0};
    for (int d = 0; d < dim_; ++d) b0[d] = index(x[d], d);
    for (int64_t c : buckets_[bucket(b0[0], b0[1], b0[2])]) {
      bool in_box = true;
      for (int d = 0; d < dim_ && in_box; ++d) in_box = x[d] >= box_[2 * (dim_ * c + d)] && x[d] <= box_[2 * (dim_ * c + d) + 1];
      if (!in_box) continue;
      double l[3];
      if (inside(c, x, l) >= -1e-12) {
        std::copy(l, l + dim_, xi);
        return c;
      }
    }
    // else the least outside of the nearest rings' cells
    int64_t best = -1;
    double best_min = -1e300;
    int b[3] = {0, 0, 0};
    for (int d = 0; d < dim_; ++d) b[d] = index(x[d], d);
    const int third = dim_ == 3 ? 1 : 0;  // the rings of a 2D grid are flat
    for (int ring = 0; ring <= nb_ && best_min < -1e-12; ++ring) {  // widen until inside, or all searched
      for (int i = b[0] - ring; i <= b[0] + ring; ++i)
        for (int j = b[1] - ring; j <= b[1] + ring; ++j)
          for (int k = b[2] - ring * third; k <= b[2] + ring * third; ++k) {
            if (i < 0 || j < 0 || k < 0 || i >= nb_ || j >= nb_ || (third && k >= nb_)) continue;
            if (std::max({std::abs(i - b[0]), std::abs(j - b[1]), std::abs(k - b[2])}) != ring) continue;
            for (int64_t c : buckets_[bucket(i, j, k)]) {
              double l[3];
              const double lmin = inside(c, x, l);
              if (lmin > best_min) best_min = lmin, best = c, std::copy(l, l + dim_, xi);
            }
          }
      if (best >= 0 && ring >= 1) break;  // outside the mesh: the nearest rings decide
    }
    return best;
  }

 private:
  int index(double v, int d) const {
    return std::clamp(static_cast<int>(std::floor((v - lo_[d]) / size_[d])), 0, nb_ - 1);
  }
  // xi of x in cell c, and how far inside: the least barycentric
  // coordinate, or the distance to the cube's sides (negative: outside)
  double inside(int64_t c, const double *x, double *l) const {
    reference(c, x, l);
    double lmin = 1e300, sum = 0;
    for (int d = 0; d < dim_; ++d) {
      lmin = std::min(lmin, m_.simplicial(c) ? l[d] : std::min(l[d], 1 - l[d]));
      sum += l[d];
    }
    return m_.simplicial(c) ? std::min(lmin, 1 - sum) : lmin;
  }
  size_t bucket(int i, int j, int k) const {
    return static_cast<size_t>((dim_ == 3 ? (static_cast<int64_t>(i) * nb_ + j) * nb_ + k : static_cast<int64_t>(i) * nb_ + j));
  }
  // xi with x(xi) = x: the affine map's inverse, or Newton's iterations on
  // the multilinear map from the centre (quadratic convergence; 8 reach
  // round-off for the convex cells of the meshes, and points near them)
  void reference(int64_t c, const double *x, double *xi) const {
    nd::CellMap A(m_, c);
    const bool simplex = m_.simplicial(c);
    std::fill(xi, xi + dim_, simplex ? 0.0 : 0.5);
    double y[3], dx[3];
    for (int it = 0; it < (simplex ? 1 : 8); ++it) {
      A.at(xi);
      A.to_physical(xi, y);
      for (int d = 0; d < dim_; ++d) dx[d] = x[d] - y[d];
      for (int i = 0; i < dim_; ++i)
        for (int j = 0; j < dim_; ++j) xi[i] += A.Jinv[i * dim_ + j] * dx[j];
    }
    if (!simplex) {  // not converged (a point far off the cell, where the map folds): far outside it
      A.to_physical(xi, y);
      double dist = 0;
      for (int d = 0; d < dim_; ++d) dist += (x[d] - y[d]) * (x[d] - y[d]);
      if (!(std::sqrt(dist) <= 1e-9 * std::pow(std::abs(A.det), 1.0 / dim_))) std::fill(xi, xi + dim_, -1e300);
    }
  }
  const nd::Mesh &m_;
  const int dim_;
  double lo_[3], size_[3];
  int nb_;
  std::vector<std::vector<int64_t>> buckets_;
  std::vector<double> box_;  // each cell's bounding box, per axis low and high
};

// u and its gradient (row-major dim x dim, du_i/dx_j) at reference point xi of cell c (map A)
void evaluate(const nd::Space &s, const std::vector<double> &u, int64_t c, nd::CellMap A, const double *xi,
              double *val, double *grad) {
  const int dim = s.mesh->dim;
  const nd::Lagrange &basis = s.basis_of(c);
  double phi[27], dphi_ref[81], dphi[3];
  A.at(xi);
  basis.values(xi, phi);
  basis.gradients(xi, dphi_ref);
  const int64_t *nodes = s.nodes_of(c);
  std::fill(val, val + dim, 0.0);
  std::fill(grad, grad + dim * dim, 0.0);
  for (int a = 0; a < basis.n; ++a) {
    A.physical_gradient(dphi_ref + dim * a, dphi);
    for (int i = 0; i < dim; ++i) {
      const double ui = u[dim * nodes[a] + i];
      val[i] += phi[a] * ui;
      for (int j = 0; j < dim; ++j) grad[dim * i + j] += dphi[j] * ui;
    }
  }
}

// 2 mu eps:eps + lambda tr(eps)^2 of a displacement gradient
double strain_energy_density(int dim, const double *g) {
  double ee = 0, tr = 0;
  for (int i = 0; i < dim; ++i) {
    tr += g[dim * i + i];
    for (int j = 0; j < dim; ++j) {
      const double e = 0.5 * (g[dim * i + j] + g[dim * j + i]);
      ee += e * e;
    }
  }
  return 2 * kMu * ee + kLambda * tr * tr;
}

// Relative L2 and energy-norm errors of (coarse, uc[k]) against (reference,
// ur[k]) for each k, integrated with the reference mesh's rule of degree
// 2 p_ref; each quadrature point located once for every k.
void field_errors(const Run &ref, const std::vector<const std::vector<double> *> &ur, const Run &run,
                  const std::vector<const std::vector<double> *> &uc, const Locator &loc, double *l2, double *energy) {
  const nd::Space &R = *ref.space, &C = *run.space;
  const int dim = R.mesh->dim;
  const size_t K = ur.size();
  // (the reference mesh holds one cell type)
  const nd::QuadratureRule q =
      R.mesh->simplicial(0) ? nd::simplex_rule(dim, 2 * R.degree) : nd::cube_rule(dim, 2 * R.degree);
  std::vector<double> e_l2(K), r_l2(K), e_en(K), r_en(K);
  for (int64_t c = 0; c < R.mesh->n_cells; ++c) {
    nd::CellMap A(*R.mesh, c);
    for (size_t k = 0; k < q.size(); ++k) {
      const double *xi = &q.points[dim * k];
      double x[3], vr[3], gr[9], vc[3], gc[9], xic[3], dg[9];
      A.at(xi);
      A.to_physical(xi, x);
      const int64_t cc = loc.find(x, xic);
      const double w = q.weights[k] * std::abs(A.det);
      for (size_t s = 0; s < K; ++s) {
        evaluate(R, *ur[s], c, A, xi, vr, gr);
        evaluate(C, *uc[s], cc, nd::CellMap(*C.mesh, cc), xic, vc, gc);
        for (int i = 0; i < dim; ++i) {
          e_l2[s] += w * (vc[i] - vr[i]) * (vc[i] - vr[i]);
          r_l2[s] += w * vr[i] * vr[i];
        }
        for (int i = 0; i < dim * dim; ++i) dg[i] = gc[i] - gr[i];
        e_en[s] += w * strain_energy_density(dim, dg);
        r_en[s] += w * strain_energy_density(dim, gr);
      }
    }
  }
  for (size_t s = 0; s < K; ++s) l2[s] = std::sqrt(e_l2[s] / r_l2[s]), energy[s] = std::sqrt(e_en[s] / r_en[s]);
}

// The force history of a run at time t in [0, T]: its value at a time level
// (t within 1e-9 steps of it), linear in between.
double force_at(const Run &r, double t) {
  const double x = t / r.spec.tau;
  const double nearest = std::round(x);
  if (std::abs(x - nearest) < 1e-9) return r.force[static_cast<size_t>(std::clamp<double>(nearest, 0, r.steps))];
  const int64_t n = std::clamp<int64_t>(static_cast<int64_t>(std::floor(x)), 0, r.steps - 1);
  const double a = x - static_cast<double>(n);
  return (1 - a) * r.force[n] + a * r.force[n + 1];
}

// ||F_a - F_b|| / ||F_b|| in L2(0,T), trapezoidal at the time levels of the
// run with the larger step, the other run's history taken there by force_at
// (where the smaller step divides the larger, its own values: the earlier
// comparison with the reference, whose step divides the coarse one).
double force_difference(const Run &a, const Run &b) {
  const Run &grid = a.spec.tau >= b.spec.tau ? a : b;
  double e = 0, r = 0;
  for (int64_t n = 0; n <= grid.steps; ++n) {
    const double w = (n == 0 || n == grid.steps) ? 0.5 : 1.0, t = static_cast<double>(n) * grid.spec.tau;
    const double fa = &grid == &a ? a.force[n] : force_at(a, t), fb = &grid == &b ? b.force[n] : force_at(b, t);
    e += w * (fa - fb) * (fa - fb);
    r += w * fb * fb;
  }
  return std::sqrt(e / r);
}

// L2(0,T) error of a run's force history against a reference's
double force_error(const Run &ref, const Run &run) { return force_difference(run, ref); }

}  // namespace

int main(int argc, char **argv) {
  std::string plan = "quick", out = ".", cells = "simplex", body = "disk";
  int repeat = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--plan")) plan = argv[i + 1];
    else if (!std::strcmp(argv[i], "--out")) out = argv[i + 1];
    else if (!std::strcmp(argv[i], "--repeat")) repeat = std::max(1, std::atoi(argv[i + 1]));
    else if (!std::strcmp(argv[i], "--cells")) cells = argv[i + 1];
    else if (!std::strcmp(argv[i], "--body")) body = argv[i + 1];
    else plan = "";
  }
  if ((argc - 1) % 2 != 0 || (plan != "quick" && plan != "full") || (cells != "simplex" && cells != "quadrilateral") ||
      (body != "disk" && body != "ball")) {
    std::fprintf(stderr, "usage: disk_study --plan quick|full --out DIR [--repeat K] [--cells simplex|quadrilateral] "
                         "[--body disk|ball]\n");
    return 2;
  }
  const bool ball = body == "ball", quads = !ball && cells == "quadrilateral";
  if (quads) g_family = "disk_quad";
  if (ball) g_family = "ball";
  const bool quick = plan == "quick";
  const char *const kExplicit = "explicit+redistributed";
  std::vector<Run> runs;
  Run ref, ref_red;
  std::vector<Run *> refs{&ref};
  // quadrilaterals: the triangles' reference beside their own (no redistributed one)
  Run simplex_ref;
  if (ball) {
    // one reference for both families: P2 tetrahedra on the finest
    // tetrahedral mesh that fits, half its step; the ladders of both
    // families the same, P1 also one mesh finer
    const double h_ref = quick ? 4 : 2;
    ref.spec = {"hybrid", 2, h_ref, 0.5 * kTauOverH * h_ref, true};
    for (const char *family : {"ball", "ball_hex"})
      for (int degree : {1, 2}) {
        std::vector<double> hs;
        if (degree == 1) hs = quick ? std::vector<double>{4} : std::vector<double>{4, 2};
        else if (!quick) hs = {4};
        if (degree == 1 && !quick && !std::strcmp(family, "ball")) hs.push_back(1);
        for (double h : hs) {
          Run r;
          r.spec = {"hybrid", degree, h, kTauOverH * h, false, family};
          runs.push_back(std::move(r));
        }
      }
  } else {
    // the ladder; the reference is the finest mesh in P2 with half its time
    // step; the redistributed model's reference the explicit redistributed P2
    // one mesh finer (full plan) or on the finest mesh (quick plan)
    const std::vector<double> hs = quick ? std::vector<double>{4, 2} : std::vector<double>{4, 2, 1};
    const double h_ref = hs.back(), h_ref_red = quick ? h_ref : h_ref / 2;
    ref.spec = {"hybrid", 2, h_ref, 0.5 * kTauOverH * h_ref, true};
    ref_red.spec = {kExplicit, 2, h_ref_red, 0, true};
    simplex_ref.spec = {"hybrid", 2, h_ref, 0.5 * kTauOverH * h_ref, true, "disk"};
    refs.push_back(quads ? &simplex_ref : &ref_red);
    const std::vector<const char *> schemes =
        quads ? std::vector<const char *>{"hybrid"}
              : std::vector<const char *>{"hybrid", "newmark(0.25,0.5)", "hybrid+redistributed", kExplicit};
    for (const char *scheme : schemes)
      for (int degree : {1, 2})
        for (double h : hs) {
          if (quick && degree == 2 && h == h_ref) continue;
          Run r;
          r.spec = {scheme, degree, h, std::strcmp(scheme, kExplicit) ? kTauOverH * h : 0.0, false};
          runs.push_back(std::move(r));
        }
  }
  for (Run *r : refs) {
    run(*r, 1);
    if (r->status != "ok") {
      std::fprintf(stderr, "disk_study: the reference run %s failed: %s\n", r->spec.label().c_str(),
                   r->status.c_str());
      return 1;
    }
  }
  for (Run &r : runs) run(r, repeat);
  // the successive differences: each run (and the redistributed reference)
  // against the same curve's run on the mesh twice as coarse
  auto coarser = [&](const Run &r) -> const Run * {
    for (const Run &c : runs)
      if (c.spec.scheme == r.spec.scheme && c.spec.degree == r.spec.degree && c.spec.h == 2 * r.spec.h &&
          c.spec.family == r.spec.family && c.status == "ok" && r.status == "ok")
        return &c;
    return nullptr;
  };

  const std::string csv = out + "/" + g_family + ".csv", fcsv = out + "/" + g_family + "_force.csv";
  FILE *f = std::fopen(csv.c_str(), "w"), *ff = std::fopen(fcsv.c_str(), "w");
  if (!f || !ff) {
    std::fprintf(stderr, "disk_study: cannot write %s\n", out.c_str());
    return 1;
  }
  std::fprintf(f, "code,scheme,degree,h,unknowns,tau,T,steps,setup_s,loop_s,repeats,newton_its,e_l2_u_t12,"
                  "e_energy_u_t12,e_l2_u_t14,e_energy_u_t14,e_force_l2,e_force_l2_red,d_force_coarser,tau_c,status,"
                  "cells,d_l2_u_t14_coarser\n");
  std::fprintf(ff, "run,t,force\n");
  // errors: the five columns against the reference; then the force against
  // the redistributed reference, the successive difference and tau_c; last
  // the cells and the successive difference of u in L2 at t = 14 (the finer
  // run the reference: no reference needed)
  auto row = [&](const Run &r, const std::string &errors) {
    std::string extra;
    char b[64];
    if (!quads && !ball && !r.spec.reference && r.status == "ok")
      std::snprintf(b, sizeof b, "%.6g", force_error(ref_red, r)), extra = b;
    const Run *c = &r == &ref ? nullptr : coarser(r);
    std::snprintf(b, sizeof b, ",%.6g", c ? force_difference(*c, r) : NAN);
    extra += c ? b : ",";
    std::snprintf(b, sizeof b, ",%.10g", r.tau_c);
    extra += r.tau_c > 0 ? b : ",";
    const char *kind = dimension(r.spec.family) == 3 ? (tensor_cells(r.spec.family) ? "hexahedron" : "tetrahedron")
                                                     : (tensor_cells(r.spec.family) ? "quadrilateral" : "triangle");
    std::string d_u;
    if (c) {
      const Locator loc(*c->space->mesh);
      double l2, en;
      field_errors(r, {&r.u2}, *c, {&c->u2}, loc, &l2, &en);
      std::snprintf(b, sizeof b, "%.6g", l2);
      d_u = b;
    }
    std::fprintf(f, "nitschedyn,\"%s\",%d,%g,%lld,%.10g,%g,%lld,%.6g,%.6g,%d,%.0f,%s,%s,%s,%s,%s\n",
                 r.spec.scheme.c_str(), r.spec.degree, r.spec.h, static_cast<long long>(r.unknowns), r.spec.tau, kT,
                 static_cast<long long>(r.steps), r.setup_s, r.loop_s, r.repeats, r.newton, errors.c_str(),
                 extra.c_str(), r.spec.reference ? "reference" : r.status.c_str(), kind, d_u.c_str());
    for (size_t n = 0; n < r.force.size(); ++n)
      std::fprintf(ff, "\"%s\",%.10g,%.10g\n", r.spec.label().c_str(), static_cast<double>(n) * r.spec.tau, r.force[n]);
  };
  row(ref, ",,,,");
  if (!quads && !ball) row(ref_red, ",,,,");
  {  // the transfer itself: the reference against itself through the locator is exact
    const Locator loc(*ref.space->mesh);
    double l2, en;
    field_errors(ref, {&ref.u2}, ref, {&ref.u2}, loc, &l2, &en);
    if (!(l2 < 1e-12 && en < 1e-10)) {
      std::fprintf(stderr, "disk_study: the field transfer is not exact on one mesh (%g, %g)\n", l2, en);
      return 1;
    }
  }
  auto errors = [&](const Run &r) {
    const Locator loc(*r.space->mesh);
    double l2[2], en[2];
    field_errors(ref, {&ref.u1, &ref.u2}, r, {&r.u1, &r.u2}, loc, l2, en);
    char b[160];
    std::snprintf(b, sizeof b, "%.6g,%.6g,%.6g,%.6g,%.6g", l2[0], en[0], l2[1], en[1], force_error(ref, r));
    return std::string(b);
  };
  for (const Run &r : runs) row(r, r.status == "ok" ? errors(r) : ",,,,");
  if (quads) {  // the triangles' reference against the quadrilaterals'
    simplex_ref.spec.reference = false;
    simplex_ref.status = "simplex-reference";
    row(simplex_ref, errors(simplex_ref));
  }
  const bool ok = std::fclose(f) == 0 && std::fclose(ff) == 0;
  return ok ? 0 : 1;
}
