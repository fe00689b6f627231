// Contact on the host's operators: N(U), N'(U) and the contact values at a
// U the host gives (problem/host_contact.hpp).
#include <string>

#include "capi/csr_out.hpp"
#include "capi/guard.hpp"
#include "capi/handles.hpp"
#include "problem/host_contact.hpp"

namespace nd {
namespace {
// u: n free DOF values, all finite
void need_u(Problem &pr, int64_t n, const double *u) {
  const int64_t expected = pr.discretization().dofs.n_free;
  if (n != expected)
    fail(ND_ERR_SIZE, "free DOFs: n is " + std::to_string(n) + ", expected " + std::to_string(expected));
  need(u, "u");
  need_finite(u, n, "u");
}
}  // namespace
}  // namespace nd

extern "C" {

ND_EXPORT int nd_problem_contact_residual(nd_problem p, int64_t n, const double *u, double *r) {
  return nd::guarded("nd_problem_contact_residual", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_u(pr, n, u);
    nd::need(r, "r");
    nd::host_contact_residual(pr, u, r);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_contact_tangent(nd_problem p, int64_t n, const double *u, int64_t *nnz, int64_t *row_ptr,
                                         int64_t *col_idx, double *values) {
  return nd::guarded("nd_problem_contact_tangent", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(nnz, "nnz");
    const bool sizes = !row_ptr && !col_idx && !values;
    if (sizes) {  // the pattern alone: u is not read
      const int64_t expected = pr.discretization().dofs.n_free;
      if (n != expected)
        nd::fail(ND_ERR_SIZE, "free DOFs: n is " + std::to_string(n) + ", expected " + std::to_string(expected));
    } else {
      nd::need_u(pr, n, u);
    }
    const nd::Csr T = nd::host_contact_tangent(pr, sizes ? nullptr : u);
    if (nd::csr_request(T, nullptr, nnz, row_ptr, col_idx, values)) nd::csr_copy(T, row_ptr, col_idx, values);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_contact_values(nd_problem p, int64_t n, const double *u, int nvalues, double *values) {
  return nd::guarded("nd_problem_contact_values", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_u(pr, n, u);
    if (nvalues < 1 || nvalues > nd::kHostContactValues)
      nd::fail(ND_ERR_SIZE, "nvalues is " + std::to_string(nvalues) + "; it must be 1 to " +
                                std::to_string(nd::kHostContactValues));
    nd::need(values, "values");
    nd::host_contact_values(pr, u, nvalues, values);
    return ND_OK;
  });
}

}  // extern "C"
