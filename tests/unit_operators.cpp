// Mass and stiffness: total mass, rigid motions, symmetry, and P1 = P2 on
// fields both spaces represent exactly; the products pass by node blocks.
#include <cmath>
#include <cstring>

#include "assembly/bulk.hpp"
#include "common/simd.hpp"
#include "linalg/node_blocks.hpp"
#include "mesh/mesh.hpp"
#include "nitschedyn.h"
#include "monitor/energies.hpp"
#include "problem/discretization.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "solve/newton.hpp"

#include <check.h>
#include "testutil.h"
#include "unit_fixtures.hpp"

namespace {

double total(const nd::Csr &A) {
  double s = 0;
  for (double v : A.val) s += v;
  return s;
}

double max_abs(const std::vector<double> &v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

double max_asymmetry(const nd::Csr &A) {
  double m = 0;
  for (int64_t i = 0; i < A.n; ++i)
    for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k)
      m = std::max(m, std::fabs(A.val[k] - A.val[A.find(A.col[k], i)]));
  return m;
}

// interpolate a vector field given per point into the (free = all) DOFs
template <class F>
std::vector<double> interpolate(const nd::Space &s, F f) {
  std::vector<double> u(s.n_dofs());
  for (int64_t i = 0; i < s.n_nodes; ++i) f(s.node_x(i), &u[i * s.dim]);
  return u;
}

double quadratic_form(const nd::Csr &A, const std::vector<double> &u) {
  std::vector<double> y(u.size());
  A.multiply(u.data(), y.data());
  return nd::dot(A.n, u.data(), y.data());
}

const nd::Material steel_like{3.0, 0.3, 2.5};

// The pattern by its definition: row r holds the free DOFs of every taken
// cell that holds r (each pair of a cell's DOFs, sorted, duplicates dropped)
nd::Csr pattern_of_dof_pairs(const nd::Space &s, const nd::DofMap &dofs, const nd::AssemblyPart &part) {
  std::vector<std::vector<int64_t>> rows(static_cast<size_t>(dofs.n_free));
  const int nb = s.basis.n, d = s.dim;
  for (int64_t c = 0; c < s.mesh->n_cells; ++c) {
    if (!part.takes(s, dofs, c)) continue;
    for (int i = 0; i < nb * d; ++i) {
      const int64_t r = dofs.free[s.nodes_of(c)[i / d] * d + i % d];
      if (r < 0 || (part.rows && !(*part.rows)[r])) continue;
      for (int j = 0; j < nb * d; ++j)
        if (const int64_t col = dofs.free[s.nodes_of(c)[j / d] * d + j % d]; col >= 0) rows[r].push_back(col);
    }
  }
  nd::Csr whole = nd::csr_from_rows(std::move(rows));
  if (!part.rows && !part.cells) return whole;
  nd::Csr A = whole;  // a part stores its rows that have entries, and no others
  A.part = true;
  std::vector<int64_t> &ptr = A.ptr.mut();
  ptr.assign(1, 0);
  for (int64_t i = 0; i < whole.n; ++i)
    if (whole.ptr[i + 1] > whole.ptr[i]) A.held.push_back(i), ptr.push_back(whole.ptr[i + 1]);
  return A;
}

// A line, an irregular rectangle and a cube of 2 x 2 x 2 cells, each with
// region 7 on its side x = 0 (the cube: z = 0), to clamp.
std::vector<std::shared_ptr<nd::Mesh>> meshes_with_region_7() {
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, face_z0[3] = {1, 1, 0}, side_x0[3] = {0, 1, 0};
  auto box = std::make_shared<nd::Mesh>(nd::make_box(2, 2, 2, lo, hi));
  nd::add_region_box(*box, 7, lo, face_z0);
  auto rect = ndtest::irregular_rectangle(4);
  nd::add_region_box(*rect, 7, lo, side_x0);
  auto line = ndtest::irregular_interval(6, 0, 1);
  nd::add_region_box(*line, 7, lo, lo);  // the end x = 0
  return {line, rect, box};
}

}  // namespace

// operator_pattern builds the pattern over nodes and expands it: the same
// rows and columns as the DOF pairs of the cells, with clamped DOFs, on a
// part of the rows and of the cells (which stores those rows only), in 1D,
// 2D and 3D, P1 and P2.
START_TEST(the_pattern_is_the_dof_pairs_of_the_cells) {
  const std::vector<std::shared_ptr<nd::Mesh>> meshes = meshes_with_region_7();
  int compared = 0;
  for (const auto &mesh : meshes)
    for (int degree = 1; degree <= 2; ++degree) {
      nd::Space s(mesh, degree);
      for (int clamped = 0; clamped <= 1; ++clamped) {
        nd::DofMap dofs(s, clamped ? std::vector<int>{7} : std::vector<int>{});
        ck_assert(clamped ? dofs.n_free < s.n_dofs() : dofs.n_free == s.n_dofs());
        std::vector<char> rows(static_cast<size_t>(dofs.n_free)), cells(static_cast<size_t>(mesh->n_cells));
        for (int64_t node = 0; node < s.n_nodes; ++node)
          for (int a = 0; a < s.dim; ++a)
            if (const int64_t r = dofs.free[node * s.dim + a]; r >= 0) rows[r] = node % 3 == 0;
        for (int64_t c = 0; c < mesh->n_cells; c += 2) cells[c] = 1;
        for (int variant = 0; variant < 3; ++variant) {
          nd::AssemblyPart part;
          if (variant >= 1) part.rows = &rows;
          if (variant == 2) part.cells = &cells;
          const nd::Csr a = nd::operator_pattern(s, dofs, part), b = pattern_of_dof_pairs(s, dofs, part);
          ck_assert_msg(a.n == b.n && a.part == b.part && a.held == b.held && a.ptr == b.ptr && a.col == b.col &&
                            a.val == b.val,
                        "%dD P%d clamped %d part %d: the patterns differ", s.dim, degree, clamped, variant);
          ck_assert(b.col.size() > 0);
          ++compared;
        }
      }
    }
  ck_assert_int_eq(compared, 36);
}
END_TEST

START_TEST(total_mass_is_rho_times_measure) {
  // 1D (0.3, 2), 2D [0,2]x[0,1], 3D unit cube; P1 and P2; consistent and lumped
  const std::shared_ptr<nd::Mesh> meshes[] = {ndtest::irregular_interval(9, 0.3, 2.0),
                                              ndtest::irregular_rectangle(3), ndtest::cube_of_tets()};
  const double measure[] = {1.7, 2.0, 1.0};
  for (int m = 0; m < 3; ++m)
    for (int degree = 1; degree <= 2; ++degree) {
      nd::Space s(meshes[m], degree);
      nd::DofMap dofs(s, {});
      nd::BulkOperators ops = nd::assemble_bulk(s, dofs, steel_like);
      const double expected = steel_like.density * measure[m] * s.dim;  // per component
      ck_assert_double_eq_tol(total(ops.M), expected, 1e-13 * expected);
      double lumped = 0;
      for (double v : ops.M_lumped) {
        ck_assert_msg(v > 0, "lumped mass must be positive (dim %d, P%d)", s.dim, degree);
        lumped += v;
      }
      ck_assert_double_eq_tol(lumped, expected, 1e-13 * expected);
      ck_assert_double_le(max_asymmetry(ops.M), 1e-15 * expected);
      ck_assert_double_le(max_asymmetry(ops.K), 1e-14);
    }
}
END_TEST

START_TEST(stiffness_annihilates_rigid_motions) {
  const std::shared_ptr<nd::Mesh> meshes[] = {ndtest::irregular_interval(9, 0.3, 2.0),
                                              ndtest::irregular_rectangle(3), ndtest::cube_of_tets()};
  for (int m = 0; m < 3; ++m)
    for (int degree = 1; degree <= 2; ++degree) {
      nd::Space s(meshes[m], degree);
      nd::DofMap dofs(s, {});
      nd::BulkOperators ops = nd::assemble_bulk(s, dofs, steel_like);
      const int d = s.dim;
      // translations e_k, and the rotations x_a e_b - x_b e_a
      std::vector<std::vector<double>> motions;
      for (int k = 0; k < d; ++k)
        motions.push_back(interpolate(s, [&](const double *, double *u) {
          for (int c = 0; c < d; ++c) u[c] = c == k;
        }));
      for (int a = 0; a < d; ++a)
        for (int b = a + 1; b < d; ++b)
          motions.push_back(interpolate(s, [&](const double *x, double *u) {
            for (int c = 0; c < d; ++c) u[c] = 0;
            u[b] = x[a];
            u[a] = -x[b];
          }));
      ck_assert_int_eq(static_cast<int>(motions.size()), d * (d + 1) / 2);
      double kmax = 0;
      for (double v : ops.K.val) kmax = std::max(kmax, std::fabs(v));
      for (auto &u : motions) {
        std::vector<double> y(u.size());
        ops.K.multiply(u.data(), y.data());
        ck_assert_msg(max_abs(y) <= 1e-13 * kmax, "K r = %g for a rigid motion (dim %d, P%d)", max_abs(y), d, degree);
      }
    }
}
END_TEST

START_TEST(p1_and_p2_agree_on_linear_fields) {
  // u = A x + c is in both spaces: the energies and the mass norm must agree
  // with each other and with the exact integrals.
  auto mesh = ndtest::irregular_interval(7, 0.3, 2.0);
  const double a = 0.7, b = -1.3;  // u = a + b x
  double energy[2], mass[2];
  for (int degree = 1; degree <= 2; ++degree) {
    nd::Space s(mesh, degree);
    nd::DofMap dofs(s, {});
    nd::BulkOperators ops = nd::assemble_bulk(s, dofs, steel_like);
    auto u = interpolate(s, [&](const double *x, double *v) { v[0] = a + b * x[0]; });
    energy[degree - 1] = quadratic_form(ops.K, u);
    mass[degree - 1] = quadratic_form(ops.M, u);
  }
  const double L0 = 0.3, L1 = 2.0;
  const double exact_energy = steel_like.young * b * b * (L1 - L0);
  const double exact_mass = steel_like.density * (std::pow(a + b * L1, 3) - std::pow(a + b * L0, 3)) / (3 * b);
  for (int k = 0; k < 2; ++k) {
    ck_assert_double_eq_tol(energy[k], exact_energy, 1e-13 * exact_energy);
    ck_assert_double_eq_tol(mass[k], exact_mass, 1e-13 * exact_mass);
  }
  // 2D: a linear field, plane strain energy is the same for P1 and P2
  auto rect = ndtest::irregular_rectangle(2);
  double e2[2];
  for (int degree = 1; degree <= 2; ++degree) {
    nd::Space s(rect, degree);
    nd::DofMap dofs(s, {});
    nd::BulkOperators ops = nd::assemble_bulk(s, dofs, steel_like);
    auto u = interpolate(s, [&](const double *x, double *v) {
      v[0] = 0.1 + 0.4 * x[0] - 0.2 * x[1];
      v[1] = -0.3 + 0.5 * x[0] + 0.25 * x[1];
    });
    e2[degree - 1] = quadratic_form(ops.K, u);
  }
  ck_assert_double_eq_tol(e2[0], e2[1], 1e-13 * e2[0]);
}
END_TEST

START_TEST(load_vector_integrates_the_body_force) {
  // sum of F over a component = f_k |Omega| for P1 and P2
  auto mesh = ndtest::irregular_interval(6, 0.3, 2.0);
  for (int degree = 1; degree <= 2; ++degree) {
    nd::Space s(mesh, degree);
    nd::DofMap dofs(s, {});
    const double f = -0.37;
    std::vector<double> F = nd::assemble_load(s, dofs, &f, {});
    double sum = 0;
    for (double v : F) sum += v;
    ck_assert_double_eq_tol(sum, f * 1.7, 1e-14);
  }
}
END_TEST

START_TEST(patch_test_constant_strain) {
  // u = B x + c has constant strain: K u must equal the load of its boundary
  // tractions sigma(u) n, side by side, exactly (P1 and P2, 2D and 3D, on
  // distorted triangles and on tetrahedra).
  const double B[3][3] = {{0.3, -0.1, 0.2}, {0.25, -0.4, 0.05}, {-0.15, 0.1, 0.35}}, c[3] = {0.1, 0.2, -0.3};
  for (int dim = 2; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree) {
      auto mesh = dim == 2 ? ndtest::irregular_rectangle(3) : ndtest::cube_of_tets();
      const double ext[3] = {dim == 2 ? 2.0 : 1.0, 1.0, 1.0};
      // one region per side, with its outward normal
      std::vector<nd::NeumannLoad> sides;
      const double lam = steel_like.lambda(dim), mu = steel_like.mu(dim);
      double trace = 0;
      for (int k = 0; k < dim; ++k) trace += B[k][k];
      for (int k = 0; k < dim; ++k)
        for (int side = 0; side < 2; ++side) {
          double lo[3], hi[3], n[3] = {0, 0, 0};
          for (int j = 0; j < 3; ++j) lo[j] = -1, hi[j] = 3;
          lo[k] = hi[k] = side ? ext[k] : 0.0;
          n[k] = side ? 1 : -1;
          const int region = 2 * k + side;
          nd::add_region_box(*mesh, region, lo, hi);
          nd::NeumannLoad nl{region, {0, 0, 0}};
          for (int a = 0; a < dim; ++a)  // sigma n = lambda tr(B) n + mu (B + B^T) n
            for (int b = 0; b < dim; ++b)
              nl.g[a] += (a == b ? lam * trace : 0.0) * n[b] + mu * (B[a][b] + B[b][a]) * n[b];
          sides.push_back(nl);
        }
      nd::Space s(mesh, degree);
      nd::DofMap dofs(s, {});
      nd::BulkOperators ops = nd::assemble_bulk(s, dofs, steel_like);
      auto u = interpolate(s, [&](const double *x, double *v) {
        for (int a = 0; a < dim; ++a) {
          v[a] = c[a];
          for (int b = 0; b < dim; ++b) v[a] += B[a][b] * x[b];
        }
      });
      std::vector<double> Ku(u.size());
      ops.K.multiply(u.data(), Ku.data());
      const std::vector<double> F = nd::assemble_load(s, dofs, nullptr, sides);
      double diff = 0;
      for (size_t i = 0; i < F.size(); ++i) diff = std::max(diff, std::fabs(Ku[i] - F[i]));
      ck_assert_msg(diff <= 1e-13 * max_abs(F), "dim %d P%d: |K u - F| = %g (|F| = %g)", dim, degree, diff, max_abs(F));
    }
}
END_TEST

// The passes by node blocks (linalg/node_blocks.hpp) have the bits of the
// CSR passes: the products pass's M U, M V, M A, K U and the energy's sums,
// stored or not, with and without A; Newton's residual A U - r and M U; an
// explicit step's K_Theta U (through the acceleration it gives). With
// consistent and lumped mass, with and without clamped nodes (whose DOFs
// all leave the numbering), 2D and 3D, P1 and P2 (P2 in 3D has rows of an
// odd number of blocks: the even and odd sums alternate by block). And the
// blocks are refused where the operators do not have their form: 1D, M
// coupling two components or differing between them, a row whose columns
// are not whole nodes. Each pass in both its forms: the scalar one and,
// where the CPU has AVX2, the wide one (which then runs by default).
START_TEST(node_block_passes_have_the_csr_bits) {
  const std::vector<std::shared_ptr<nd::Mesh>> all = meshes_with_region_7(), meshes = {all[1], all[2]};
  const std::shared_ptr<nd::Mesh> &box = all[2];
#if defined(__x86_64__) && defined(__GNUC__)
  const bool avx2 = __builtin_cpu_supports("avx2");
#else
  const bool avx2 = false;
#endif
  ck_assert(nd::simd_on() == avx2);  // on by default where the CPU has it
  int compared = 0;
  for (int simd = 0; simd <= 1; ++simd)
  for (const auto &mesh : meshes)
    for (int degree = 1; degree <= 2; ++degree)
      for (int clamped = 0; clamped <= 1; ++clamped)
        for (int lumped = 0; lumped <= 1; ++lumped) {
          nd::set_simd(simd == 1);
          ck_assert(nd::simd_on() == (simd == 1 && avx2));
          nd::Space s(mesh, degree);
          nd::Discretization d(nd::DofMap(s, clamped ? std::vector<int>{7} : std::vector<int>{}), lumped);
          ck_assert(clamped ? d.dofs.n_free < s.n_dofs() : d.dofs.n_free == s.n_dofs());
          nd::BulkOperators ops = nd::assemble_bulk(s, d.dofs, steel_like);
          d.K = ops.K;
          d.M = ops.M;
          if (lumped)  // the lumped diagonal on the same pattern, as discretize makes it
            for (int64_t i = 0; i < d.M.n; ++i)
              for (int64_t k = d.M.ptr[i]; k < d.M.ptr[i + 1]; ++k)
                d.M.val[k] = d.M.col[k] == i ? ops.M_lumped[i] : 0.0;
          const auto blocks = nd::make_node_blocks(d.K, d.M, s.dim);
          ck_assert_msg(blocks != nullptr, "%dD P%d: no blocks", s.dim, degree);
          const size_t n = static_cast<size_t>(d.K.n);
          for (int with_A = 0; with_A <= 1; ++with_A) {
            nd::State st;
            st.U.resize(n), st.V.resize(n), st.A.resize(n);
            for (size_t i = 0; i < n; ++i)  // signs and magnitudes that vary
              st.U[i] = std::sin(1.3 * i + 0.2), st.V[i] = std::cos(0.7 * i) * (i % 3 ? 1 : -40),
              st.A[i] = std::sin(0.37 * i * i);
            st.A_valid = with_A;
            nd::State by_csr = st, by_blocks = st;
            d.node_blocks = nullptr;
            nd::Products a, b;
            nd::compute_products(d, by_csr, a);
            const double e_csr = nd::mechanical_energy(d, st, nd::Products{});  // (the unstored pass)
            d.node_blocks = blocks;
            nd::compute_products(d, by_blocks, b);
            const double e_blocks = nd::mechanical_energy(d, st, nd::Products{});
            auto same = [](const std::vector<double> &x, const std::vector<double> &y) {
              return x.size() == y.size() &&
                     (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0);
            };
            ck_assert_msg(same(a.MU, b.MU) && same(a.MV, b.MV) && same(a.MA, b.MA) && same(a.KU, b.KU),
                          "%dD P%d clamped %d lumped %d A %d: the products differ", s.dim, degree, clamped, lumped,
                          with_A);
            ck_assert(a.MU.size() == n && a.MA.size() == (with_A ? n : 0));
            ck_assert(std::memcmp(&a.kinetic, &b.kinetic, sizeof(double)) == 0 &&
                      std::memcmp(&a.strain, &b.strain, sizeof(double)) == 0);
            ck_assert(std::memcmp(&e_csr, &e_blocks, sizeof(double)) == 0);
            ck_assert(a.kinetic != 0 && a.strain != 0);
            // Newton's residual A U - r and M U (multiply_pair), A = c M + K
            nd::Csr A;
            nd::csr_combine(1e3, d.M, 1.0, d.K, A);
            const auto A_blocks = nd::make_node_blocks(A, d.M, s.dim);
            ck_assert(A_blocks != nullptr);
            nd::ContactPoints none;
            nd::ContactLaw law;
            law.cp = &none;
            nd::NewtonSystem sys{&A, nullptr, &d.M, 1e3, 1.0, &law};
            std::vector<double> G_csr(n), MU_csr(n), G_blocks(n), MU_blocks(n);
            const double norm_csr = nd::newton_residual(sys, st.A, st.U, G_csr, nullptr, MU_csr);
            sys.blocks = A_blocks.get();
            const double norm_blocks = nd::newton_residual(sys, st.A, st.U, G_blocks, nullptr, MU_blocks);
            ck_assert_msg(same(G_csr, G_blocks) && same(MU_csr, MU_blocks) && norm_csr == norm_blocks,
                          "%dD P%d: the residuals differ", s.dim, degree);
            ck_assert(same(MU_csr, a.MU) && norm_csr > 0);
            // an explicit step's M A = -K_Theta U (no load, no contact; K_Theta = K)
            d.K_theta = d.K;
            if (lumped) d.M_lumped = ops.M_lumped;
            nd::State by_csr_A = st, by_blocks_A = st;
            d.node_blocks = nullptr, d.k_theta_blocks = nullptr;
            d.equilibrium_acceleration(by_csr_A, ND_SOLVER_AUTO, false);
            d.node_blocks = blocks;
            d.equilibrium_acceleration(by_blocks_A, ND_SOLVER_AUTO, false);
            ck_assert(d.k_theta_blocks != nullptr);
            ck_assert_msg(same(by_csr_A.A, by_blocks_A.A), "%dD P%d: the accelerations differ", s.dim, degree);
            d.k_theta_blocks = nullptr;
            ++compared;
          }
        }
  ck_assert_int_eq(compared, 64);
  {
    nd::Space s(all[0], 1);
    nd::BulkOperators ops = nd::assemble_bulk(s, nd::DofMap(s, {}), steel_like);
    ck_assert(nd::make_node_blocks(ops.K, ops.M, 1) == nullptr);
  }
  nd::Space s(box, 1);
  nd::BulkOperators ops = nd::assemble_bulk(s, nd::DofMap(s, {}), steel_like);
  ck_assert(nd::make_node_blocks(ops.K, ops.M, 3) != nullptr);
  nd::Csr coupled = ops.M;
  coupled.val[coupled.ptr[0] + 1] = 1e-3;  // row 0 (component 0), column 1 (component 1)
  ck_assert(nd::make_node_blocks(ops.K, coupled, 3) == nullptr);
  nd::Csr uneven = ops.M;
  uneven.val[uneven.ptr[1] + 1] *= 1.5;  // row 1's entry on the diagonal of its first block
  ck_assert(nd::make_node_blocks(ops.K, uneven, 3) == nullptr);
  nd::Csr K = ops.K, M = ops.M;  // row 0's first two columns swapped: not node 0's DOFs in order
  std::vector<int64_t> &col = K.col.mut();
  std::swap(col[0], col[1]);
  M.col = K.col;
  ck_assert(nd::make_node_blocks(K, M, 3) == nullptr);
}
END_TEST

int main(void) {
  Suite *s = suite_create("operators");
  TCase *tc = tcase_create("bulk");
  tcase_add_test(tc, the_pattern_is_the_dof_pairs_of_the_cells);
  tcase_add_test(tc, total_mass_is_rho_times_measure);
  tcase_add_test(tc, stiffness_annihilates_rigid_motions);
  tcase_add_test(tc, p1_and_p2_agree_on_linear_fields);
  tcase_add_test(tc, load_vector_integrates_the_body_force);
  tcase_add_test(tc, patch_test_constant_strain);
  tcase_add_test(tc, node_block_passes_have_the_csr_bits);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
