// Which FE nodes a rank owns (issue 15): the rank's part of a field
// (nd_get_field_owned) and, through DofGeometry, the rows of the distributed
// step matrix (the free DOFs of its nodes). Every node has exactly one owner.
// This slice: contiguous blocks of node numbers, dealt out as evenly as the
// count allows (rank r owns nodes [begin, end)); a problem without a
// communicator owns every node.
#pragma once
#include <cstdint>

#include "parallel/communicator.hpp"

namespace nd {

struct NodeRange {
  int64_t begin = 0, end = 0;
  int64_t size() const { return end - begin; }
};

// The nodes of the calling rank of c (null: all of them); not collective.
NodeRange owned_nodes(const Communicator *c, int64_t n_nodes);

}  // namespace nd
