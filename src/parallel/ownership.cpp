#include "parallel/ownership.hpp"

#include <algorithm>
#include <numeric>

namespace nd {

std::vector<int> slab_partition(const Mesh &m, int parts) {
  const int d = m.dim;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int k = 0; k < d; ++k) {
    lo[k] = hi[k] = m.n_vertices ? m.x(0)[k] : 0.0;
    for (int64_t v = 1; v < m.n_vertices; ++v) lo[k] = std::min(lo[k], m.x(v)[k]), hi[k] = std::max(hi[k], m.x(v)[k]);
  }
  int axis = 0;
  for (int k = 1; k < d; ++k)
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  std::vector<double> centre(static_cast<size_t>(m.n_cells), 0.0);
  for (int64_t c = 0; c < m.n_cells; ++c) {
    const int nv = m.cell_vertices(c);
    for (int i = 0; i < nv; ++i) centre[c] += m.x(m.cell(c)[i])[axis] / nv;
  }
  std::vector<int64_t> order(static_cast<size_t>(m.n_cells));
  std::iota(order.begin(), order.end(), int64_t{0});
  std::stable_sort(order.begin(), order.end(), [&](int64_t a, int64_t b) { return centre[a] < centre[b]; });
  std::vector<int> owner(static_cast<size_t>(m.n_cells), 0);
  const int64_t share = m.n_cells / parts, extra = m.n_cells % parts;
  int64_t k = 0;
  for (int r = 0; r < parts; ++r)
    for (int64_t i = 0; i < share + (r < extra ? 1 : 0); ++i) owner[order[k++]] = r;
  return owner;
}

namespace {

#ifdef ND_HAVE_PETSC
// The dual graph's rows of the cells [begin, end): the cells sharing a facet
// (facet_size() vertices) with each, ascending.
void dual_graph(const Mesh &m, int64_t begin, int64_t end, std::vector<int64_t> &ia, std::vector<int64_t> &ja) {
  std::vector<int64_t> first(static_cast<size_t>(m.n_vertices + 1), 0), cells(m.cells.size());
  for (int64_t v : m.cells)
    if (v >= 0) ++first[v + 1];  // (not a mixed mesh's padding)
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<int64_t> next(first.begin(), first.end() - 1);
  for (int64_t c = 0; c < m.n_cells; ++c)
    for (int i = 0; i < m.cell_vertices(c); ++i) cells[next[m.cell(c)[i]]++] = c;
  ia.assign(1, 0);
  ja.clear();
  std::vector<int64_t> met;
  for (int64_t c = begin; c < end; ++c) {
    met.clear();
    for (int i = 0; i < m.cell_vertices(c); ++i) {
      const int64_t v = m.cell(c)[i];
      met.insert(met.end(), cells.begin() + first[v], cells.begin() + first[v + 1]);
    }
    std::sort(met.begin(), met.end());
    for (size_t k = 0; k < met.size();) {  // a neighbour through a facet appears facet_size() times
      size_t e = k;
      while (e < met.size() && met[e] == met[k]) ++e;
      if (met[k] != c && static_cast<int>(e - k) >= m.facet_size()) ja.push_back(met[k]);
      k = e;
    }
    ia.push_back(static_cast<int64_t>(ja.size()));
  }
}
#endif

std::vector<int> partition_cells(const Mesh &m, const Communicator *c, int size, std::string &method) {
#ifdef ND_HAVE_PETSC
  const int rank = communicator_rank(c);
  const int64_t share = m.n_cells / size, extra = m.n_cells % size;
  const int64_t begin = rank * share + std::min<int64_t>(rank, extra);
  const int64_t end = begin + share + (rank < extra ? 1 : 0);
  std::vector<int64_t> ia, ja;
  dual_graph(m, begin, end, ia, ja);
  std::vector<int> owner;
  if (petsc_partition_cells(c, m.n_cells, ia, ja, owner, method)) return owner;
#else
  (void)c;
#endif
  method = "slabs";
  return slab_partition(m, size);
}

}  // namespace

std::shared_ptr<const Ownership> partition_mesh(const Space &s, const Communicator *c) {
  const int size = communicator_size(c), rank = communicator_rank(c);
  std::string method = "one rank";
  std::vector<int> cells;
  if (size > 1) cells = partition_cells(*s.mesh, c, size, method);
  auto own = std::make_shared<Ownership>(ownership_of_cells(s, std::move(cells), rank, size));
  own->method = std::move(method);
  return own;
}

Ownership ownership_of_cells(const Space &s, std::vector<int> cell_owner, int rank, int size) {
  Ownership own;
  own.size = size, own.rank = rank;
  if (size == 1) {
    own.nodes.resize(static_cast<size_t>(s.n_nodes));
    std::iota(own.nodes.begin(), own.nodes.end(), int64_t{0});
    return own;
  }
  own.cell_owner = std::move(cell_owner);
  // a node belongs to its lowest-numbered cell's rank (a node of no cell to rank 0)
  own.node_owner.assign(static_cast<size_t>(s.n_nodes), -1);
  for (int64_t cell = 0; cell < s.mesh->n_cells; ++cell)
    for (int i = 0; i < s.basis_of(cell).n; ++i) {
      int &o = own.node_owner[s.nodes_of(cell)[i]];
      if (o < 0) o = own.cell_owner[cell];
    }
  for (int64_t i = 0; i < s.n_nodes; ++i) {
    int &o = own.node_owner[i];
    if (o < 0) o = 0;
    if (o == own.rank) own.nodes.push_back(i);
  }
  return own;
}

}  // namespace nd
