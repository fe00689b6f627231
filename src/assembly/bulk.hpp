// Volume operators over the free DOFs: mass (consistent and lumped),
// stiffness, and the constant load vector.
#pragma once
#include <vector>

#include "assembly/material.hpp"
#include "fem/space.hpp"
#include "linalg/csr.hpp"

namespace nd {

struct NeumannLoad {
  int region;
  double g[3];
};

// A part of the operators: the cells whose contributions are taken (1 per
// cell; null: all) and the rows kept (1 per free DOF; null: all). A rank's
// own cells (its part of the step matrix, every row they touch) or its own
// rows (every cell's contribution to them), parallel/ownership.hpp.
struct AssemblyPart {
  const std::vector<char> *cells = nullptr;
  const std::vector<char> *rows = nullptr;
  bool takes(const Space &s, const DofMap &dofs, int64_t cell) const;
};

// The pattern shared by all operators: every pair of free DOFs of a cell,
// on all n_free rows (the rows a part does not keep are empty).
Csr operator_pattern(const Space &s, const DofMap &dofs, const AssemblyPart &part = {});

// The element mass (nb x nb, scalar, times rho) and stiffness (nb*dim
// squared, row (i,a), column (j,b)) of one cell, over all its local DOFs,
// with the cell's own material.
class ElementMatrices {
 public:
  ElementMatrices(const Space &s, const CellMaterials &mat);
  ElementMatrices(const Space &s, CellMaterials &&mat) = delete;  // (it keeps a reference)
  void compute(int64_t cell);  // fills nb, me, ke, mass and rho
  // The lumped diagonal of me as it is then: Q1, the row sums; otherwise,
  // and after a redistribution, HRZ: the diagonal scaled to the cell's mass.
  void lump(std::vector<double> &diagonal, bool redistributed) const;
  int nb = 0;       // the cell's local basis functions (its type's)
  std::vector<double> me, ke;
  double mass = 0;  // the cell's: rho |K|
  double rho = 0;   // the cell's density

 private:
  const Space &s_;
  const CellMaterials &mat_;
  std::vector<double> lam_, mu_;  // of each material of the list
  QuadratureRule mass_rule_[2], stiff_rule_[2];  // a simplex's, a quadrilateral's or hexahedron's
  bool simplex_ = true;                          // the cell's type
  std::vector<double> phi_, gref_, g_;
};

struct BulkOperators {
  Csr M, K;
  std::vector<double> M_lumped;  // diagonal, HRZ (row sums for P1 and Q1)
};
// With `contact_nodes` (assembly/redistribution.hpp; nullptr: off) the mass
// of those nodes is redistributed; the lumped mass is then the HRZ lumping of
// the redistributed element mass (the mass is kept, the moments are not).
// With a part: that part, on its pattern; each kept entry has the bits of
// the whole assembly's (the same contributions, added in the same order).
// The lumped diagonal is then the part's too.
BulkOperators assemble_bulk(const Space &s, const DofMap &dofs, const CellMaterials &mat,
                            const std::vector<char> *contact_nodes = nullptr, const AssemblyPart &part = {});

// Constant load: body force f (dim values, or nullptr) and Neumann tractions.
// Returns an empty vector when there is no load at all.
std::vector<double> assemble_load(const Space &s, const DofMap &dofs, const double *body_force,
                                  const std::vector<NeumannLoad> &neumann);

}  // namespace nd
