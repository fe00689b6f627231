// The contact rows a_q, s_q against fields with known u_n and sigma_n, and
// the tangent N'(U) against central differences of N(U), for Theta = 1, 0, -1
// and for the hybrid scheme's Phi. N is piecewise linear in U, so away from
// the kinks a central difference is exact up to round-off: the tolerance is a
// round-off bound (1e-7 relative for a step of 1e-6), not a fudge.
#include "common/error.hpp"  // before check.h, whose fail() macro would clash with nd::fail
#include <check.h>

#include <cmath>
#include <random>
#include <string>

#include "assembly/bulk.hpp"
#include "assembly/contact.hpp"
#include "solve/contact_law.hpp"
#include "nitschedyn.h"
#include "testutil.h"
#include "unit_fixtures.hpp"

namespace {

const nd::Material mat{1.7, 0.3, 1.0};

struct Scene {
  std::shared_ptr<nd::Mesh> mesh;
  std::unique_ptr<nd::Space> space;
  std::unique_ptr<nd::DofMap> dofs;
  nd::ContactPoints cp;
};

// 1D: contact at x = 0.3 against a plane at x = 0.25 (gap 0.05); 2D, 3D: the
// bottom y = 0 (z = 0) against the plane y = -0.05 (z = -0.05). Optionally
// clamped at the far end.
Scene make_scene(int dim, int degree, bool clamp) {
  Scene s;
  if (dim == 1) {
    s.mesh = ndtest::irregular_interval(6, 0.3, 2.0);
    const double lo0 = 0, hi0 = 0.31, lo1 = 1.9, hi1 = 2.1;
    nd::add_region_box(*s.mesh, 1, &lo0, &hi0);
    nd::add_region_box(*s.mesh, 2, &lo1, &hi1);
  } else if (dim == 2) {
    s.mesh = ndtest::irregular_rectangle(3);
    const double lo0[2] = {-1, -1}, hi0[2] = {3, 0}, lo1[2] = {-1, 1}, hi1[2] = {3, 2};
    nd::add_region_box(*s.mesh, 1, lo0, hi0);
    nd::add_region_box(*s.mesh, 2, lo1, hi1);
  } else {
    s.mesh = ndtest::cube_of_tets();
    const double lo0[3] = {-1, -1, -1}, hi0[3] = {2, 2, 0}, lo1[3] = {-1, -1, 1}, hi1[3] = {2, 2, 2};
    nd::add_region_box(*s.mesh, 1, lo0, hi0);
    nd::add_region_box(*s.mesh, 2, lo1, hi1);
  }
  s.space = std::make_unique<nd::Space>(s.mesh, degree);
  s.dofs = std::make_unique<nd::DofMap>(*s.space, clamp ? std::vector<int>{2} : std::vector<int>{});
  nd::ContactPlane pl{1, {0, 0, 0}, {0, 0, 0}};
  pl.point[0] = dim == 1 ? 0.25 : 0.0;
  pl.point[dim - 1] = dim == 1 ? 0.25 : -0.05;
  pl.normal[dim - 1] = 1;
  s.cp = nd::assemble_contact(*s.space, *s.dofs, mat, {pl}, 0.3);
  return s;
}

}  // namespace

START_TEST(rows_give_normal_displacement_and_stress) {
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree) {
      Scene s = make_scene(dim, degree, false);
      ck_assert_int_gt(static_cast<int>(s.cp.size()), 0);
      // u = B x + c, with n = -e_dim: u_n = -u_dim, sigma_n = lambda tr(eps) + 2 mu eps_{dd}
      const double B[3][3] = {{0.4, -0.2, 0.1}, {0.5, 0.25, -0.3}, {0.2, -0.15, 0.35}}, c[3] = {0.1, -0.3, 0.2};
      std::vector<double> U(s.space->n_dofs());
      for (int64_t i = 0; i < s.space->n_nodes; ++i)
        for (int a = 0; a < dim; ++a) {
          U[i * dim + a] = c[a];
          for (int b = 0; b < dim; ++b) U[i * dim + a] += B[a][b] * s.space->node_x(i)[b];
        }
      double trace = 0;
      for (int a = 0; a < dim; ++a) trace += B[a][a];
      const double sigma_n = mat.lambda(dim) * trace + 2 * mat.mu(dim) * B[dim - 1][dim - 1];
      double total_weight = 0;
      for (size_t q = 0; q < s.cp.size(); ++q) {
        const double *x = &s.cp.x[q * dim];
        double u_last = c[dim - 1];
        for (int b = 0; b < dim; ++b) u_last += B[dim - 1][b] * x[b];
        ck_assert_double_eq_tol(s.cp.a[q].dot(U.data()), -u_last, 1e-14);
        ck_assert_double_eq_tol(s.cp.s[q].dot(U.data()), sigma_n, 1e-12);
        ck_assert_double_eq_tol(s.cp.gap[q], 0.05, 1e-14);
        total_weight += s.cp.w[q];
      }
      // the weights integrate 1 over the contact boundary: a point, the side of
      // length 2, the unit square face
      ck_assert_double_eq_tol(total_weight, dim == 2 ? 2.0 : 1.0, 1e-14);
    }
}
END_TEST

// max over columns of |N'(U) e_j - (N(U + h e_j) - N(U - h e_j)) / 2h|, relative
double tangent_error(const Scene &s, const nd::ContactLaw &law, const std::vector<double> &U) {
  const int64_t n = s.dofs->n_free;
  nd::Csr T = nd::operator_pattern(*s.space, *s.dofs);
  law.add_tangent(U.data(), 1.0, T);
  const double h = 1e-6;
  // scale: the largest entry any point can contribute, (w/gamma) max|b| max|p|
  double err = 0, scale = 0;
  for (size_t q = 0; q < s.cp.size(); ++q) {
    double bmax = 0, pmax = 0;
    for (size_t k = 0; k < s.cp.a[q].val.size(); ++k) {
      const double a = s.cp.a[q].val[k], sg = s.cp.gamma[q] * s.cp.s[q].val[k];
      bmax = std::max(bmax, std::fabs(a - law.theta * sg));
      pmax = std::max(pmax, std::fabs(a - sg));
    }
    scale = std::max(scale, s.cp.w[q] / s.cp.gamma[q] * bmax * pmax);
  }
  std::vector<double> Up(U), Um(U), Np(n), Nm(n);
  for (int64_t j = 0; j < n; ++j) {
    Up[j] += h;
    Um[j] -= h;
    std::fill(Np.begin(), Np.end(), 0.0);
    std::fill(Nm.begin(), Nm.end(), 0.0);
    law.add_force(Up.data(), 1.0, Np.data(), nullptr);
    law.add_force(Um.data(), 1.0, Nm.data(), nullptr);
    for (int64_t i = 0; i < n; ++i) {
      const int64_t k = T.find(i, j);
      const double exact = k >= 0 ? T.val[k] : 0.0;
      err = std::max(err, std::fabs(exact - (Np[i] - Nm[i]) / (2 * h)));
    }
    Up[j] = Um[j] = U[j];
  }
  return err / scale;
}

START_TEST(tangent_matches_finite_differences) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> uni(-0.2, 0.2);
  const double thetas[] = {1.0, 0.0, -1.0};
  int checked_active = 0;
  for (int dim = 1; dim <= 3; ++dim)
    for (int degree = 1; degree <= 2; ++degree)
      for (double theta : thetas)
        for (int hybrid = 0; hybrid <= 1; ++hybrid) {
          Scene s = make_scene(dim, degree, true);
          nd::ContactLaw law{&s.cp, theta};
          std::vector<double> Pn(s.cp.size());
          const auto phi = nd::make_scheme(ND_SCHEME_HYBRID, {});
          if (hybrid) {  // alternate the sign of P^n so both branches of Phi are used
            for (size_t q = 0; q < Pn.size(); ++q) Pn[q] = (q % 2 ? -1 : 1) * (0.02 + 0.01 * q);
            law.scheme = phi.get();
            law.Pn = &Pn;
          }
          // a random U whose P_q (and P^n + P_q) stay clear of the kinks
          std::vector<double> U(s.dofs->n_free);
          for (int attempt = 0;; ++attempt) {
            ck_assert_int_lt(attempt, 1000);
            for (auto &u : U) u = uni(rng);
            bool clear = true;
            for (size_t q = 0; q < s.cp.size(); ++q) {
              const double P = law.P(q, U.data());
              clear &= std::fabs(P) > 1e-3 && (!hybrid || std::fabs(P + Pn[q]) > 1e-3);
            }
            if (clear) break;
          }
          std::vector<char> active;
          std::vector<double> N(U.size(), 0.0);
          law.add_force(U.data(), 1.0, N.data(), &active);
          for (char a : active) checked_active += a;
          const double err = tangent_error(s, law, U);
          ck_assert_msg(err < 1e-7, "dim %d P%d Theta %g hybrid %d: tangent error %g", dim, degree, theta,
                        hybrid, err);
        }
  ck_assert_int_gt(checked_active, 0);  // the test did exercise active points
}
END_TEST

START_TEST(hybrid_phi_matches_its_definition) {
  // Phi = H(P^n)[(P^n+P)/2]_+ + H(-P^n)([P^n]_+ + [P]_+)/2, H(0) = 1/2
  Scene s = make_scene(1, 1, true);
  std::vector<double> Pn(1);
  const auto hybrid = nd::make_scheme(ND_SCHEME_HYBRID, {});
  nd::ContactLaw law{&s.cp, 1.0, hybrid.get(), &Pn};
  auto pos = [](double x) { return x > 0 ? x : 0; };
  const double values[] = {-0.3, -0.1, 0.0, 0.05, 0.2};
  for (double pn : values)
    for (double P : values) {
      Pn[0] = pn;
      double v, slope;
      law.law(0, P, v, slope);
      const double H = pn > 0 ? 1 : pn < 0 ? 0 : 0.5;
      const double expected = H * pos(0.5 * (pn + P)) + (1 - H) * 0.5 * (pos(pn) + pos(P));
      ck_assert_double_eq_tol(v, expected, 1e-17);
    }
}
END_TEST

// The passes read a_q's index list for s_q (ContactLaw::dots): the
// assembled points have it (the check passes), and a point whose s_q lists
// other indices, or an s_q missing, is refused with ND_ERR_INTERNAL.
START_TEST(s_shares_a_index_list_or_is_refused) {
  for (int dim = 1; dim <= 3; ++dim) {
    Scene s = make_scene(dim, 2, true);
    nd::require_shared_index_lists(s.cp);  // (throws on failure: the test errors)
    const size_t q = s.cp.size() - 1;
    ck_assert(s.cp.size() > 0 && s.cp.s[q].idx.size() > 1);
    auto refused = [](const nd::ContactPoints &cp, const char *says) {
      try {
        nd::require_shared_index_lists(cp);
      } catch (const nd::Error &e) {
        return e.code() == ND_ERR_INTERNAL && std::string(e.what()).find(says) != std::string::npos;
      }
      return false;
    };
    nd::ContactPoints swapped = s.cp;
    std::swap(swapped.s[q].idx[0], swapped.s[q].idx[1]);
    ck_assert(refused(swapped, ("contact point " + std::to_string(q) + ":").c_str()));
    nd::ContactPoints missing = s.cp;
    missing.s.pop_back();
    ck_assert(refused(missing, "one s_q per a_q"));
  }
}
END_TEST

int main(void) {
  Suite *s = suite_create("contact");
  TCase *tc = tcase_create("rows_and_tangent");
  tcase_add_test(tc, rows_give_normal_displacement_and_stress);
  tcase_add_test(tc, tangent_matches_finite_differences);
  tcase_add_test(tc, hybrid_phi_matches_its_definition);
  tcase_add_test(tc, s_shares_a_index_list_or_is_refused);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
