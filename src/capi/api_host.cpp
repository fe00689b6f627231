// Contact on the host's operators: N(U), N'(U) and the contact values at a
// U the host gives, and the step form by the scheme's time rule from the
// host's U^n (problem/host_contact.hpp).
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
// u_old (the step form's U^n): n finite values, or null for the law at the end
void need_u_old(const double *u_old, int64_t n, bool step) {
  if (!step) return;
  need(u_old, "u_old");
  need_finite(u_old, n, "u_old");
}
// The residual of either form (u_old null: at the end of the step)
int contact_residual(const char *call, nd_problem p, int64_t n, const double *u, const double *u_old, bool step,
                     double *r) {
  return guarded(call, [&] {
    Problem &pr = problem_of(p);
    need_u(pr, n, u);
    need_u_old(u_old, n, step);
    need(r, "r");
    host_contact_residual(pr, u, u_old, r);
    return ND_OK;
  });
}
// The tangent of either form; with NULL arrays the sizes (u, u_old not read)
int contact_tangent(const char *call, nd_problem p, int64_t n, const double *u, const double *u_old, bool step,
                    int64_t *nnz, int64_t *row_ptr, int64_t *col_idx, double *values) {
  return guarded(call, [&] {
    Problem &pr = problem_of(p);
    need(nnz, "nnz");
    const bool sizes = !row_ptr && !col_idx && !values;
    if (sizes) {  // the pattern alone: u is not read
      const int64_t expected = pr.discretization().dofs.n_free;
      if (n != expected)
        fail(ND_ERR_SIZE, "free DOFs: n is " + std::to_string(n) + ", expected " + std::to_string(expected));
    } else {
      need_u(pr, n, u);
      need_u_old(u_old, n, step);
    }
    const Csr T = host_contact_tangent(pr, sizes ? nullptr : u, sizes ? nullptr : u_old);
    if (csr_request(T, nullptr, nnz, row_ptr, col_idx, values)) csr_copy(T, row_ptr, col_idx, values);
    return ND_OK;
  });
}
}  // namespace
}  // namespace nd

extern "C" {

ND_EXPORT int nd_problem_contact_residual(nd_problem p, int64_t n, const double *u, double *r) {
  return nd::contact_residual("nd_problem_contact_residual", p, n, u, nullptr, false, r);
}

ND_EXPORT int nd_problem_contact_tangent(nd_problem p, int64_t n, const double *u, int64_t *nnz, int64_t *row_ptr,
                                         int64_t *col_idx, double *values) {
  return nd::contact_tangent("nd_problem_contact_tangent", p, n, u, nullptr, false, nnz, row_ptr, col_idx, values);
}

ND_EXPORT int nd_problem_contact_step_residual(nd_problem p, int64_t n, const double *u, const double *u_old,
                                               double *r) {
  return nd::contact_residual("nd_problem_contact_step_residual", p, n, u, u_old, true, r);
}

ND_EXPORT int nd_problem_contact_step_tangent(nd_problem p, int64_t n, const double *u, const double *u_old,
                                              int64_t *nnz, int64_t *row_ptr, int64_t *col_idx, double *values) {
  return nd::contact_tangent("nd_problem_contact_step_tangent", p, n, u, u_old, true, nnz, row_ptr, col_idx,
                             values);
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
