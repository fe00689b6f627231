// A used state's memory, for the next (state.hpp)
#include "time/state.hpp"

#include <utility>

namespace nd {

namespace {
template <class T>
void take(std::vector<T> &to, std::vector<T> &from) {
  to.swap(from);
  to.clear();  // (the capacity stays)
}
}  // namespace

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

State reuse_storage(State &&used) {
  State s;
  for (auto field : {&State::U, &State::V, &State::A, &State::F_fixed, &State::gap, &State::reaction, &State::phi,
                     &State::slip, &State::phi_t})
    take(s.*field, used.*field);
  s.products = reuse_storage(std::move(used.products));
  take(s.tangent_log.i, used.tangent_log.i);
  take(s.tangent_log.x, used.tangent_log.x);
  take(s.control.a_mean, used.control.a_mean);
  return s;
}

}  // namespace nd
