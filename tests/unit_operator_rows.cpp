// The operators of a rank's rows (issue 15, slice 5: discretize with an
// Ownership): with the cells cut in 2 and 3 slabs, each part holds exactly
// its nodes' rows of M, K and K_Theta, every entry bitwise the whole
// operator's (the same cells' contributions added in the same order, the
// Nitsche terms of every contact point that reaches the row), and stores no
// other row (n_own + 1 row pointers, not n + 1); over the parts every entry
// is held once. So do the step matrix c M + K_Theta formed from them and the
// refactored Newton tangent (every contact point's rank-one term added, rows
// not held left out).
// 2D P1/P2 and 3D P1 drops (the contact rows cross the cuts), Theta = 1
// and -1.
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <vector>

#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "common/counters.hpp"
#include "parallel/ownership.hpp"
#include "problem/discretization.hpp"
#include "solve/contact_law.hpp"
#include "testutil.h"
#include "unit_drop.hpp"

namespace {

// Row i of `part` is row i of `whole` (own) or not stored (not own).
void check_row(const nd::Csr &whole, const nd::Csr &part, int64_t i, bool own, const char *what) {
  ck_assert_msg(part.part && !whole.part, "%s: the part is not stored as one", what);
  const int64_t at = part.slot(i);
  if (!own) {
    ck_assert_msg(at < 0, "%s: row %lld is not this part's but is stored", what, (long long)i);
    return;
  }
  ck_assert_msg(at >= 0, "%s: row %lld is this part's but not stored", what, (long long)i);
  const int64_t b = part.ptr[at], e = part.ptr[at + 1], wb = whole.ptr[i], we = whole.ptr[i + 1];
  ck_assert_msg(e - b == we - wb, "%s: row %lld holds %lld entries, the whole row %lld", what, (long long)i,
                (long long)(e - b), (long long)(we - wb));
  ck_assert_msg(std::memcmp(&part.col[b], &whole.col[wb], sizeof(int64_t) * (e - b)) == 0,
                "%s: row %lld has other columns", what, (long long)i);
  ck_assert_msg(std::memcmp(&part.val[b], &whole.val[wb], sizeof(double) * (e - b)) == 0,
                "%s: row %lld has other values", what, (long long)i);
}

// c M + K_Theta + sum_q f_q b_q p_q^T (the refactored tangent's terms, every
// point active with a weight of its own)
nd::Csr tangent(const nd::Discretization &d) {
  nd::Csr T;
  nd::csr_combine(40.0, d.M, 1.0, d.K_theta, T);
  std::vector<double> b, p;
  for (size_t q = 0; q < d.contact.size(); ++q) nd::add_point_tangent(d.contact, d.theta, q, 0.5 + 0.01 * q, T, b, p);
  return T;
}

void rows_of_each_part(int dim, int degree, double theta) {
  nd_problem p = ndtest::drop_scene(dim, degree, ndtest::kSchemes[3], theta);
  nd::Problem &pb = p->problem;
  const nd::Discretization &whole = pb.discretization();
  const nd::Space &space = pb.space();
  ck_assert(!whole.rows_split && whole.contact.size() > 0);
  const int64_t n = whole.dofs.n_free;
  const nd::Csr T_whole = tangent(whole);
  for (int parts : {2, 3}) {
    const std::vector<int> cells = nd::slab_partition(*space.mesh, parts);
    std::vector<int> holders(static_cast<size_t>(n), 0);
    size_t held[3] = {0, 0, 0};
    bool nitsche_across = false;  // a contact point whose rows reach two parts
    for (int rank = 0; rank < parts; ++rank) {
      const nd::Ownership own = nd::ownership_of_cells(space, cells, rank, parts);
      nd::Counters counters;
      const auto d = nd::discretize(space, pb.definition(), &counters, &own);
      ck_assert(d->rows_split);
      const nd::Csr T = tangent(*d);
      std::vector<char> mine(static_cast<size_t>(n), 0);
      for (int64_t dof = 0; dof < space.n_dofs(); ++dof)
        if (const int64_t r = d->dofs.free[dof]; r >= 0) mine[r] = own.node_owner[dof / dim] == rank;
      int64_t rows = 0;
      for (int64_t i = 0; i < n; ++i) {
        check_row(whole.M, d->M, i, mine[i], "M");
        check_row(whole.K, d->K, i, mine[i], "K");
        check_row(whole.K_theta, d->K_theta, i, mine[i], "K_Theta");
        check_row(T_whole, T, i, mine[i], "tangent");
        holders[i] += mine[i];
        rows += mine[i];
      }
      ck_assert_msg(rows > 0 && rows < n, "%d parts: part %d holds %lld of %lld rows", parts, rank, (long long)rows,
                    (long long)n);
      // its row pointers are its rows', not n + 1 (issue 15: they fall with the ranks)
      for (const nd::Csr *A : std::initializer_list<const nd::Csr *>{&d->M, &d->K, &d->K_theta, &T})
        ck_assert_int_eq(static_cast<int64_t>(A->ptr.size()), rows + 1);
      for (const nd::SparseRow &s : whole.contact.s) {
        bool in = false, out = false;
        for (int64_t i : s.idx) (mine[i] ? in : out) = true;
        nitsche_across |= in && out;
      }
      held[0] += d->M.val.size(), held[1] += d->K.val.size(), held[2] += d->K_theta.val.size();
      ck_assert_int_eq(counters.matrix_entries,
                       static_cast<int64_t>(d->M.val.size() + d->K.val.size() + d->K_theta.val.size()));
    }
    for (int64_t i = 0; i < n; ++i)
      ck_assert_msg(holders[i] == 1, "row %lld held by %d parts", (long long)i, holders[i]);
    ck_assert_uint_eq(held[0], whole.M.val.size());
    ck_assert_uint_eq(held[1], whole.K.val.size());
    ck_assert_uint_eq(held[2], whole.K_theta.val.size());
    ck_assert_msg(nitsche_across, "%dD P%d, %d parts: no contact point reaches two parts", dim, degree, parts);
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}

START_TEST(each_part_holds_its_rows_bitwise) {
  for (double theta : {1.0, -1.0}) {
    rows_of_each_part(2, 1, theta);
    rows_of_each_part(2, 2, theta);
    rows_of_each_part(3, 1, theta);
  }
}
END_TEST

// A pass over a part's rows (Csr::for_rows) reads its rows at their places:
// the products on its rows are the whole operator's, bitwise, with
// multiply and multiply_pair. A pass over other rows (all of them, or a list
// that is not the part's) is refused with ND_ERR_INTERNAL, not read out of
// bounds.
START_TEST(a_pass_over_a_part_reads_its_rows_or_is_refused) {
  nd_problem p = ndtest::drop_scene(2, 2, ndtest::kSchemes[3], 1.0);
  nd::Problem &pb = p->problem;
  const nd::Discretization &whole = pb.discretization();
  const nd::Space &space = pb.space();
  const int64_t n = whole.dofs.n_free;
  const std::vector<int> cells = nd::slab_partition(*space.mesh, 2);
  const nd::Ownership own = nd::ownership_of_cells(space, cells, 1, 2);
  nd::Counters counters;
  const auto d = nd::discretize(space, pb.definition(), &counters, &own);
  const nd::Csr &K = d->K_theta;
  const nd::RowSet rows{K.held.data(), static_cast<int64_t>(K.held.size())};
  const size_t size = static_cast<size_t>(n);
  std::vector<double> x(size);
  std::vector<double> y(size);
  std::vector<double> y_whole(size);
  std::vector<double> z_whole(size);
  for (int64_t i = 0; i < n; ++i) x[i] = std::sin(0.7 * static_cast<double>(i)) + 0.01 * static_cast<double>(i % 5);
  whole.K_theta.multiply(x.data(), y_whole.data());
  whole.M.multiply(x.data(), z_whole.data());
  K.multiply(x.data(), y.data(), rows);
  std::vector<double> y2(size);
  std::vector<double> z2(size);
  nd::multiply_pair(
      K, x.data(), d->M, x.data(),
      [&](int64_t i, double Kx, double Mx) {
        y2[i] = Kx;
        z2[i] = Mx;
      },
      rows);
  for (int64_t i : K.held) {
    ck_assert_msg(std::memcmp(&y[i], &y_whole[i], sizeof(double)) == 0, "row %lld: %.17g, whole %.17g",
                  (long long)i, y[i], y_whole[i]);
    ck_assert(std::memcmp(&y2[i], &y_whole[i], sizeof(double)) == 0);
    ck_assert(std::memcmp(&z2[i], &z_whole[i], sizeof(double)) == 0);
  }
  // refused: every row, and as many rows as the part's but others (shifted by one)
  std::vector<int64_t> shifted(K.held.begin(), K.held.end());
  for (int64_t &i : shifted) i = (i + 1) % n;
  for (const nd::RowSet &other : {nd::RowSet{}, nd::RowSet{shifted.data(), static_cast<int64_t>(shifted.size())}}) {
    int code = ND_OK;
    try {
      K.multiply(x.data(), y.data(), other);
    } catch (const nd::Error &e) {
      code = e.code();
    }
    ck_assert_int_eq(code, ND_ERR_INTERNAL);
    code = ND_OK;
    try {
      nd::multiply_pair(K, x.data(), d->M, x.data(), [](int64_t, double, double) {}, other);
    } catch (const nd::Error &e) {
      code = e.code();
    }
    ck_assert_int_eq(code, ND_ERR_INTERNAL);
  }
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

// The operators of one problem (M, K, K_Theta, A = c M + K_Theta) share
// one index array (linalg/csr.hpp's SharedIndex): one copy of the pattern,
// not four. Writing a shared array copies it first, so the others keep
// theirs.
START_TEST(operators_share_one_pattern) {
  nd_problem p = ndtest::drop_scene(2, 2, ndtest::kSchemes[3], 1.0);
  ND_OK_OR_FAIL(nd_step(p));
  nd::Problem &pb = p->problem;
  const nd::Discretization &d = pb.discretization();
  const nd::Csr &A = pb.integrator()->A;
  for (const nd::Csr *op : {&d.K, &d.K_theta, &A}) {
    ck_assert(op->col.shared_with(d.M.col));
    ck_assert(op->ptr.shared_with(d.M.ptr));
  }
  nd::Csr copy = A;
  const std::vector<int64_t> before = A.col.vec();
  copy.col.mut()[0] += 1;  // a copy written apart
  ck_assert(!copy.col.shared_with(A.col));
  ck_assert(A.col.vec() == before && d.M.col.shared_with(A.col));
  ck_assert_int_eq(copy.col[0], before[0] + 1);
  ND_OK_OR_FAIL(nd_problem_destroy(&p));
}
END_TEST

}  // namespace

int main(void) {
  Suite *s = suite_create("operator_rows");
  TCase *tc = tcase_create("core");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, each_part_holds_its_rows_bitwise);
  tcase_add_test(tc, a_pass_over_a_part_reads_its_rows_or_is_refused);
  tcase_add_test(tc, operators_share_one_pattern);
  suite_add_tcase(s, tc);
  return nd_test_run(s);
}
