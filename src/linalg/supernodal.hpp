// A numeric supernodal LL^T in CHOLMOD's layout, read through its arrays:
// the solves that sweep it (linalg/cholmod.cpp's own, not cholmod_l_solve)
// and the rank-one updates and downdates that modify it in place
// (linalg/updatable_cholesky.hpp). CHOLMOD's own updates (cholmod_l_updown)
// need a simplicial LDL^T, whose solves cost up to twice the supernodal
// ones in 3D: the Newton tangent of a 3D body in contact would pay that at
// every iteration. Here the factor stays supernodal: an update leaves L's
// structure as it is, so its columns must lie where L has entries (a
// column on a clique of the matrix's graph does: an element's DOFs).
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace nd {

// The arrays of a supernodal factor (CHOLMOD's super, pi, px, s, x, Perm).
// Supernode s: columns [super[s], super[s + 1]); its rows s_rows[pi[s] ..
// pi[s + 1]) (the columns' own first, then those below, ascending); its
// values at x + px[s], column-major with leading dimension pi[s + 1] - pi[s].
struct SupernodalFactor {
  int64_t n = 0, count = 0;
  const int64_t *super = nullptr, *pi = nullptr, *px = nullptr, *s_rows = nullptr, *perm = nullptr;
  double *x = nullptr;
  // Block s: its diagonal block (cols columns from `first`, leading
  // dimension ld) and the block below it (`below` rows, at the unknowns
  // `rows`), both at L
  struct Block {
    int64_t first;
    int cols, ld, below;
    const int64_t *rows;
    double *L;
  };
  Block operator[](int64_t s) const {
    const int cols = static_cast<int>(super[s + 1] - super[s]), ld = static_cast<int>(pi[s + 1] - pi[s]);
    // (x null: a symbolic factor, before its numeric factorization; the
    // tree reads its structure alone)
    return Block{super[s], cols, ld, ld - cols, s_rows + pi[s] + cols, x ? x + px[s] : nullptr};
  }
};

// A supernodal factor's elimination tree: which supernodes a right-hand
// side with few nonzeros reaches in the forward solve (those of its
// nonzeros' columns and their ancestors; the others stay zero), and which
// the backward solve needs for a few rows (theirs and their ancestors).
struct SupernodalTree {
  explicit SupernodalTree(const SupernodalFactor &L);
  // marks column c's supernode and its ancestors (stops at one already marked)
  void mark_path(int64_t c, std::vector<char> &marked) const {
    for (int64_t s = of_column[c]; s >= 0 && !marked[s]; s = parent[s]) marked[s] = 1;
  }
  std::vector<int64_t> of_column, parent;  // a column's supernode; a supernode's parent (-1: a root)
};

// A solve's workspaces (supernodal_forward's y, reached and e), kept by a
// factor from solve to solve, so that a solve allocates nothing and zeroes
// no n-long vector. A factor is not solved from two
// threads at once (the library calls it from one).
struct SupernodalWork {
  std::vector<double> y, e;
  std::vector<char> reached;
  void fit(const SupernodalFactor &L, std::size_t maxesize) {
    y.resize(static_cast<std::size_t>(L.n));  // (no zeros but the first time: forward sets every entry)
    e.resize(std::max<std::size_t>(maxesize, 1));
    reached.resize(static_cast<std::size_t>(L.count));
  }
};

// y = L^{-1} P x over the supernodes x's nonzeros reach (the others stay
// zero); inv: 1 / L(j, j); reached and e are workspaces (count and the
// largest block's rows long)
void supernodal_forward(const SupernodalFactor &L, const SupernodalTree &tree, const double *inv, const double *x,
                        std::vector<double> &y, std::vector<char> &reached, std::vector<double> &e);
// y = L^{-T} y over the supernodes `needed` marks (null: all), root first
void supernodal_backward(const SupernodalFactor &L, const double *inv, std::vector<double> &y,
                         std::vector<double> &e, const std::vector<char> *needed);

// L L^T <- L L^T + sum_j v_j v_j^T (add) or - sum_j v_j v_j^T, vector j's
// nonzeros at the permuted rows rows[ptr[j] .. ptr[j + 1]) (no repeats) with
// the values vals[...], inv kept 1 / L(j, j): rank-one modifications one
// after the other, each over the columns from its first row to the root
// (its path in the elimination tree), column by column (the LINPACK
// recurrence). Up to kBatch vectors go up their paths together, each
// column modified by one after the other while it is in cache: the bits of
// the modifications made one at a time. false when a vector has a row where
// its first column of L has none (a batch's vectors are checked before it
// starts), or when a pivot of the result is not positive and finite (L is
// then half modified: no longer a factor of anything).
class SupernodalModifier {
 public:
  // (64, not 4: a batch walks the root's large blocks once for kBatch
  // vectors; wider batches gain nothing more: docs/performance.md, "Batches
  // of rank updates". w_ holds up to 512 bytes an unknown, as wide as the
  // widest batch met)
  static constexpr int kBatch = 64;
  bool modify(const SupernodalFactor &L, const SupernodalTree &tree, double *inv, bool add, const int64_t *ptr,
              const int64_t *rows, const double *vals, int64_t k);
  // entries of L times the vectors that modified them, since construction
  // (a column's entry rotated by m vectors counts m; its diagonal counts)
  int64_t rotated_entries() const { return rotated_; }

 private:
  void clear(const SupernodalFactor &L, const SupernodalTree &tree, const std::vector<int64_t> &first);
  std::vector<double> w_;    // n x width_, row by row: the vectors' entries (zeros between calls)
  int width_ = 0;            // at most kBatch
  std::vector<double> v_;    // a block's rows x a batch's vectors, vector by vector
  std::vector<char> marked_;  // (zeros between calls)
  std::vector<int64_t> path_;
  std::vector<int64_t> first_;  // a batch's vectors' first rows
  int64_t rotated_ = 0;
};

// path[j]: the entries of L in the columns from j to the root (what a
// rank-one modification whose first row is j reads and writes)
std::vector<double> supernodal_paths(const SupernodalFactor &L);

}  // namespace nd
