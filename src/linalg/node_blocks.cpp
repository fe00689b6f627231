#include "linalg/node_blocks.hpp"

#include <cstdint>

namespace nd {

std::shared_ptr<const NodeBlocks> make_node_blocks(const Csr &K, const Csr &M, int dim) {
  if (dim < 2 || dim > 3 || K.part || M.part || K.n % dim != 0 || M.n != K.n || !(M.ptr == K.ptr) || !(M.col == K.col) ||
      K.n / dim > INT32_MAX)
    return nullptr;
  const int64_t nodes = K.n / dim;
  auto b = std::make_shared<NodeBlocks>();
  b->dim = dim;
  b->ptr.assign(1, 0);
  const int64_t entries = static_cast<int64_t>(K.val.size());
  b->node.reserve(static_cast<size_t>(entries / (dim * dim)));
  b->k.reserve(static_cast<size_t>(entries));
  b->m.reserve(static_cast<size_t>(entries / (dim * dim)));
  for (int64_t N = 0; N < nodes; ++N) {
    const int64_t first = dim * N, begin = K.ptr[first], len = K.ptr[first + 1] - begin;
    if (len % dim != 0) return nullptr;
    for (int c = 1; c < dim; ++c)
      if (K.ptr[first + c + 1] - K.ptr[first + c] != len) return nullptr;
    for (int64_t o = 0; o < len; o += dim) {
      const int64_t col = K.col[begin + o];
      if (col % dim != 0) return nullptr;
      const double m = M.val[begin + o];
      for (int e = 0; e < dim; ++e)
        for (int c = 0; c < dim; ++c) {
          const int64_t at = K.ptr[first + c] + o + e;  // row dim N + c, column dim J + e
          if (K.col[at] != col + e) return nullptr;
          if (M.val[at] != (c == e ? m : 0.0)) return nullptr;
          b->k.push_back(K.val[at]);
        }
      b->node.push_back(static_cast<int32_t>(col / dim));
      b->m.push_back(m);
    }
    b->ptr.push_back(static_cast<int64_t>(b->node.size()));
  }
  return b;
}

}  // namespace nd
