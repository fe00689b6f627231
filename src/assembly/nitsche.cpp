#include "assembly/nitsche.hpp"

#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"
#include "nitschedyn.h"

namespace nd {

Csr assemble_k_theta(const Csr &K, const ContactPoints &cp, double theta) {
  Csr K_theta = K;
  add_nitsche_terms(K_theta, cp, theta, nullptr);
  return K_theta;
}

namespace {
// A pair's point's stress row without the master's entries (zeros: a_q's
// index list, on which the slave cell's pattern has no place), else `s`
const SparseRow &slave_part(const ContactPoints &cp, size_t q, const SparseRow &s, SparseRow &scratch) {
  if (cp.pairing.empty() || cp.pairing[q * kPairingValues] < 0) return s;
  scratch.idx.clear(), scratch.val.clear();
  for (size_t k = 0; k < s.idx.size(); ++k)
    if (s.val[k] != 0) scratch.idx.push_back(s.idx[k]), scratch.val.push_back(s.val[k]);
  return scratch;
}
}  // namespace

void add_nitsche_terms(Csr &K, const ContactPoints &cp, double theta, const std::vector<char> *points) {
  SparseRow scratch;
  if (theta != 0)
    for (size_t q = 0; q < cp.size(); ++q) {
      if (points && !(*points)[q]) continue;
      const SparseRow &s = slave_part(cp, q, cp.s[q], scratch);
      K.add_outer(s.idx, s.val.data(), s.val.data(), -(theta * cp.w[q] * cp.gamma[q]));
      // friction: the tangential traction's term too (docs/design.md §10.2)
      if (cp.m > 1 && cp.friction[q])
        for (int k = 1; k < cp.m; ++k) {
          const SparseRow &t = slave_part(cp, q, cp.s_row(q, k), scratch);
          K.add_outer(t.idx, t.val.data(), t.val.data(), -(theta * cp.w[q] * cp.gamma[q]));
        }
    }
  for (double x : K.val)
    if (!std::isfinite(x))
      fail(ND_ERR_NITSCHE, "the Nitsche terms overflow (Theta = " + num(theta) + "): lower gamma0 or rescale the units");
}

}  // namespace nd
