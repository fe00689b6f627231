// Operators out: the matrices, the DOF map, the load and the cells a host
// code reads (problem/exports.hpp).
#include <algorithm>
#include <string>

#include "capi/guard.hpp"
#include "capi/csr_out.hpp"
#include "capi/handles.hpp"
#include "problem/exports.hpp"

namespace nd {
namespace {
void need_count(int64_t n, int64_t expected, const char *what) {
  if (n != expected)
    fail(ND_ERR_SIZE, std::string(what) + ": n is " + std::to_string(n) + ", expected " + std::to_string(expected));
}
}  // namespace

}  // namespace nd

extern "C" {

ND_EXPORT int nd_problem_get_matrix(nd_problem p, int which, int64_t *n, int64_t *nnz, int64_t *row_ptr,
                                    int64_t *col_idx, double *values) {
  return nd::guarded("nd_problem_get_matrix", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_member(ND_IS_MEMBER_(ND_MATRIX_LIST, which), ND_ERR_KEY, "which", which, "ND_MATRIX_*");
    nd::need(n, "n");
    nd::need(nnz, "nnz");
    const nd::Csr A = nd::exported_matrix(pr, which);
    if (nd::csr_request(A, n, nnz, row_ptr, col_idx, values)) nd::csr_copy(A, row_ptr, col_idx, values);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_dof_map(nd_problem p, int64_t n, int64_t *node, int *component) {
  return nd::guarded("nd_problem_get_dof_map", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_count(n, pr.discretization().dofs.n_free, "free DOFs");
    nd::exported_dof_map(pr, node, component);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_load(nd_problem p, int64_t n, double *f) {
  return nd::guarded("nd_problem_get_load", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need_count(n, pr.discretization().dofs.n_free, "free DOFs");
    nd::need(f, "f");
    const std::vector<double> F = nd::exported_load(pr);
    std::copy(F.begin(), F.end(), f);
    return ND_OK;
  });
}

ND_EXPORT int nd_problem_get_cells(nd_problem p, int64_t *n_cells, int *nodes_per_cell, int64_t *nodes) {
  return nd::guarded("nd_problem_get_cells", [&] {
    nd::Problem &pr = nd::problem_of(p);
    nd::need(n_cells, "n_cells");
    nd::need(nodes_per_cell, "nodes_per_cell");
    const nd::Space &sp = pr.space();
    const int64_t cells = sp.mesh->n_cells;
    if (nodes) {
      if (*n_cells != cells)
        nd::fail(ND_ERR_SIZE, "*n_cells is " + std::to_string(*n_cells) + ", the mesh has " +
                                  std::to_string(cells) + " cells (a first call with nodes NULL gives the sizes)");
      std::copy(sp.cell_nodes.begin(), sp.cell_nodes.end(), nodes);
    }
    *n_cells = cells;
    *nodes_per_cell = sp.stride;  // (a mixed mesh: the largest cell's, the others padded with -1)
    return ND_OK;
  });
}

}  // extern "C"
