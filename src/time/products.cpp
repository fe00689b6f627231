// A used state's products' memory, for the next (products.hpp)
#include "time/products.hpp"

#include <utility>

namespace nd {

void clear_keeping_memory(PointValues &v) {
  v.P.clear(), v.un.clear();
  v.partial = false, v.summed = false;
  v.sums = PointSums{};
  v.ref.reset();
}

Products reuse_storage(Products &&used) {
  Products p;
  for (auto field : {&Products::MU, &Products::MV, &Products::MA, &Products::KU}) std::swap(p.*field, used.*field);
  std::swap(p.points, used.points);
  clear_keeping_memory(p.points);
  return p;
}

}  // namespace nd
