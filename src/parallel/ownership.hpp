// Which rank owns what: the cells of the mesh are
// partitioned over the ranks of a problem's communicator, and each FE node
// belongs to the rank of the lowest-numbered cell that holds it. A rank owns
// the rows of its nodes' free DOFs in the distributed step matrix
// (DofGeometry), assembles its own cells' contributions to that matrix, and
// reads its nodes' part of a field (nd_get_field_owned). Every cell and every
// node has exactly one owner; a problem without a communicator (or on one
// rank) owns everything.
//
// The partition: PETSc's MatPartitioning of the cell dual graph (cells
// adjacent through a facet) with PT-Scotch or ParMETIS, whichever this PETSc
// has (checked at run time, in that order; Debian's has PT-Scotch only), and
// PT-Scotch only where it runs safely: MPI initialized with
// MPI_THREAD_MULTIPLE, or SCOTCH_PTHREAD_NUMBER=1 in the environment (its
// threads call MPI). -nd_mat_partitioning_type of PETSc's options database
// chooses another of PETSc's types. Otherwise slabs: the cells sorted by their
// centroid's coordinate along the mesh's longest extent, cut in consecutive
// parts of equal counts. Collective (once, when the communicator is given);
// the result is the same on every rank.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fem/space.hpp"
#include "parallel/communicator.hpp"

namespace nd {

struct Ownership {
  int rank = 0, size = 1;
  std::vector<int> cell_owner;  // per cell (empty: one rank owns everything)
  std::vector<int> node_owner;  // per FE node (empty likewise)
  std::vector<int64_t> nodes;   // this rank's nodes, ascending
  std::string method = "one rank";  // "ptscotch", "parmetis", another PETSc type, or "slabs"
  bool owns_cell(int64_t c) const { return cell_owner.empty() || cell_owner[c] == rank; }
};

std::shared_ptr<const Ownership> partition_mesh(const Space &s, const Communicator *c);
// What `rank` of `size` owns when the cells have these owners (ignored on one rank).
Ownership ownership_of_cells(const Space &s, std::vector<int> cell_owner, int rank, int size);

// The slabs of `parts` nearly equal parts (sizes differ by at most one):
// the owner of each cell.
std::vector<int> slab_partition(const Mesh &m, int parts);

#ifdef ND_HAVE_PETSC
// linalg/petsc.cpp: the cell dual graph's rows [cell_begin, cell_begin +
// ia.size() - 1) on this rank (ia, ja: CSR, global cell numbers) partitioned
// over c's ranks; the owner of every cell, on every rank, and the method's
// name, or false when this PETSc has neither PT-Scotch nor ParMETIS and no
// other type was asked for.
bool petsc_partition_cells(const Communicator *c, int64_t n_cells, const std::vector<int64_t> &ia,
                           const std::vector<int64_t> &ja, std::vector<int> &owner, std::string &method);
#endif

}  // namespace nd
