// An operator and M by nodes, for the passes that multiply both (the
// products pass, solve/products.cpp: K and M; Newton's residual: A and
// M) or the operator alone (an explicit step's K_Theta U): the operator's
// dim x dim blocks and one entry of M per block, a block's column as its
// node in 4 bytes. A pass then reads about 11 bytes per entry of the
// operator in 2D and 9 in 3D, against 24 on the CSR pattern they share (two
// values, a column index), half (2D) or two thirds (3D) of whose M entries
// are zeros: M couples no two components. The copies (K's blocks, and A's
// with contact points) trade memory for the bandwidth these passes are
// bound by (docs/performance.md, "Node blocks").
// On x86-64 with AVX2 (checked at run time, common/simd.hpp) a pass runs
// four lanes wide, with the scalar pass's bits.
#pragma once
#include <cstdint>
#include <cstring>
#include <memory>
#include <type_traits>
#include <vector>

#include "common/simd.hpp"
#include "linalg/csr.hpp"

namespace nd {

struct NodeBlocks {
  int dim = 0;
  std::vector<int64_t> ptr;   // node N's blocks: [ptr[N], ptr[N + 1])
  std::vector<int32_t> node;  // a block's column node
  std::vector<double> k;      // dim * dim per block, column by column: K(dim N + c, dim J + e) at e * dim + c
  std::vector<double> m;      // one per block: M(dim N + c, dim J + c), the same for every c

  // f(i, (K U)_i, (M U)_i, (M V)_i, (M A)_i) for every row i, ascending
  // (without mass: K U only, the others 0; M A: 0 without acc), in one
  // pass: with the bits of the CSR passes (Csr::multiply, multiply_pair,
  // the products pass), which sum the entries of a row at even and odd
  // offsets apart, then add the two: an
  // entry at offset dim b + e (block b, column component e) goes to the sum
  // its offset's parity says, in the same order. M's entries off a block's
  // diagonal are stored zeros there, added as 0 x = +-0, which changes no
  // sum that starts from +0 (of finite values).
  // With sums (energy non-null): energy[0] = sum_i V_i (M V)_i and energy[1]
  // = sum_i U_i (K U)_i, rows ascending (the products pass's sums), added
  // here, where they stay in registers (in f, through references, each add
  // would wait for the store of the one before)
  template <int d, bool mass, bool acc, bool sums, class F>
  void for_rows(const double *U, const double *V, const double *A, F &&f, double *energy) const;
  // the arrays a pass reads, as pointers (locals the compiler need not
  // reload where the pass's callback stores)
  template <int d>
  struct Raw {
    static_assert(d == 2 || d == 3, "blocks of 2 or 3 components");
    int64_t nodes;
    const double *k, *m;
    const int32_t *node;
  };
  template <int d>
  Raw<d> raw() const {
    return {static_cast<int64_t>(ptr.size()) - 1, k.data(), m.data(), node.data()};
  }
#ifdef ND_AVX2
  // the same, the operator's part in AVX2 (the bits of for_rows)
  template <int d, bool mass, bool acc, bool sums, class F>
  __attribute__((target("avx2"))) void for_rows_avx2(const double *U, const double *V, const double *A, F &f,
                                                     double *energy) const;
#endif
};

// The blocks of K and M (same pattern, every row stored), or null where
// they do not have that form: dim not 2 or 3, a row count not a multiple of dim
// (clamped DOFs, each with its node's others: a multiple), a row whose
// columns are not whole nodes in order, the rows of a node with different
// columns, M coupling two components or differing between them, or more
// than 2^31 nodes.
std::shared_ptr<const NodeBlocks> make_node_blocks(const Csr &K, const Csr &M, int dim);

// b->for_rows at b's dimension (2 or 3: the only ones make_node_blocks
// makes), with the energy's sums where energy is not null (mass only);
// false, and nothing done, without blocks (b null): the caller's CSR pass
// then
template <bool mass, bool acc, class F>
bool for_node_rows(const NodeBlocks *b, const double *U, const double *V, const double *A, F &&f,
                   double *energy = nullptr) {
  if (!b) return false;
  auto run = [&](auto d, auto sums) {
    constexpr int dim = decltype(d)::value;
    constexpr bool with_sums = mass && decltype(sums)::value;
#ifdef ND_AVX2
    if (simd_on()) return b->template for_rows_avx2<dim, mass, acc, with_sums>(U, V, A, f, energy);
#endif
    b->template for_rows<dim, mass, acc, with_sums>(U, V, A, f, energy);
  };
  using two = std::integral_constant<int, 2>;
  using three = std::integral_constant<int, 3>;
  if (b->dim == 2) energy ? run(two{}, std::true_type{}) : run(two{}, std::false_type{});
  else energy ? run(three{}, std::true_type{}) : run(three{}, std::false_type{});
  return true;
}

namespace node_blocks_detail {

typedef double Pair __attribute__((vector_size(16)));

template <int dim>
struct Sums {
  // [even, odd]: K U of the node's rows 0 and 1 in one pair, row 2's alone;
  // per row component c, (M U, M V) and M A
  Pair ku01[2] = {}, uv[dim][2] = {};
  double ku2[2] = {}, ma[dim][2] = {};
};

// the block of a column node (U, V, A at its DOFs; k: the block column by
// column), at an even or odd block offset within the row
template <int dim, bool mass, bool acc, bool odd_block>
inline __attribute__((always_inline)) void add_block(Sums<dim> &s, const double *k, double m, const double *U,
                                                     const double *V, const double *A) {
#pragma GCC unroll 3
  for (int e = 0; e < dim; ++e) {
    const int h = ((odd_block ? dim : 0) + e) & 1;
    Pair k01;
    std::memcpy(&k01, k + e * dim, sizeof k01);  // rows 0 and 1 at column e
    s.ku01[h] += k01 * Pair{U[e], U[e]};
    if (dim == 3) s.ku2[h] += k[e * dim + 2] * U[e];
    if (mass) s.uv[e][h] += Pair{m, m} * Pair{U[e], V[e]};
    if (mass && acc) s.ma[e][h] += m * A[e];
  }
}

#ifdef ND_AVX2
// The wide form's sums, set to zero by for_rows_avx2 (a constructor would
// not be AVX2 code).
// 2D, where a block's column component e is its parity h: k[0] = (row 0,
// row 1) x (column 0, column 1), mu[0] = (M U, M V) x (row 0, row 1), ma =
// M A's rows.
// 3D, per parity h, the lanes 0-2 the rows: k[h] (Sums' ku01[h] and
// ku2[h]), mu[h], mv[h], ma3[h] (Sums' uv[c][h] and ma[c][h]).
struct WideSums {
  __m256d k[2], mu[2], mv[2], ma3[2];
  __m128d ma;
};

// rows 0-2 of a column of three (the fourth lane 0: never read past it)
__attribute__((target("avx2"), always_inline)) inline __m256d three(const double *x) {
  return _mm256_maskload_pd(x, _mm256_setr_epi64x(-1, -1, -1, 0));
}

// the operator's part of a block of a column node (U at its DOFs; k: the
// block column by column), at an even or odd block offset within the row
template <int dim, bool odd_block>
__attribute__((target("avx2"), always_inline)) inline void add_k_avx2(WideSums &s, const double *k, const double *U) {
  if (dim == 2) {
    // (K00, K10, K01, K11) (U0, U0, U1, U1)
    const __m256d u = _mm256_permute4x64_pd(_mm256_castpd128_pd256(_mm_loadu_pd(U)), 0x50);
    s.k[0] += _mm256_loadu_pd(k) * u;
    return;
  }
#pragma GCC unroll 3
  for (int e = 0; e < 3; ++e) {
    const int h = ((odd_block ? 3 : 0) + e) & 1;
    // column e; the fourth lane (the next column's first entry) never read
    const __m256d col = e < 2 ? _mm256_loadu_pd(k + 3 * e) : three(k + 6);
    s.k[h] += col * _mm256_broadcast_sd(U + e);
  }
}

// 2D: M's part of a block
template <bool acc>
__attribute__((target("avx2"), always_inline)) inline void add_m_2d(WideSums &s, double m, const double *U,
                                                                    const double *V, const double *A) {
  const __m256d m4 = _mm256_set1_pd(m);
  s.mu[0] += m4 * _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(U)), _mm_loadu_pd(V), 1);
  if (acc) s.ma += _mm256_castpd256_pd128(m4) * _mm_loadu_pd(A);
}

// 3D: M's part of two blocks at an even and the next odd offset (odd null:
// the row's last block, alone). Row c of an even block sums at parity c & 1,
// of an odd one at the other: one blend per parity puts each lane's term
// where the scalar pass adds it. Alone, the other lanes add +0, which
// changes no sum (a sum from +0 is never -0).
__attribute__((target("avx2"), always_inline)) inline void add_m_3d(__m256d *sums, double m0, const double *x0,
                                                                    double m1, const double *x1) {
  const __m256d p0 = _mm256_set1_pd(m0) * three(x0);
  const __m256d p1 = x1 ? _mm256_set1_pd(m1) * three(x1) : _mm256_setzero_pd();
  sums[0] += _mm256_blend_pd(p0, p1, 0b1010);  // rows 0, 2 even; row 1 odd
  sums[1] += _mm256_blend_pd(p1, p0, 0b1010);  // row 1 even; rows 0, 2 odd
}
#endif

}  // namespace node_blocks_detail

template <int dim, bool mass, bool acc, bool sums, class F>
void NodeBlocks::for_rows(const double *U, const double *V, const double *A, F &&f, double *energy) const {
  using namespace node_blocks_detail;
  const Raw<dim> b = raw<dim>();
  double kinetic = 0, strain = 0;
  for (int64_t N = 0; N < b.nodes; ++N) {
    Sums<dim> t;
    // block jj at an even or odd block offset within the row
    auto add = [&](auto odd, int64_t jj) __attribute__((always_inline)) {
      const int64_t c = static_cast<int64_t>(b.node[jj]) * dim;
      add_block<dim, mass, acc, decltype(odd)::value>(t, b.k + jj * dim * dim, b.m[jj], U + c, mass ? V + c : nullptr,
                                                      acc ? A + c : nullptr);
    };
    int64_t j = ptr[N];
    const int64_t end = ptr[N + 1];
    for (; j + 1 < end; j += 2) {  // (for odd dim, odd blocks start at odd offsets)
      add(std::false_type{}, j);
      add(std::true_type{}, j + 1);
    }
    if (j < end) add(std::false_type{}, j);
    const Pair ku01 = t.ku01[0] + t.ku01[1];
#pragma GCC unroll 3
    for (int c = 0; c < dim; ++c) {
      const Pair uv = t.uv[c][0] + t.uv[c][1];
      const int64_t i = dim * N + c;
      const double ku = c < 2 ? ku01[c] : t.ku2[0] + t.ku2[1];
      if (sums) kinetic += V[i] * uv[1], strain += U[i] * ku;
      f(i, ku, uv[0], uv[1], mass && acc ? t.ma[c][0] + t.ma[c][1] : 0.0);
    }
  }
  if (sums) energy[0] = kinetic, energy[1] = strain;
}

#ifdef ND_AVX2
template <int dim, bool mass, bool acc, bool sums, class F>
__attribute__((target("avx2"))) void NodeBlocks::for_rows_avx2(const double *U, const double *V, const double *A,
                                                                F &f, double *energy) const {
  using namespace node_blocks_detail;
  const Raw<dim> b = raw<dim>();
  double kinetic = 0, strain = 0;
  auto at = [&](const double *x, int64_t jj) __attribute__((always_inline)) {
    return x + static_cast<int64_t>(b.node[jj]) * dim;
  };
  if (dim == 2) {
    auto add = [&](WideSums &t, int64_t jj) __attribute__((target("avx2"), always_inline)) {
      add_k_avx2<2, false>(t, b.k + jj * 4, at(U, jj));
      if (mass) add_m_2d<acc>(t, b.m[jj], at(U, jj), at(V, jj), acc ? at(A, jj) : nullptr);
    };
    auto rows = [&](const WideSums &t, int64_t N) __attribute__((target("avx2"), always_inline)) {
      // (Sums' other parity of uv and ma: +0, which changes no sum)
      const __m128d ku = _mm256_castpd256_pd128(t.k[0]) + _mm256_extractf128_pd(t.k[0], 1);
      const __m128d mu = _mm256_castpd256_pd128(t.mu[0]), mv = _mm256_extractf128_pd(t.mu[0], 1);
#pragma GCC unroll 2
      for (int c = 0; c < 2; ++c) {  // (unrolled: a lane at a variable index is read through memory)
        const int64_t i = 2 * N + c;
        if (sums) kinetic += V[i] * mv[c], strain += U[i] * ku[c];
        f(i, ku[c], mu[c], mv[c], mass && acc ? t.ma[c] : 0.0);
      }
    };
    auto zero = [](WideSums &t) __attribute__((target("avx2"), always_inline)) {
      t.k[0] = t.mu[0] = _mm256_setzero_pd();
      t.ma = _mm_setzero_pd();
    };
    // Two nodes at a time, their blocks side by side: each node's sums
    // still add its blocks one after the other (their bits), but the two
    // chains of dependent adds overlap. The rows then in order. Only in 2D:
    // in 3D (8 sums a node) two nodes spill registers and run slower.
    int64_t N = 0;
    for (; N + 1 < b.nodes; N += 2) {
      WideSums t0, t1;
      zero(t0), zero(t1);
      int64_t j0 = ptr[N], j1 = ptr[N + 1];
      const int64_t end0 = ptr[N + 1], end1 = ptr[N + 2];
      for (; j0 < end0 && j1 < end1; ++j0, ++j1) add(t0, j0), add(t1, j1);
      for (; j0 < end0; ++j0) add(t0, j0);
      for (; j1 < end1; ++j1) add(t1, j1);
      rows(t0, N);
      rows(t1, N + 1);
    }
    if (N < b.nodes) {
      WideSums t;
      zero(t);
      for (int64_t j = ptr[N]; j < ptr[N + 1]; ++j) add(t, j);
      rows(t, N);
    }
    _mm256_zeroupper();
    if (sums) energy[0] = kinetic, energy[1] = strain;
    return;
  }
  for (int64_t N = 0; N < b.nodes; ++N) {
    WideSums t;
    t.k[0] = t.k[1] = t.mu[0] = t.mu[1] = t.mv[0] = t.mv[1] = t.ma3[0] = t.ma3[1] = _mm256_setzero_pd();
    t.ma = _mm_setzero_pd();
    int64_t j = ptr[N];
    const int64_t end = ptr[N + 1];
    for (; j < end; j += 2) {
      const bool pair = j + 1 < end;
      add_k_avx2<3, false>(t, b.k + j * 9, at(U, j));
      if (pair) add_k_avx2<3, true>(t, b.k + (j + 1) * 9, at(U, j + 1));
      if (mass) {
        const double m0 = b.m[j], m1 = pair ? b.m[j + 1] : 0;
        add_m_3d(t.mu, m0, at(U, j), m1, pair ? at(U, j + 1) : nullptr);
        add_m_3d(t.mv, m0, at(V, j), m1, pair ? at(V, j + 1) : nullptr);
        if (acc) add_m_3d(t.ma3, m0, at(A, j), m1, pair ? at(A, j + 1) : nullptr);
      }
    }
    // the lanes read without a store (a wide store read back narrow stalls
    // the loads on store forwarding)
    const __m256d ku = t.k[0] + t.k[1], mu = t.mu[0] + t.mu[1], mv = t.mv[0] + t.mv[1], ma = t.ma3[0] + t.ma3[1];
#pragma GCC unroll 3
    for (int c = 0; c < 3; ++c) {
      const int64_t i = 3 * N + c;
      if (sums) kinetic += V[i] * mv[c], strain += U[i] * ku[c];
      f(i, ku[c], mu[c], mv[c], mass && acc ? ma[c] : 0.0);
    }
  }
  _mm256_zeroupper();
  if (sums) energy[0] = kinetic, energy[1] = strain;
}
#endif

}  // namespace nd
