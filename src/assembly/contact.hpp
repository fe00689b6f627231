// The contact quadrature points and their constant rows (docs/design.md §2):
//   a_q . U = u_n(x_q),  s_q . U = sigma_n(u)(x_q) (gradient in the owning cell)
// with weight w_q, gamma_q = gamma0 h_K and initial gap g_q. Assembled once.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "assembly/material.hpp"
#include "fem/space.hpp"

namespace nd {

struct Share;  // parallel/share.hpp

struct SparseRow {
  std::vector<int64_t> idx;  // free DOF indices
  std::vector<double> val;
  double dot(const double *U) const {
    double s = 0;
    for (size_t k = 0; k < idx.size(); ++k) s += val[k] * U[idx[k]];
    return s;
  }
};

// A rigid plane through `point`; `normal` is the unit normal pointing from
// the obstacle towards the body (nu_o). The contact normal is n = -nu_o and
// the initial gap g0(x) = (x - point) . nu_o.
struct ContactPlane {
  int region;
  double point[3];
  double normal[3];
};

// values per point of a pairing (contact/pairing.hpp): the master facet, -1
// for a point not of a pair, and 3 coordinates there (barycentric; a
// hexahedron's face's bilinear (s, t), then 0)
constexpr int kPairingValues = 4;

struct ContactPoints {
  std::vector<SparseRow> a, s;
  // the same rows on the clamped DOFs (full DOF indices): the nodal contact
  // force and the reactions need them, the step does not
  std::vector<SparseRow> a_fixed, s_fixed;
  std::vector<int> plane;                // index into the definition's planes; -1: a curved region's point
  std::vector<int> region;               // the point's region
  std::vector<double> normal;            // nu_q = -n_q, 3 per point: what the rows were made with
  std::vector<double> phi;               // the basis values at the point (Space::stride each, 0 past its cell's basis): u_q(U) (contact/obstacles.hpp)
  std::vector<double> w, gamma, gap, x;  // x: n * dim
  std::vector<double> h;                 // diameter h_K of the owning cell
  // gamma_q / gamma0: h_K, times E / E_K where the owning cell's material is
  // not the default's (CellMaterials::gamma_length)
  std::vector<double> gamma_length;
  std::vector<int64_t> facet;            // index into Mesh::boundary
  // nu_q = sum_k |a_qk| + gamma_q |s_qk| >= ||p_q||_1, so |P_q(U) - P_q(U')|
  // <= nu_q max_{i in dofs} |U_i - U'_i| with the gaps held, dofs the free
  // DOFs the points' rows touch, sorted (set_bounds; empty nu: no bound,
  // ContactLaw::certainly_free then always evaluates)
  std::vector<double> nu;
  std::vector<int64_t> dofs;
  // sum_k |a_qk| >= ||a_q||_1: u_n - g0 likewise (the penetration guard's bound)
  std::vector<double> a_sum;
  // runs of consecutive points with one index list (a facet's points: 9 on
  // a tetrahedron's facet with P1, 16 with P2), run r the points [runs[r], runs[r + 1])
  // (the last entry size()), and whether a run's points have the same s_q,
  // bit for bit (P1: the stress of a cell is constant): set_bounds; empty,
  // each point alone. ContactLaw::P_all reads U at a run's DOFs once for
  // all its points, and a shared s_q once.
  std::vector<int64_t> runs;
  std::vector<char> run_shares_s;
  // the runs' rows interleaved, for ContactLaw::P_all's wide form (four
  // points per load): run r's a values from run_rows[run_row_at[r]], entry
  // k of its point p (of n) at k n + p, then its s values likewise unless
  // the run shares s_q (set_bounds, with runs)
  std::vector<double> run_rows;
  std::vector<int64_t> run_row_at;
  // which rank evaluates which point in a step (the rank of its facet's
  // cell); null: this process evaluates every point
  std::shared_ptr<const Share> share;
  // Friction (docs/design.md §10.2): m = dim values per point, the normal
  // pair (a, s) and m - 1 tangential pairs ta . U = t_qk . u(x_q), ts . U =
  // t_qk . sigma(u) n_q, point q's k-th (k < m - 1) at q (m - 1) + k, with
  // a_q's index list; t_qk (3 values each, in `tangent`) an orthonormal basis
  // of the plane normal to n_q. m = 1 (frictionless): all empty.
  int m = 1;
  std::vector<SparseRow> ta, ts, ta_fixed, ts_fixed;
  std::vector<double> tangent;
  // per point (m > 1): whether its region's law is frictional; K_Theta then
  // carries its tangential Theta-term -Theta w_q gamma_q sum_k ts_qk ts_qk^T
  std::vector<char> friction;
  // Two bodies (docs/design.md §10.3, contact/pairing.hpp): each point's
  // pairing, kPairingValues values (the master facet, -1 for a point not of
  // a pair, and its coordinates there), and the master cell's
  // basis values at the paired point (Space::stride each); both empty without pairs
  std::vector<double> pairing, counterpart_phi;
  size_t size() const { return w.size(); }
  // the a and s rows of value k (0: the normal, k >= 1: tangential k - 1)
  const SparseRow &a_row(size_t q, int k) const { return k == 0 ? a[q] : ta[q * (m - 1) + (k - 1)]; }
  const SparseRow &s_row(size_t q, int k) const { return k == 0 ? s[q] : ts[q * (m - 1) + (k - 1)]; }
};

// An orthonormal basis t_1 .. t_{dim-1} of the plane normal to the unit n
// (3 values each): 2D t = (-n_y, n_x); 3D t_1 along e x n for the axis e
// least aligned with n, t_2 = n x t_1.
void tangent_basis(int dim, const double *n, double *t);

// g_q = (x_q - point) . nu_o with the current point of each point's plane
// (the point may move in time; the rows and weights do not).
std::vector<double> contact_gaps(const ContactPoints &cp, const std::vector<ContactPlane> &planes);

// nu, dofs and the runs, with the gammas the points have now
void set_bounds(ContactPoints &cp);

// The points of each region of `regions`, in that order (s_q with the
// material of the point's cell); plane_of[r] the
// index of regions[r]'s plane when its gaps have the closed form
// (contact_gaps), -1 otherwise (gaps 0 here: contact/obstacles.hpp), and
// normal_of(r, b, x, nu) the unit normal nu_q (from the obstacle towards the
// body) of the next point of regions[r], at x on boundary facet b: its rows
// hold n_q = -nu_q.
using NormalOf = std::function<void(size_t r, int64_t b, const double *x, double *nu)>;
// tangential: the friction rows too (m = dim)
ContactPoints assemble_contact(const Space &sp, const DofMap &dofs, const CellMaterials &mat, const std::vector<int> &regions,
                               const std::vector<int> &plane_of, const NormalOf &normal_of, double gamma0,
                               bool tangential = false);
// Point q of a pair: its rows gain the master's side, a_q . U = n_q . (u(x_q)
// - u(X_q)) with X_q the point of master cell `cell` at reference
// coordinates xi (the tangential rows likewise); the stresses s_q stay the
// slave's, zeros on the master's DOFs (one index list for a_q and s_q). A DOF
// of both sides (a body touching itself next to a shared node) is one entry.
void append_counterpart(const Space &sp, const DofMap &dofs, ContactPoints &cp, size_t q, int64_t cell,
                        const double *xi);
// the planes alone (each region's plane's normal)
ContactPoints assemble_contact(const Space &sp, const DofMap &dofs, const CellMaterials &mat,
                               const std::vector<ContactPlane> &planes, double gamma0);

}  // namespace nd
