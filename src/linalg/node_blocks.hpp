// K and M by nodes, for the products pass (monitor/energies.cpp): K's
// dim x dim blocks and one entry of M per block, a block's column as its
// node in 4 bytes. The pass then reads about 11 bytes per entry of K in 2D
// and 9 in 3D, against 24 on the CSR pattern M and K share (K's value, M's,
// a column index), half of whose M entries are zeros (M couples no two
// components): measured on the disks, the pass 0.55-0.71 of the CSR one.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "linalg/csr.hpp"

namespace nd {

struct NodeBlocks {
  int dim = 0;
  std::vector<int64_t> ptr;   // node N's blocks: [ptr[N], ptr[N + 1])
  std::vector<int32_t> node;  // a block's column node
  std::vector<double> k;      // dim * dim per block, column by column: K(dim N + c, dim J + e) at e * dim + c
  std::vector<double> m;      // one per block: M(dim N + c, dim J + c), the same for every c
};

// The blocks of K and M (same pattern, every row stored), or null where
// they do not have that form: dim < 2, a row count not a multiple of dim
// (clamped DOFs leave a node's others numbered apart), a row whose columns
// are not whole nodes in order, the rows of a node with different columns,
// M coupling two components or differing between them, or more than 2^31
// nodes.
std::shared_ptr<const NodeBlocks> make_node_blocks(const Csr &K, const Csr &M, int dim);

}  // namespace nd
