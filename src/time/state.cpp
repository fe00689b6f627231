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
  for (auto field : {&State::U, &State::V, &State::A, &State::F_fixed, &State::gap, &State::reaction, &State::phi,
                     &State::slip, &State::phi_t})
    take(s.*field, used.*field);
  take(s.tangent_log.i, used.tangent_log.i);
  take(s.tangent_log.x, used.tangent_log.x);
  take(s.control.a_mean, used.control.a_mean);
  return s;
}

}  // namespace nd
