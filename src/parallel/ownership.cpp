#include "parallel/ownership.hpp"

#include <algorithm>

namespace nd {

NodeRange owned_nodes(const Communicator *c, int64_t n_nodes) {
  const int64_t size = communicator_size(c), rank = communicator_rank(c);
  const int64_t share = n_nodes / size, extra = n_nodes % size;
  NodeRange r;
  r.begin = rank * share + std::min(rank, extra);
  r.end = r.begin + share + (rank < extra ? 1 : 0);
  return r;
}

}  // namespace nd
