// An operator and M by nodes, for the passes that multiply both (the
// products pass, monitor/energies.cpp: K and M; Newton's residual: A and
// M) or the operator alone (an explicit step's K_Theta U): the operator's
// dim x dim blocks and one entry of M per block, a block's column as its
// node in 4 bytes. A pass then reads about 11 bytes per entry of the
// operator in 2D and 9 in 3D, against 24 on the CSR pattern they share (two
// values, a column index), half (2D) or two thirds (3D) of whose M entries
// are zeros: M couples no two components. The copies cost memory: measured
// peaks 123 -> 145 MB on disk P2 h = 0.5, 226 -> 246 MB on ball P2 h = 4
// (K's blocks, and A's with contact points).
#pragma once
#include <cstdint>
#include <cstring>
#include <memory>
#include <type_traits>
#include <vector>

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
  template <int d, bool mass, bool acc, class F>
  void for_rows(const double *U, const double *V, const double *A, F &&f) const;
};

// The blocks of K and M (same pattern, every row stored), or null where
// they do not have that form: dim not 2 or 3, a row count not a multiple of dim
// (clamped DOFs, each with its node's others: a multiple), a row whose
// columns are not whole nodes in order, the rows of a node with different
// columns, M coupling two components or differing between them, or more
// than 2^31 nodes.
std::shared_ptr<const NodeBlocks> make_node_blocks(const Csr &K, const Csr &M, int dim);

// b->for_rows at b's dimension (2 or 3: the only ones make_node_blocks
// makes); false, and nothing done, without blocks (b null): the caller's
// CSR pass then
template <bool mass, bool acc, class F>
bool for_node_rows(const NodeBlocks *b, const double *U, const double *V, const double *A, F &&f) {
  if (!b) return false;
  if (b->dim == 2) b->template for_rows<2, mass, acc>(U, V, A, f);
  else b->template for_rows<3, mass, acc>(U, V, A, f);
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

}  // namespace node_blocks_detail

template <int dim, bool mass, bool acc, class F>
void NodeBlocks::for_rows(const double *U, const double *V, const double *A, F &&f) const {
  using namespace node_blocks_detail;
  static_assert(dim == 2 || dim == 3, "blocks of 2 or 3 components");
  const int64_t nodes = static_cast<int64_t>(ptr.size()) - 1;
  const double *kk = k.data(), *mm = m.data();
  const int32_t *nn = node.data();
  constexpr int64_t bb = dim * dim;
  for (int64_t N = 0; N < nodes; ++N) {
    Sums<dim> t;
    // block jj at an even or odd block offset within the row
    auto add = [&](auto odd, int64_t jj) __attribute__((always_inline)) {
      const int64_t c = static_cast<int64_t>(nn[jj]) * dim;
      add_block<dim, mass, acc, decltype(odd)::value>(t, kk + jj * bb, mm[jj], U + c, mass ? V + c : nullptr,
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
      f(dim * N + c, c < 2 ? ku01[c] : t.ku2[0] + t.ku2[1], uv[0], uv[1],
        mass && acc ? t.ma[c][0] + t.ma[c][1] : 0.0);
    }
  }
}

}  // namespace nd
