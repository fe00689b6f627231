#include "assembly/bulk.hpp"
#include "assembly/redistribution.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/format.hpp"
#include "fem/facet.hpp"
#include "nitschedyn.h"

namespace nd {

bool AssemblyPart::takes(const Space &s, const DofMap &dofs, int64_t cell) const {
  if (cells && !(*cells)[cell]) return false;
  if (!rows) return true;
  const int64_t *nodes = s.nodes_of(cell);
  for (int i = 0; i < s.basis_of(cell).n; ++i)
    for (int a = 0; a < s.dim; ++a)
      if (const int64_t r = dofs.free[nodes[i] * s.dim + a]; r >= 0 && (*rows)[r]) return true;
  return false;
}

// The pattern is built over nodes and expanded: the rows of a node's DOFs
// share their columns (the free DOFs of the nodes it shares a cell with), so
// a cell adds nb^2 node pairs, not (nb d)^2 DOF pairs, to sort. Free DOFs are
// numbered in DOF order (DofMap), so each row's columns come out sorted.
Csr operator_pattern(const Space &s, const DofMap &dofs, const AssemblyPart &part) {
  const int d = s.dim;
  const std::vector<int64_t> &free = dofs.free;
  auto held = [&](int64_t r) { return r >= 0 && (!part.rows || (*part.rows)[r]); };
  auto node_held = [&](int64_t v) {
    for (int a = 0; a < d; ++a)
      if (held(free[v * d + a])) return true;
    return false;
  };
  std::vector<std::vector<int64_t>> adjacent(static_cast<size_t>(s.n_nodes));
  for (int64_t c = 0; c < s.mesh->n_cells; ++c) {
    if (!part.takes(s, dofs, c)) continue;
    const int64_t *nodes = s.nodes_of(c);
    const int nb = s.basis_of(c).n;
    for (int i = 0; i < nb; ++i)
      if (node_held(nodes[i]))
        for (int j = 0; j < nb; ++j) adjacent[nodes[i]].push_back(nodes[j]);
  }
  Csr A;
  A.n = dofs.n_free;
  // rows in node order are in row order (DofMap); a part stores the rows it
  // holds (every free DOF of a node it touches) and no others
  A.part = part.cells || part.rows;
  std::vector<int64_t> &ptr = A.ptr.mut(), &col = A.col.mut();
  ptr.assign(1, 0);
  for (int64_t v = 0; v < s.n_nodes; ++v) {
    std::vector<int64_t> &adj = adjacent[v];
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
    int64_t columns = 0;
    for (int64_t w : adj)
      for (int b = 0; b < d; ++b) columns += free[w * d + b] >= 0;
    for (int a = 0; a < d; ++a) {
      const int64_t r = free[v * d + a];
      if (r < 0 || (A.part && (adj.empty() || !held(r)))) continue;
      if (A.part) A.held.push_back(r);
      ptr.push_back(ptr.back() + (held(r) ? columns : 0));
    }
  }
  if (!A.part && static_cast<int64_t>(ptr.size()) != A.n + 1)
    fail(ND_ERR_INTERNAL, "the free DOFs are not numbered in node order");
  col.resize(static_cast<size_t>(ptr.back()));
  for (int64_t v = 0, at = 0; v < s.n_nodes; ++v)
    for (int a = 0; a < d; ++a) {
      const int64_t r = free[v * d + a];
      if (r < 0 || (A.part && (adjacent[v].empty() || !held(r)))) continue;
      int64_t k = ptr[at++];
      for (int64_t w : adjacent[v])
        for (int b = 0; b < d; ++b)
          if (free[w * d + b] >= 0) col[k++] = free[w * d + b];
    }
  A.val.assign(A.col.size(), 0.0);
  return A;
}

ElementMatrices::ElementMatrices(const Space &s, const CellMaterials &mat)
    : me(static_cast<size_t>(s.stride * s.stride)),
      ke(static_cast<size_t>(s.stride * s.dim * s.stride * s.dim)),
      s_(s),
      mat_(mat),
      // a multilinear map's det J has degree dim - 1 in each variable: the
      // mass is exact with it, the stiffness on parallelograms and parallelepipeds
      mass_rule_{simplex_rule(s.dim, 2 * s.degree), cube_rule(s.dim, 2 * s.degree + s.dim - 1)},
      stiff_rule_{simplex_rule(s.dim, 2 * (s.degree - 1)), cube_rule(s.dim, 2 * s.degree)},
      phi_(static_cast<size_t>(s.stride)),
      gref_(static_cast<size_t>(s.stride * s.dim)),
      g_(static_cast<size_t>(s.stride * s.dim)) {
  for (const Material &m : mat.list) lam_.push_back(m.lambda(s.dim)), mu_.push_back(m.mu(s.dim));
}

void ElementMatrices::compute(int64_t c) {
  const Lagrange &basis = s_.basis_of(c);
  nb = basis.n;
  simplex_ = s_.mesh->simplicial(c);
  const QuadratureRule &mass_rule = mass_rule_[simplex_ ? 0 : 1], &stiff_rule = stiff_rule_[simplex_ ? 0 : 1];
  const int d = s_.dim;
  const size_t which = mat_.uniform() ? 0 : static_cast<size_t>(mat_.index[c]);
  const double lam = lam_[which], mu = mu_[which];
  rho = mat_.list[which].density;
  CellMap map(*s_.mesh, c);
  const bool affine = map.affine;
  mass = affine ? rho * map.det / (d == 1 ? 1.0 : d == 2 ? 2.0 : 6.0) : 0.0;
  me.assign(static_cast<size_t>(nb * nb), 0.0);  // (within the capacity: no allocation)
  ke.assign(static_cast<size_t>(nb * d * nb * d), 0.0);
  for (size_t q = 0; q < mass_rule.size(); ++q) {
    map.at(&mass_rule.points[q * d]);
    basis.values(&mass_rule.points[q * d], phi_.data());
    const double w = mass_rule.weights[q] * map.det * rho;
    if (!affine) mass += w;
    for (int i = 0; i < nb; ++i)
      for (int j = 0; j < nb; ++j) me[i * nb + j] += w * phi_[i] * phi_[j];
  }
  const std::vector<double> &g = g_;
  for (size_t q = 0; q < stiff_rule.size(); ++q) {
    map.at(&stiff_rule.points[q * d]);
    basis.gradients(&stiff_rule.points[q * d], gref_.data());
    for (int i = 0; i < nb; ++i) map.physical_gradient(&gref_[i * d], &g_[i * d]);
    const double w = stiff_rule.weights[q] * map.det;
    // row (i,a), column (j,b): lambda d_a phi_i d_b phi_j
    //                          + mu (delta_ab grad phi_i . grad phi_j + d_b phi_i d_a phi_j)
    for (int i = 0; i < nb; ++i)
      for (int j = 0; j < nb; ++j) {
        double gg = 0;
        for (int k = 0; k < d; ++k) gg += g[i * d + k] * g[j * d + k];
        for (int a = 0; a < d; ++a)
          for (int b = 0; b < d; ++b)
            ke[(i * d + a) * nb * d + j * d + b] +=
                w * (lam * g[i * d + a] * g[j * d + b] + mu * ((a == b ? gg : 0.0) + g[i * d + b] * g[j * d + a]));
      }
  }
}

void ElementMatrices::lump(std::vector<double> &diagonal, bool redistributed) const {
  diagonal.resize(static_cast<size_t>(nb));
  if (!simplex_ && s_.degree == 1 && !redistributed) {
    for (int i = 0; i < nb; ++i) {
      double sum = 0;
      for (int j = 0; j < nb; ++j) sum += me[i * nb + j];
      diagonal[i] = sum;
    }
    return;
  }
  double diag = 0;
  for (int i = 0; i < nb; ++i) diag += me[i * nb + i];
  for (int i = 0; i < nb; ++i) diagonal[i] = me[i * nb + i] * mass / diag;
}

BulkOperators assemble_bulk(const Space &s, const DofMap &dofs, const CellMaterials &mat,
                            const std::vector<char> *contact_nodes, const AssemblyPart &part) {
  BulkOperators ops;
  ops.M = operator_pattern(s, dofs, part);
  ops.K = ops.M.zeros_like();
  ops.M_lumped.assign(static_cast<size_t>(dofs.n_free), 0.0);
  const int d = s.dim;
  ElementMatrices em(s, mat);
  const std::vector<double> &me = em.me, &ke = em.ke;
  std::vector<int64_t> offset(static_cast<size_t>(s.stride));
  std::vector<double> lumped;
  for (int64_t c = 0; c < s.mesh->n_cells; ++c) {
    if (!part.takes(s, dofs, c)) continue;
    em.compute(c);
    if (contact_nodes) redistribute_element_mass(s, c, *contact_nodes, em.me);
    em.lump(lumped, contact_nodes != nullptr);
    const int64_t *nodes = s.nodes_of(c);
    const int nb = em.nb;
    for (int i = 0; i < nb; ++i) {
      bool found = false;  // offset[j]: where node j's columns start in node i's rows
      for (int a = 0; a < d; ++a) {
        const int64_t r = dofs.free[nodes[i] * d + a];
        if (r < 0 || (part.rows && !(*part.rows)[r])) continue;
        const int64_t row_start = ops.K.ptr[ops.K.slot(r)];  // (a part searches its rows once per row)
        if (!found) {  // the rows of a node share their columns, in DOF order (operator_pattern): one search per node pair
          for (int j = 0; j < nb; ++j) {  // node j's first free DOF; its others follow it in the row
            int b = 0;
            while (b < d && dofs.free[nodes[j] * d + b] < 0) ++b;
            offset[j] = b == d ? -1 : ops.K.find(r, dofs.free[nodes[j] * d + b]) - row_start;
          }
          found = true;
        }
        ops.M_lumped[r] += lumped[i];
        for (int j = 0; j < nb; ++j) {
          if (offset[j] < 0) continue;
          int64_t k = row_start + offset[j];
          for (int b = 0; b < d; ++b) {
            if (dofs.free[nodes[j] * d + b] < 0) continue;
            ops.K.val[k] += ke[(i * d + a) * nb * d + j * d + b];
            if (a == b) ops.M.val[k] += me[i * nb + j];
            ++k;
          }
        }
      }
    }
  }
  // Finite but extreme parameters (E = 1e308, rho = 1e-308, a huge or tiny
  // mesh) overflow or underflow here: refused with what to change, rather
  // than NaN operators that fail later as an internal error.
  auto all_finite = [](const std::vector<double> &v) {
    for (double x : v)
      if (!std::isfinite(x)) return false;
    return true;
  };
  // (with several materials the message names the default's values and says so)
  const std::string which = mat.uniform() ? "" : " (the default material; the cells have several)";
  const Material &m0 = mat.list[0];
  if (!all_finite(ops.K.val))
    fail(ND_ERR_MATERIAL, "the stiffness matrix overflows with E = " + num(m0.young) + " and nu = " +
                              num(m0.poisson) + which + " on this mesh: rescale the units");
  if (!all_finite(ops.M.val) || !all_finite(ops.M_lumped))
    fail(ND_ERR_MATERIAL, "the mass matrix overflows with density " + num(m0.density) + which +
                              " on this mesh: rescale the units");
  for (double m : ops.M_lumped)  // (a part leaves the other DOFs at 0)
    if (!(m > 0 || ((contact_nodes || part.cells || part.rows) && m == 0)) || !(m == 0 || std::isnormal(m)))
      fail(ND_ERR_MATERIAL, "the mass matrix underflows with density " + num(m0.density) + which +
                                " on this mesh: rescale the units");
  return ops;
}

std::vector<double> assemble_load(const Space &s, const DofMap &dofs, const double *f,
                                  const std::vector<NeumannLoad> &neumann) {
  if (!f && neumann.empty()) return {};
  std::vector<double> F(static_cast<size_t>(dofs.n_free), 0.0);
  const int d = s.dim;
  std::vector<double> phi(static_cast<size_t>(s.stride));
  auto add = [&](int64_t c, const double *vec, double w) {
    const int64_t *nodes = s.nodes_of(c);
    for (int i = 0; i < s.basis_of(c).n; ++i)
      for (int a = 0; a < d; ++a) {
        const int64_t r = dofs.free[nodes[i] * d + a];
        if (r >= 0) F[r] += w * phi[i] * vec[a];
      }
  };
  if (f) {  // (exact for P1, P2; for Q1, Q2 with det J's degree added)
    const QuadratureRule rules[2] = {simplex_rule(d, s.degree), cube_rule(d, s.degree + d - 1)};
    for (int64_t c = 0; c < s.mesh->n_cells; ++c) {
      CellMap map(*s.mesh, c);
      const QuadratureRule &rule = rules[s.mesh->simplicial(c) ? 0 : 1];
      for (size_t q = 0; q < rule.size(); ++q) {
        map.at(&rule.points[q * d]);
        s.basis_of(c).values(&rule.points[q * d], phi.data());
        add(c, f, rule.weights[q] * map.det);
      }
    }
  }
  for (const NeumannLoad &nl : neumann)
    for (int64_t b : s.mesh->regions.at(nl.region)) {
      const Facet &facet = s.mesh->boundary[b];
      for (const FacetPoint &fp : facet_quadrature(*s.mesh, facet, s.degree)) {
        s.basis_of(facet.cell).values(fp.xi, phi.data());
        add(facet.cell, nl.g, fp.weight);
      }
    }
  for (double x : F)
    if (!std::isfinite(x)) fail(ND_ERR_VALUE, "the load vector overflows: the body force or a traction is too large for this mesh");
  return F;
}

}  // namespace nd
