// The contact columns Z_q = A^{-1} b_q on split rows (fast/contact_columns.hpp)
// under mpiexec -n 1, 2, 4: held at a rank's own rows and the points' DOFs,
// they give what whole columns give (G, p_q . Z_j, the sums of columns once
// completed), the same on every rank, and a column receives from the other
// ranks only its values at the points' DOFs they own.
//
// A is c M + K on a 2D P1 rectangle (SPD, 242 unknowns); the rows are split
// in PETSc's even blocks, the rank of each row its block's; the contact rows
// are synthetic, each spread over the unknowns so that every rank's block
// holds some of a point's DOFs and others do not.
//
// Also on this matrix: the contact points a Newton pass reads on split rows
// (its own and those touching its rows, exchanged with their owners alone);
// the rows Newton reads on split rows, kept by a
// refactoring tangent's solves; and a factorization refused by one rank alone (a
// non-finite value in its rows) is refused on every rank, none left waiting
// in the assembly (parallel/agreement.hpp), and the next one succeeds.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "assembly/bulk.hpp"
#include "capi/handles.hpp"  // before check.h, whose fail() macro hides nd::fail
#include "common/error.hpp"
#include "linalg/factorization.hpp"
#include "parallel/communicator_mpi.hpp"
#include "parallel/share.hpp"
#include "problem/discretization.hpp"
#include "fast/contact_columns.hpp"
#include "solve/contact_law.hpp"
#include "solve/newton.hpp"
#include "fast/tangents.hpp"
#include "unit_drop.hpp"
#include "unit_fixtures.hpp"
// last: check.h's fail() macro would clash with nd::fail and std::ios::fail
#include <check.h>

#include "nitschedyn_mpi.h"
#include "testutil_mpi.h"

namespace {

int g_rank = 0, g_size = 1;

using ndtest::spd_matrix;

// nq points, point q on 6 unknowns spread over [0, n) (ascending, distinct)
nd::ContactPoints synthetic_points(int64_t n, int nq) {
  nd::ContactPoints cp;
  for (int q = 0; q < nq; ++q) {
    nd::SparseRow a, s;
    for (int k = 0; k < 6; ++k) a.idx.push_back((q * 5 + k * (n / 6)) % n);
    std::sort(a.idx.begin(), a.idx.end());
    for (size_t k = 0; k < a.idx.size(); ++k) {
      a.val.push_back(std::sin(1.3 * q + 0.7 * static_cast<double>(k)));
      s.val.push_back(std::cos(0.4 * q - 1.1 * static_cast<double>(k)));
    }
    s.idx = a.idx;
    cp.a.push_back(a);
    cp.s.push_back(s);
    cp.gamma.push_back(0.05 + 0.01 * q);
    cp.w.push_back(1.0);
  }
  return cp;
}

// nq points appended to cp, each on 6 consecutive unknowns spread over [0, n)
// (most within one rank's rows)
void add_local_points(nd::ContactPoints &cp, int64_t n, int nq) {
  for (int q = 0; q < nq; ++q) {
    nd::ContactPoints one = synthetic_points(6, 1);
    for (int64_t &i : one.a[0].idx) i += q * (n - 6) / (nq - 1);
    one.s[0].idx = one.a[0].idx;
    cp.a.push_back(one.a[0]), cp.s.push_back(one.s[0]), cp.gamma.push_back(0.03), cp.w.push_back(0.5);
  }
}

// PETSc's even split of n rows (linalg/petsc.cpp make_layout, blocks of 1)
std::vector<int> even_owner(int64_t n) {
  std::vector<int> owner(static_cast<size_t>(n));
  const int64_t share = n / g_size, extra = n % g_size;
  for (int r = 0, i = 0; r < g_size; ++r)
    for (int64_t k = 0; k < share + (r < extra ? 1 : 0); ++k) owner[static_cast<size_t>(i++)] = r;
  return owner;
}

bool same_on_all_ranks(const std::vector<double> &v) {
  return nd_test_same_on_all_ranks(v.data(), static_cast<int>(sizeof(double) * v.size())) != 0;
}

// the larger of two gaps, NaN if either is (std::max passes over a NaN)
double worse(double a, double b) { return std::isnan(a) || std::isnan(b) ? NAN : std::max(a, b); }

double max_abs_diff(const std::vector<double> &a, const std::vector<double> &b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = worse(d, std::fabs(a[i] - b[i]));
  return d;
}
double max_abs(const std::vector<double> &a) {
  double m = 0;
  for (double x : a) m = std::max(m, std::fabs(x));
  return m;
}

// MUMPS (direct: to round-off) and GAMG (a Krylov solve to rtol 1e-12: the
// 1e-9 that unit_linalg allows its solves) against CHOLMOD on whole columns
void check_split_columns(int solver, double tol) {
  const nd::Csr A = spd_matrix(10);
  const int64_t n = A.n;
  const nd::ContactPoints cp = synthetic_points(n, 9);
  const double theta = -1;  // b_q != p_q: G is not symmetric
  nd::CommunicatorPtr comm = nd::communicator_from_c(MPI_COMM_WORLD);
  nd::Counters counters;
  const std::vector<int> owner = even_owner(n);
  auto rows = nd::make_share(comm, owner, &counters);
  nd::DofGeometry g;
  g.comm = comm;  // row_end < 0: the even split
  auto split = nd::make_factorization(solver, A, nd::Structure::SymmetricPositiveDefinite, &counters, &g);
  split->factor(A, nd::Structure::SymmetricPositiveDefinite);
  auto whole = nd::make_factorization(ND_SOLVER_CHOLMOD, A, nd::Structure::SymmetricPositiveDefinite);
  whole->factor(A, nd::Structure::SymmetricPositiveDefinite);
  nd::ContactColumns on_rows(*split, n, 100, rows.get()), all(*whole, n, 100);
  on_rows.bind(cp, theta);
  all.bind(cp, theta);

  // the points' DOFs this rank does not own: what each column receives
  std::vector<char> at_point(static_cast<size_t>(n), 0);
  for (const nd::SparseRow &a : cp.a)
    for (int64_t i : a.idx) at_point[i] = 1;
  int64_t halo = 0;
  for (int64_t i = 0; i < n; ++i) halo += at_point[i] && owner[i] != g_rank;

  const std::vector<int64_t> S = {0, 2, 3, 5, 8}, T = {1, 2, 4, 5, 6, 7};
  const int64_t r0 = counters.values_received, s0 = counters.solves;
  on_rows.require(S);
  all.require(S);
  ck_assert_int_eq(counters.solves - s0, 5);
  ck_assert_msg(nd_test_on_all_ranks(counters.values_received - r0 == 5 * halo),
                "rank %d: %lld values received for 5 columns, %lld points' DOFs of other ranks", g_rank,
                static_cast<long long>(counters.values_received - r0), static_cast<long long>(halo));
  on_rows.require(T);  // 4 new columns
  all.require(T);
  ck_assert_int_eq(on_rows.computed(), 9);
  ck_assert(nd_test_on_all_ranks(counters.values_received - r0 == 9 * halo));

  const std::vector<double> G = on_rows.G(T), G_all = all.G(T);
  ck_assert_msg(nd_test_on_all_ranks(max_abs_diff(G, G_all) <= tol * max_abs(G_all)), "G off by %g",
                max_abs_diff(G, G_all) / max_abs(G_all));
  ck_assert(same_on_all_ranks(G));  // every rank decides its Newton steps on the same bits
  std::vector<double> dots, dots_all;
  for (size_t q = 0; q < cp.size(); ++q)
    for (int64_t j : T) dots.push_back(on_rows.dot(q, j)), dots_all.push_back(all.dot(q, j));
  ck_assert(nd_test_on_all_ranks(max_abs_diff(dots, dots_all) <= tol * max_abs(dots_all)));
  ck_assert(same_on_all_ranks(dots));

  // sums of columns: right at the rank's rows, then completed from the others
  std::vector<double> f = {0.5, 0.0, -1.25, 2.0, 0.75, -0.3}, x0(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) x0[i] = std::cos(0.37 * static_cast<double>(i));
  {
    std::vector<double> x = x0, x_all = x0;
    on_rows.subtract_blocked(T, f.data(), x.data());
    all.subtract_blocked(T, f.data(), x_all.data());
    const int64_t before = counters.values_received;
    on_rows.complete(x.data());
    int64_t own = 0;
    for (int o : owner) own += o == g_rank;
    ck_assert(nd_test_on_all_ranks(counters.values_received - before == (g_size > 1 ? n - own : 0)));
    ck_assert_msg(nd_test_on_all_ranks(max_abs_diff(x, x_all) <= tol * max_abs(x_all)), "sum off by %g",
                  max_abs_diff(x, x_all) / max_abs(x_all));
    ck_assert(same_on_all_ranks(x));
  }
  // a solve kept at the held rows (the condensed Newton's y0), then completed
  {
    std::vector<double> y = x0, y_all = x0;
    const int64_t before = counters.values_received;
    ck_assert(on_rows.solve_held(y.data()) == (g_size > 1));
    ck_assert(nd_test_on_all_ranks(counters.values_received - before == halo));
    on_rows.complete(y.data());
    whole->solve(y_all.data());
    ck_assert_msg(nd_test_on_all_ranks(max_abs_diff(y, y_all) <= tol * max_abs(y_all)), "y0 off by %g",
                  max_abs_diff(y, y_all) / max_abs(y_all));
    ck_assert(same_on_all_ranks(y));
  }

  // the low-rank tangent on the split columns: T^{-1} x, T = A + B D P^T
  // (6 of the 9 points active at U = 0: those with a negative gap)
  nd::ContactPoints cp_gaps = cp;
  for (size_t q = 0; q < cp.size(); ++q) cp_gaps.gap.push_back(q % 3 == 0 ? 1.0 : -1.0);
  const nd::ContactLaw law{&cp_gaps, theta};
  const std::vector<double> U(static_cast<size_t>(n), 0.0);
  nd::ContactColumns lr_rows(*split, n, 100, rows.get()), lr_all(*whole, n, 100);
  const nd::Structure gen = nd::Structure::General;
  auto T_rows = nd::make_lowrank_tangent(A, *split, solver, gen, -1, -1, nullptr, &g, &lr_rows);
  auto T_all = nd::make_lowrank_tangent(A, *whole, ND_SOLVER_CHOLMOD, gen, -1, -1, nullptr, nullptr, &lr_all);
  std::vector<double> y = x0, y_all = x0;
  T_rows->solve(law, 10.0, U.data(), true, y.data());
  T_all->solve(law, 10.0, U.data(), true, y_all.data());
  ck_assert_int_eq(T_rows->stats.lowrank, 1);
  ck_assert(nd_test_on_all_ranks(lr_rows.computed() == 6));
  ck_assert_msg(nd_test_on_all_ranks(max_abs_diff(y, y_all) <= tol * max_abs(y_all)), "T^-1 x off by %g",
                max_abs_diff(y, y_all) / max_abs(y_all));
  ck_assert(same_on_all_ranks(y));
  // the same with a distributed state's rows (the rank's rows, their
  // columns, the points' DOFs): T^{-1} x right there, NaN elsewhere, and its
  // solve of A receives only those rows, nothing gathered after (several
  // ranks: one has no rows to split)
  if (rows) {
    const std::vector<int64_t> state_rows = nd::newton_held_rows(A, *rows, cp);
    nd::ContactColumns lr_state(*split, n, 100, rows.get(), &state_rows);
    auto T_state = nd::make_lowrank_tangent(A, *split, solver, gen, -1, -1, nullptr, &g, &lr_state);
    std::vector<char> held(static_cast<size_t>(n), 0);
    int64_t others = 0;
    for (int64_t i : state_rows) held[i] = 1, others += owner[i] != g_rank;
    std::vector<double> z = x0;
    const int64_t before = counters.values_received, columns = 6;
    T_state->solve(law, 10.0, U.data(), true, z.data());
    ck_assert_int_eq(T_state->stats.lowrank, 1);
    // the 6 columns and the solve of A, each the state's rows of other ranks
    ck_assert_msg(nd_test_on_all_ranks(counters.values_received - before == (columns + 1) * others),
                  "rank %d: %lld values received, %lld held rows of others", g_rank,
                  static_cast<long long>(counters.values_received - before), static_cast<long long>(others));
    double off = 0;
    bool nan_elsewhere = true;
    for (int64_t i = 0; i < n; ++i) {
      if (held[i])
        off = worse(off, std::fabs(z[i] - y_all[i]));
      else
        nan_elsewhere &= std::isnan(z[i]);
    }
    ck_assert_msg(nd_test_on_all_ranks(off <= tol * max_abs(y_all) && nan_elsewhere),
                  "rank %d: T^-1 x at the state's rows %g off", g_rank, off / max_abs(y_all));
  }
  if (g_rank == 0)
    std::printf("%s on %d rank(s): 9 columns received %lld values each (rank 0; whole: %lld), G within %.1e\n",
                split->name(), g_size, static_cast<long long>(halo),
                static_cast<long long>(g_size > 1 ? n - std::count(owner.begin(), owner.end(), 0) : 0),
                max_abs_diff(G, G_all) / max_abs(G_all));
}

START_TEST(columns_on_own_rows_are_the_whole_columns) { check_split_columns(ND_SOLVER_PETSC_MUMPS, 1e-12); }
END_TEST

START_TEST(columns_on_own_rows_with_gamg) { check_split_columns(ND_SOLVER_PETSC_GAMG, 1e-9); }
END_TEST

// The rows Newton reads of its iterate on split rows (newton_held_rows): a
// rank's rows, every column of an entry in them, and the contact points'
// DOFs. A refactoring tangent that keeps them receives exactly their values
// on other ranks per solve with the refactored tangent, right there (against
// CHOLMOD's refactoring tangent on whole columns), and NaN elsewhere (no
// stale value can be read unseen).
// A on a pattern that also couples each point's DOFs, as K_Theta's does (the
// contact tangent adds its terms there)
nd::Csr with_points(const nd::Csr &A, const nd::ContactPoints &cp) {
  std::vector<std::vector<int64_t>> rows(static_cast<size_t>(A.n));
  for (int64_t r = 0; r < A.n; ++r) rows[r].assign(A.col.begin() + A.ptr[r], A.col.begin() + A.ptr[r + 1]);
  for (const nd::SparseRow &a : cp.a)
    for (int64_t i : a.idx) rows[i].insert(rows[i].end(), a.idx.begin(), a.idx.end());
  nd::Csr B = nd::csr_from_rows(std::move(rows));
  for (int64_t r = 0; r < A.n; ++r)
    for (int64_t k = A.ptr[r]; k < A.ptr[r + 1]; ++k) B.val[static_cast<size_t>(B.find(r, A.col[k]))] = A.val[k];
  return B;
}

void check_held_rows(int solver, double tol) {
  const nd::Csr A0 = spd_matrix(10);
  const nd::ContactPoints cp = synthetic_points(A0.n, 9);
  const nd::Csr A = with_points(A0, cp);
  const int64_t n = A.n;
  nd::CommunicatorPtr comm = nd::communicator_from_c(MPI_COMM_WORLD);
  nd::Counters counters;
  const std::vector<int> owner = even_owner(n);
  auto rows = nd::make_share(comm, owner, &counters);
  std::vector<char> read(static_cast<size_t>(n), 0);
  for (int64_t r = 0; r < n; ++r)  // entry by entry
    for (int64_t k = A.ptr[r]; k < A.ptr[r + 1]; ++k)
      if (owner[r] == g_rank) read[r] = read[A.col[k]] = 1;
  for (const nd::SparseRow &a : cp.a)
    for (int64_t i : a.idx) read[i] = 1;
  std::vector<int64_t> expected;
  int64_t others = 0;
  for (int64_t i = 0; i < n; ++i)
    if (read[i]) expected.push_back(i), others += owner[i] != g_rank;
  const std::vector<int64_t> held = rows ? nd::newton_held_rows(A, *rows, cp) : std::vector<int64_t>();
  if (rows) ck_assert_msg(held == expected, "rank %d: %zu rows held, %zu expected", g_rank, held.size(), expected.size());

  nd::DofGeometry g;
  g.comm = comm;
  auto split = nd::make_factorization(solver, A, nd::Structure::SymmetricPositiveDefinite, &counters, &g);
  split->factor(A, nd::Structure::SymmetricPositiveDefinite);
  auto whole = nd::make_factorization(ND_SOLVER_CHOLMOD, A, nd::Structure::SymmetricPositiveDefinite);
  whole->factor(A, nd::Structure::SymmetricPositiveDefinite);
  const nd::Structure spd = nd::Structure::SymmetricPositiveDefinite;  // Theta = 1
  auto tangent = nd::make_refactoring_tangent(A, *split, solver, spd, &counters, &g, held);
  auto tangent_all = nd::make_refactoring_tangent(A, *whole, ND_SOLVER_CHOLMOD, spd);
  ck_assert(rows ? tangent->held() && *tangent->held() == held : tangent->held() == nullptr);
  std::vector<double> x(static_cast<size_t>(n)), x_all(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) x[i] = x_all[i] = std::cos(0.3 * static_cast<double>(i));
  // 6 of the 9 points active at U = 0 (a negative gap): T = A + kappa N'(U), refactored
  nd::ContactPoints cp_gaps = cp;
  for (size_t q = 0; q < cp.size(); ++q) cp_gaps.gap.push_back(q % 3 == 0 ? 1.0 : -1.0);
  const nd::ContactLaw law{&cp_gaps, 1.0};
  const std::vector<double> U(static_cast<size_t>(n), 0.0);
  const int64_t r0 = counters.values_received;
  tangent->solve(law, 10.0, U.data(), true, x.data());
  tangent_all->solve(law, 10.0, U.data(), true, x_all.data());
  ck_assert_msg(nd_test_on_all_ranks(counters.values_received - r0 == (rows ? others : 0)),
                "rank %d: %lld values received, %lld held rows of other ranks", g_rank,
                static_cast<long long>(counters.values_received - r0), static_cast<long long>(others));
  double off = 0;
  bool nan_elsewhere = true;
  for (int64_t i = 0; i < n; ++i) {
    if (!rows || read[i])
      off = worse(off, std::fabs(x[i] - x_all[i]));
    else
      nan_elsewhere &= std::isnan(x[i]);
  }
  ck_assert_msg(nd_test_on_all_ranks(off <= tol * max_abs(x_all) && nan_elsewhere), "rank %d: %g off at the held rows",
                g_rank, off / max_abs(x_all));
  if (g_rank == 0)
    std::printf("%s on %d rank(s): a held solve received %lld values (rank 0; whole: %lld), %.1e off\n", split->name(),
                g_size, static_cast<long long>(counters.values_received - r0),
                static_cast<long long>(g_size > 1 ? n - std::count(owner.begin(), owner.end(), 0) : 0),
                off / max_abs(x_all));
}

START_TEST(a_refactoring_tangent_keeps_the_rows_newton_reads) {
  check_held_rows(ND_SOLVER_PETSC_MUMPS, 1e-12);
  check_held_rows(ND_SOLVER_PETSC_GAMG, 1e-9);
}
END_TEST

// 9 points spread over every rank's rows and 12 on 6 consecutive unknowns
// each (most of them within one rank's rows), on the unknowns of
// spd_matrix(10); its rows in PETSc's even split, point q owned by rank q
// mod the ranks (so a rank also owns points that touch none of its rows),
// and the points a Newton pass on split rows reads (null on one rank). No
// gaps yet.
struct PointsOnRanks {
  const nd::Csr A0 = spd_matrix(10);
  const int64_t n = A0.n;
  nd::ContactPoints cp;
  nd::CommunicatorPtr comm = nd::communicator_from_c(MPI_COMM_WORLD);
  nd::Counters counters;  // the shares' (values received)
  std::vector<int> owner = even_owner(n), point_owner;
  std::shared_ptr<const nd::Share> rows;
  std::shared_ptr<const nd::Halo> halo;
  PointsOnRanks() : cp(synthetic_points(n, 9)) {
    add_local_points(cp, n, 12);
    rows = nd::make_share(comm, owner, &counters);
    for (size_t q = 0; q < cp.size(); ++q) point_owner.push_back(static_cast<int>(q) % g_size);
    cp.share = nd::make_share(comm, point_owner, &counters);
    halo = rows ? nd::contact_point_halo(cp, *rows) : nullptr;
  }
  PointsOnRanks(const PointsOnRanks &) = delete;  // the shares keep &counters
  PointsOnRanks &operator=(const PointsOnRanks &) = delete;
};

// A Newton pass of the refactoring tangent on split rows (ContactLaw::halo,
// slice 10) reads the points that are the rank's own or whose rows touch its
// rows, each received from its owner alone: P_q there bitwise the gathered
// pass's (NaN elsewhere), the rank's rows of N(U) and N'(U) bitwise, the
// active-set verdicts and the contact-free check the same on every rank as
// from every point. The points' owners here ignore the rows (q mod the
// ranks), so a rank also owns points that touch none of its rows.
START_TEST(a_newton_pass_reads_the_points_touching_its_rows) {
  PointsOnRanks on;
  const int64_t n = on.n;
  nd::ContactPoints &cp = on.cp;
  nd::Counters &counters = on.counters;
  const std::vector<int> &owner = on.owner, &point_owner = on.point_owner;
  const std::shared_ptr<const nd::Halo> &halo = on.halo;
  const nd::Csr A = with_points(on.A0, cp);
  const size_t nq = cp.size();
  for (size_t q = 0; q < nq; ++q) cp.gap.push_back(q % 3 == 0 ? 1.0 : -1.0);  // 6 active near U = 0
  ck_assert(static_cast<bool>(halo) == (g_size > 1));
  std::vector<int64_t> expected;  // entry by entry
  int64_t others = 0;
  for (size_t q = 0; q < nq; ++q) {
    bool reads = point_owner[q] == g_rank;
    for (int64_t i : cp.a[q].idx) reads |= owner[i] == g_rank;
    if (reads) expected.push_back(static_cast<int64_t>(q)), others += point_owner[q] != g_rank;
  }
  if (halo) ck_assert_msg(halo->read == expected, "rank %d: %zu points read, %zu expected", g_rank, halo->read.size(), expected.size());

  std::vector<double> U(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) U[i] = 0.05 * std::sin(0.9 * static_cast<double>(i));
  nd::ContactLaw all{&cp, -1.0};  // Theta = -1: b_q != p_q
  nd::ContactLaw mine = all;
  mine.halo = halo.get();
  std::vector<double> P_all, P_mine;
  all.P_read(U.data(), P_all);  // (no halo: P_all, every point gathered)
  const int64_t r0 = counters.values_received, v0 = counters.point_values_received;
  mine.P_read(U.data(), P_mine);
  const int64_t got = counters.values_received - r0;
  ck_assert_msg(nd_test_on_all_ranks(got == (halo ? others : 0) && counters.point_values_received - v0 == got),
                "rank %d: %lld values received, %lld points of other ranks read", g_rank, static_cast<long long>(got),
                static_cast<long long>(others));
  std::vector<char> is_read(nq, halo ? 0 : 1);
  for (int64_t q : expected) is_read[q] = 1;
  bool right = true;
  for (size_t q = 0; q < nq; ++q)
    right &= is_read[q] ? std::memcmp(&P_all[q], &P_mine[q], sizeof(double)) == 0 : std::isnan(P_mine[q]);
  ck_assert_msg(nd_test_on_all_ranks(right), "rank %d: P_q read differs from the gathered pass", g_rank);

  // N(U) and the active sets
  std::vector<double> y_all(static_cast<size_t>(n), 0.0), y_mine(static_cast<size_t>(n), 0.0);
  std::vector<char> act_all, act_mine;
  all.add_force(U.data(), 10.0, y_all.data(), &act_all);
  mine.add_force(U.data(), 10.0, y_mine.data(), &act_mine);
  bool same_rows = true, same_active = true;
  for (int64_t i = 0; i < n; ++i)
    if (!halo || owner[i] == g_rank) same_rows &= std::memcmp(&y_all[i], &y_mine[i], sizeof(double)) == 0;
  for (size_t q = 0; q < nq; ++q) same_active &= !is_read[q] || act_all[q] == act_mine[q];
  ck_assert_msg(nd_test_on_all_ranks(same_rows && same_active), "rank %d: N(U) or the active set differs", g_rank);
  int active = 0;
  for (char a : act_all) active += a != 0;
  ck_assert_msg(active > 0 && active < static_cast<int>(nq), "%d of %zu points active: the test needs both", active, nq);
  const std::vector<char> none(nq, 0);
  const std::vector<char> *previous_sets[] = {&none, &act_all};
  for (const std::vector<char> *previous : previous_sets) {
    bool any_all, changed_all, any_mine, changed_mine;
    all.summarize(act_all, *previous, any_all, changed_all);
    mine.summarize(act_mine, *previous, any_mine, changed_mine);
    ck_assert(nd_test_on_all_ranks(any_mine == any_all && changed_mine == changed_all));
    ck_assert(any_all && changed_all == (previous == &none));
  }
  // N'(U) on the rank's rows
  nd::Csr T_all = A, T_mine = A;
  all.add_tangent(U.data(), 10.0, T_all);
  mine.add_tangent(U.data(), 10.0, T_mine);
  for (int64_t i = 0; i < n; ++i)
    if (!halo || owner[i] == g_rank)
      for (int64_t k = A.ptr[i]; k < A.ptr[i + 1]; ++k) same_rows &= T_all.val[k] == T_mine.val[k];
  ck_assert_msg(nd_test_on_all_ranks(same_rows), "rank %d: the tangent's rows differ", g_rank);
  // a change, or an active point, on the last rank's points alone is seen by every rank
  const size_t last = static_cast<size_t>(g_size - 1);  // (owned by rank g_size - 1)
  std::vector<char> flipped = act_all;
  flipped[last] = !flipped[last];
  bool any = false, changed = false;
  mine.summarize(act_mine, flipped, any, changed);
  ck_assert_msg(nd_test_on_all_ranks(any && changed), "rank %d: a change on rank %d unseen", g_rank, g_size - 1);
  ck_assert(nd_test_on_all_ranks(!mine.contact_free(U) && !all.contact_free(U)));
  for (double &g : cp.gap) g = 10;  // far: only point `last` touches the obstacle
  cp.gap[last] = -1;
  mine.add_force(U.data(), 10.0, y_mine.data(), &act_mine);
  mine.summarize(act_mine, act_mine, any, changed);
  ck_assert_msg(nd_test_on_all_ranks(any && !changed), "rank %d: the active point on rank %d unseen", g_rank, g_size - 1);
  ck_assert(nd_test_on_all_ranks(!mine.contact_free(U) && !all.contact_free(U)));
  cp.gap[last] = 10;  // contact-free everywhere
  ck_assert(nd_test_on_all_ranks(mine.contact_free(U) && all.contact_free(U)));
  if (g_rank == 0)
    std::printf("%d rank(s): a Newton pass on rank 0 reads %zu of %zu points, %lld received (a gather: %lld)\n", g_size,
                expected.size(), nq, static_cast<long long>(got),
                static_cast<long long>(nq - static_cast<size_t>(std::count(point_owner.begin(), point_owner.end(), 0))));
}
END_TEST

// With a distributed state (ContactLaw::held, slice 12) each rank bounds its
// own held points, and the bound that shows a Newton start contact-free is
// counted (ND_STAT_CONTACT_BOUNDS) only when every rank's bound held: the
// job's count, the same on every rank. Here one point, held by the last
// rank alone (its own, on that rank's rows only), has P_q^n = -1e-14: not
// busy, but within the bound's margin of the obstacle, so that rank's bound
// fails while every other rank's holds. The start is contact-free on every
// rank and no rank counts it (a count per rank would count it on the others).
START_TEST(a_bound_counts_when_every_rank_held_it) {
  PointsOnRanks on;
  nd::ContactPoints &cp = on.cp;
  const size_t nq = cp.size();
  cp.gap.assign(nq, 10.0);  // every point far
  nd::set_bounds(cp);
  auto held = on.halo ? nd::held_points(cp, *on.halo) : nullptr;
  const int last = g_size - 1;
  int64_t lone = -1;  // read by the last rank alone
  for (size_t q = 0; q < nq && lone < 0; ++q) {
    bool alone = on.point_owner[q] == last;
    for (int64_t i : cp.a[q].idx) alone &= on.owner[i] == last;
    if (alone) lone = static_cast<int64_t>(q);
  }
  ck_assert(lone >= 0);
  if (held)
    ck_assert(nd_test_on_all_ranks(std::binary_search(held->points.begin(), held->points.end(), lone) ==
                                   (g_rank == last)));
  std::vector<double> U(static_cast<size_t>(on.n));
  for (int64_t i = 0; i < on.n; ++i) U[i] = 0.05 * std::sin(0.9 * static_cast<double>(i));
  nd::ContactLaw at_n{&cp, 1.0};  // P_q^n at U^n = U, every point on every rank
  at_n.local = true;
  std::vector<double> Pn;
  at_n.P_all(U.data(), Pn);
  nd::ContactLaw law{&cp, 1.0};
  law.counters = &on.counters;
  law.halo = on.halo.get();
  law.held = held.get();
  law.Pn = &Pn, law.Un = U.data();

  const int64_t b0 = on.counters.contact_bounds;
  ck_assert(nd_test_on_all_ranks(law.contact_free(U)));
  ck_assert_msg(nd_test_on_all_ranks(on.counters.contact_bounds - b0 == 1), "rank %d: %lld bounds counted, 1 expected",
                g_rank, static_cast<long long>(on.counters.contact_bounds - b0));

  double sa, ss;
  law.dots(static_cast<size_t>(lone), U.data(), sa, ss);
  cp.gap[static_cast<size_t>(lone)] = sa - cp.gamma[static_cast<size_t>(lone)] * ss + 1e-14;
  at_n.P_all(U.data(), Pn);
  const double P_lone = Pn[static_cast<size_t>(lone)];
  ck_assert_msg(P_lone < 0 && P_lone > -1e-13, "P_q^n = %g at the lone point", P_lone);
  const int64_t b1 = on.counters.contact_bounds;
  ck_assert(nd_test_on_all_ranks(law.contact_free(U)));  // no point busy
  ck_assert_msg(nd_test_on_all_ranks(on.counters.contact_bounds == b1),
                "rank %d: %lld bound(s) counted; one that failed on rank %d counts on no rank", g_rank,
                static_cast<long long>(on.counters.contact_bounds - b1), last);
  if (g_rank == 0)
    std::printf("%d rank(s): the bound counted once with every point far, not with point %lld (rank %d's) at "
                "P_q^n = %.1e\n",
                g_size, static_cast<long long>(lone), last, P_lone);
}
END_TEST

// GAMG keeps the hierarchy it set up for one Newton tangent for the next
// (Factorization::refactor) while it serves: the solves still reach their
// tolerance (against CHOLMOD), no set-up is counted; a matrix the kept
// hierarchy serves badly (c M + K with another c: another time step) marks
// it stale after a solve of more than twice the first solve's iterations,
// and the next refactor sets up anew; a solve that does not converge with
// it (an indefinite preconditioner) sets up for its matrix and solves again,
// counted as a factorization. And a solve started from a guess
// (Factorization::solve_from) reaches the same tolerance in fewer
// iterations; a direct backend ignores the guess.
START_TEST(a_kept_hierarchy_serves_until_it_does_not) {
  nd::Space space(ndtest::irregular_rectangle(10), 1);
  nd::DofMap dofs(space, {});
  const nd::BulkOperators ops = nd::assemble_bulk(space, dofs, nd::Material{50, 0.25, 1});
  const int64_t n = ops.M.n;
  nd::ContactPoints cp;  // 12 points, each on 6 consecutive unknowns
  add_local_points(cp, n, 12);
  // T = c M + K + kappa N'(0), the points q with q mod 3 != skip active
  auto tangent = [&](double c, int skip) {
    nd::Csr A;
    nd::csr_combine(c, ops.M, 1.0, ops.K, A);
    nd::Csr T = with_points(A, cp);
    nd::ContactPoints at = cp;
    for (int q = 0; q < 12; ++q) at.gap.push_back(q % 3 == skip ? 1.0 : -1.0);
    const nd::ContactLaw law{&at, 1.0};
    const std::vector<double> U(static_cast<size_t>(n), 0.0);
    law.add_tangent(U.data(), 10.0, T);
    return T;
  };
  nd::CommunicatorPtr comm = nd::communicator_from_c(MPI_COMM_WORLD);
  nd::Counters counters;
  nd::DofGeometry g;  // the rigid-body modes GAMG is given in a problem
  g.comm = comm;
  nd::locate_unknowns(space, dofs, g);
  const nd::Structure spd = nd::Structure::SymmetricPositiveDefinite;
  std::vector<double> b(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) b[i] = std::cos(0.3 * static_cast<double>(i));
  // solves T x = b, checked against CHOLMOD; the Krylov iterations and the set-ups it made
  struct Solved {
    int64_t iterations, set_ups;
  };
  auto solve = [&](const nd::Factorization &f, const nd::Csr &T, const char *what) {
    auto exact = nd::make_factorization(ND_SOLVER_CHOLMOD, T, spd);
    exact->factor(T, spd);
    std::vector<double> x = b, x_exact = b;
    exact->solve(x_exact.data());
    const int64_t its = counters.krylov_iterations, set_ups = counters.factorizations;
    f.solve(x.data());
    const double off = ndtest::rel_diff(x, x_exact);
    ck_assert_msg(nd_test_on_all_ranks(off <= 1e-9), "%s: %g off CHOLMOD's", what, off);
    return Solved{counters.krylov_iterations - its, counters.factorizations - set_ups};
  };
  auto refactor = [&](nd::Factorization &f, const nd::Csr &T) {  // whether it set up, checked against the count
    const int64_t before = counters.factorizations;
    const bool fresh = f.refactor(T, spd);
    ck_assert(counters.factorizations - before == (fresh ? 1 : 0));
    return fresh;
  };

  // a stiffness-dominated tangent (a long time step), then another active set: kept
  const nd::Csr T1 = tangent(1e-2, 0), T2 = tangent(1e-2, 1), T3 = tangent(1e6, 0), T4 = tangent(1e4, 0);
  auto f = nd::make_factorization(ND_SOLVER_PETSC_GAMG, T1, spd, &counters, &g);
  ck_assert(refactor(*f, T1));
  const Solved first = solve(*f, T1, "the first tangent");
  ck_assert(!refactor(*f, T2));
  const Solved nearby = solve(*f, T2, "another active set, kept");
  ck_assert(nearby.set_ups == 0 && nearby.iterations <= 2 * first.iterations);
  ck_assert(!refactor(*f, T2));  // not stale
  ck_assert(solve(*f, T2, "kept again").set_ups == 0);
  // a mass-dominated matrix (a short time step): the kept hierarchy serves it
  // badly, the next refactor sets up anew
  ck_assert(!refactor(*f, T3));
  const Solved stale = solve(*f, T3, "a short step's matrix, kept");
  ck_assert_msg(stale.set_ups == 0 && stale.iterations > 2 * first.iterations, "%lld iterations, %lld set-ups",
                static_cast<long long>(stale.iterations), static_cast<long long>(stale.set_ups));
  ck_assert(refactor(*f, T3));
  const Solved renewed = solve(*f, T3, "a short step's matrix, set up");
  ck_assert(renewed.set_ups == 0 && renewed.iterations < stale.iterations);

  // the other way: a hierarchy for c = 1e4 makes CG on c = 1e-2 stop (an
  // indefinite preconditioner): the solve sets up for its matrix and succeeds
  auto f2 = nd::make_factorization(ND_SOLVER_PETSC_GAMG, T4, spd, &counters, &g);
  ck_assert(refactor(*f2, T4));
  const Solved mass = solve(*f2, T4, "a mass-dominated tangent");
  ck_assert(!refactor(*f2, T1));
  const Solved retried = solve(*f2, T1, "a stiff tangent, the kept hierarchy failing");
  ck_assert_msg(retried.set_ups == 1, "%lld set-ups in the solve", static_cast<long long>(retried.set_ups));
  ck_assert(!refactor(*f2, T2));  // the new hierarchy is kept for the next
  ck_assert(solve(*f2, T2, "the next stiff tangent").set_ups == 0);
  // a solve from a guess (a time step's predictor): the same tolerance, fewer
  // iterations the closer it is; a direct backend ignores it
  std::vector<double> x_exact = b, near(static_cast<size_t>(n)), x_from = b, x_zero = b;
  {
    auto exact = nd::make_factorization(ND_SOLVER_CHOLMOD, T2, spd);
    exact->factor(T2, spd);
    exact->solve(x_exact.data());
  }
  for (int64_t i = 0; i < n; ++i) near[i] = x_exact[i] * (1 + 1e-4 * std::sin(static_cast<double>(i)));
  int64_t its = counters.krylov_iterations, solves = counters.solves;
  f2->solve(x_zero.data());
  const int64_t from_zero = counters.krylov_iterations - its;
  its = counters.krylov_iterations;
  f2->solve_from(x_from.data(), near.data());
  const int64_t from_near = counters.krylov_iterations - its;
  ck_assert(counters.solves - solves == 2);
  const double off = ndtest::rel_diff(x_from, x_exact);
  ck_assert_msg(nd_test_on_all_ranks(off <= 1e-9 && from_near < from_zero), "from a guess: %g off, %lld iterations "
                "against %lld from 0", off, static_cast<long long>(from_near), static_cast<long long>(from_zero));
  // (CHOLMOD: MUMPS on several ranks is not bitwise reproducible from solve to solve)
  auto direct = nd::make_factorization(ND_SOLVER_CHOLMOD, T2, spd, &counters);
  direct->factor(T2, spd);
  std::vector<double> y = b, y_from = b, junk(static_cast<size_t>(n), 1e300);
  direct->solve(y.data());
  direct->solve_from(y_from.data(), junk.data());
  ck_assert(nd_test_on_all_ranks(std::memcmp(y.data(), y_from.data(), sizeof(double) * y.size()) == 0));
  // what Newton asks before it keeps a predictor for the step (NewtonSystem::guess), through the counting wrapper
  ck_assert(f2->starts_from_guess() && !direct->starts_from_guess());
  if (g_rank == 0)
    std::printf("GAMG on %d rank(s): %lld CG iterations from 0, %lld from a guess 1e-4 off\n", g_size,
                static_cast<long long>(from_zero), static_cast<long long>(from_near));
  if (g_rank == 0)
    std::printf("GAMG on %d rank(s), CG iterations: a tangent %lld, another active set %lld (kept); a short step's "
                "matrix %lld kept, %lld set up; a mass-dominated tangent %lld, then a stiff one %lld (failed with "
                "its hierarchy, set up in the solve)\n",
                g_size, static_cast<long long>(first.iterations), static_cast<long long>(nearby.iterations),
                static_cast<long long>(stale.iterations), static_cast<long long>(renewed.iterations),
                static_cast<long long>(mass.iterations), static_cast<long long>(retried.iterations));
}
END_TEST

// Split rows: each rank's copy of A is read at its own rows only, so a
// non-finite value there is seen by that rank alone.
START_TEST(a_matrix_refused_on_one_rank_is_refused_on_every_rank) {
  const nd::Csr A = spd_matrix(10);
  const int64_t n = A.n;
  nd::CommunicatorPtr comm = nd::communicator_from_c(MPI_COMM_WORLD);
  const int last = g_size - 1;  // owns row n - 1 in PETSc's even split
  nd::Csr bad = A;
  if (g_rank == last) {  // a diagonal entry of the last rank's last row
    const int64_t i = n - 1;
    bad.val[static_cast<size_t>(bad.find(i, i))] = NAN;
  }
  for (int solver : {ND_SOLVER_PETSC_MUMPS, ND_SOLVER_PETSC_GAMG}) {
    nd::DofGeometry g;
    g.comm = comm;
    auto f = nd::make_factorization(solver, A, nd::Structure::SymmetricPositiveDefinite, nullptr, &g);
    int code = ND_OK;
    std::string what;
    try {
      f->factor(bad, nd::Structure::SymmetricPositiveDefinite);
    } catch (const nd::Error &e) {
      code = e.code(), what = e.what();
    }
    ck_assert_msg(nd_test_on_all_ranks(code == ND_ERR_NONFINITE_STATE), "solver %d, rank %d: %d (%s)", solver, g_rank,
                  code, what.c_str());
    const bool says = g_rank == last ? what.find("non-finite entry") != std::string::npos
                                     : what.find("on another rank") != std::string::npos;
    ck_assert_msg(nd_test_on_all_ranks(says), "solver %d, rank %d: %s", solver, g_rank, what.c_str());
    // the same factorization with the good values: A x = b solved on every rank
    f->factor(A, nd::Structure::SymmetricPositiveDefinite);
    std::vector<double> x(static_cast<size_t>(n)), b(static_cast<size_t>(n)), Ax(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i) x[i] = std::sin(0.1 * static_cast<double>(i));
    A.multiply(x.data(), b.data());
    f->solve(b.data());
    ck_assert_msg(nd_test_on_all_ranks(max_abs_diff(b, x) <= 1e-9 * max_abs(x)), "solver %d: the solve after it is %.3g off",
                  solver, max_abs_diff(b, x));
  }
}
END_TEST

// Columns asked for different sets on different ranks (a bug upstream) fail
// on every rank before any collective solve, instead of pairing the ranks'
// block solves wrongly (MUMPS then corrupted memory); the cache serves the
// next, agreed set.
START_TEST(columns_of_sets_that_differ_between_ranks_are_refused) {
  const nd::Csr A = spd_matrix(10);
  const int64_t n = A.n;
  const nd::ContactPoints cp = synthetic_points(n, 9);
  nd::CommunicatorPtr comm = nd::communicator_from_c(MPI_COMM_WORLD);
  nd::Counters counters;
  auto rows = nd::make_share(comm, even_owner(n), &counters);
  nd::DofGeometry g;
  g.comm = comm;
  auto f = nd::make_factorization(ND_SOLVER_PETSC_MUMPS, A, nd::Structure::SymmetricPositiveDefinite, &counters, &g);
  f->factor(A, nd::Structure::SymmetricPositiveDefinite);
  nd::ContactColumns columns(*f, n, 100, rows.get());
  columns.bind(cp, 1.0);
  std::vector<int64_t> S = {0, 2, 3};
  if (g_rank == g_size - 1 && g_size > 1) S.push_back(5);
  int code = ND_OK;
  try {
    columns.require(S);
  } catch (const nd::Error &e) {
    code = e.code();
  }
  ck_assert_msg(nd_test_on_all_ranks(code == (g_size > 1 ? ND_ERR_INTERNAL : ND_OK)), "rank %d: %d", g_rank, code);
  ck_assert(nd_test_on_all_ranks(columns.computed() == (g_size > 1 ? 0 : 3)));
  columns.require({0, 2, 3, 5});
  ck_assert(nd_test_on_all_ranks(columns.computed() == 4));
}
END_TEST

// Where the unknowns sit (DofGeometry::x, component) is built for GAMG, the
// one solver that reads it (its rigid-body modes), and for no other: on
// split rows for the rank's rows only, each row the whole geometry's at its
// unknown; choosing another solver drops it, and GAMG again builds it again.
START_TEST(the_unknowns_are_located_for_gamg_only) {
  for (int dim : {2, 3}) {
    nd_problem p = ndtest::drop_scene(dim, 1, ndtest::kSchemes[2], 1.0);
    nd::Problem &pb = p->problem;
    nd::DofGeometry whole;  // every unknown's, made apart
    nd::locate_unknowns(pb.space(), pb.discretization().dofs, whole);
    const int64_t n = pb.discretization().dofs.n_free;
    ck_assert(whole.located && static_cast<int64_t>(whole.component.size()) == n);
    ck_assert(!pb.discretization().geometry.located && pb.discretization().geometry.x.empty());  // AUTO: none
    ND_OK_OR_FAIL(nd_problem_set_comm(p, MPI_COMM_WORLD));
    for (int solver : {ND_SOLVER_PETSC_MUMPS, ND_SOLVER_PETSC_GAMG, ND_SOLVER_PETSC_MUMPS, ND_SOLVER_PETSC_GAMG}) {
      ND_OK_OR_FAIL(nd_problem_set_linear_solver(p, solver));
      ND_OK_OR_FAIL(nd_step(p));  // (GAMG solves with the modes of what it was given)
      const nd::Discretization &d = pb.discretization();
      const nd::DofGeometry &g = d.geometry;
      if (solver != ND_SOLVER_PETSC_GAMG) {
        ck_assert_msg(!g.located && g.x.empty() && g.component.empty(), "dim %d: located for MUMPS", dim);
        continue;
      }
      ck_assert_msg(g.located && g.own_rows_only == d.rows_split && d.rows_split == (g_size > 1), "dim %d", dim);
      const nd::RowSet rows = nd::own_rows(d.rows_split ? d.rows.get() : nullptr);
      const int64_t m = rows.size(n);
      ck_assert_msg(static_cast<int64_t>(g.component.size()) == m && static_cast<int64_t>(g.x.size()) == m * dim,
                    "dim %d, rank %d: %zu unknowns described, %lld rows", dim, g_rank, g.component.size(),
                    (long long)m);
      for (int64_t k = 0; k < m; ++k) {
        const int64_t u = rows[k];
        ck_assert_int_eq(g.component[k], whole.component[u]);
        ck_assert(std::memcmp(&g.x[k * dim], &whole.x[u * dim], sizeof(double) * dim) == 0);
      }
    }
    ND_OK_OR_FAIL(nd_problem_destroy(&p));
  }
}
END_TEST

}  // namespace

int main(int argc, char **argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SINGLE, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  Suite *s = suite_create("mpi_contact_columns");
  TCase *tc = tcase_create("columns");
  tcase_set_timeout(tc, 300);
  tcase_add_test(tc, columns_on_own_rows_are_the_whole_columns);
  tcase_add_test(tc, columns_on_own_rows_with_gamg);
  tcase_add_test(tc, a_refactoring_tangent_keeps_the_rows_newton_reads);
  tcase_add_test(tc, a_newton_pass_reads_the_points_touching_its_rows);
  tcase_add_test(tc, a_bound_counts_when_every_rank_held_it);
  tcase_add_test(tc, a_kept_hierarchy_serves_until_it_does_not);
  tcase_add_test(tc, columns_of_sets_that_differ_between_ranks_are_refused);
  tcase_add_test(tc, the_unknowns_are_located_for_gamg_only);
  suite_add_tcase(s, tc);
  TCase *agreement = tcase_create("agreement");
  tcase_set_timeout(agreement, 300);
  tcase_add_test(agreement, a_matrix_refused_on_one_rank_is_refused_on_every_rank);
  suite_add_tcase(s, agreement);
  return nd_test_run_on_ranks(s);
}
