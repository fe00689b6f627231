#include "assembly/nitsche.hpp"

namespace nd {

Csr assemble_k_theta(const Csr &K, const ContactPoints &cp, double theta) {
  Csr K_theta = K;
  if (theta != 0)
    for (size_t q = 0; q < cp.size(); ++q) {
      const SparseRow &s = cp.s[q];
      K_theta.add_outer(s.idx, s.val.data(), s.val.data(), -(theta * cp.w[q] * cp.gamma[q]));
    }
  return K_theta;
}

}  // namespace nd
