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

State reuse_storage(State &&used) {
  State s;
  for (auto field : {&State::U, &State::V, &State::A, &State::F_fixed, &State::gap, &State::reaction, &State::phi})
    take(s.*field, used.*field);
  for (auto field : {&Products::MU, &Products::MV, &Products::MA, &Products::KU})
    take(s.products.*field, used.products.*field);
  take(s.products.points.P, used.products.points.P);
  take(s.products.points.un, used.products.points.un);
  take(s.tangent_log.i, used.tangent_log.i);
  take(s.tangent_log.x, used.tangent_log.x);
  return s;
}

}  // namespace nd
