// The state at t^n, in free DOFs: what a step reads and the next step writes.
#pragma once
#include <cstdint>
#include <vector>

namespace nd {

struct State {
  double t = 0;
  int64_t n = 0;
  std::vector<double> U, V, A;
  std::vector<double> F;  // the load F^n of the last step (empty: no load)
  bool A_valid = false;   // schemes without acceleration (hybrid) compute it on demand
  double W = 0;
  int last_iterations = 0;
  int64_t total_iterations = 0;
};

}  // namespace nd
