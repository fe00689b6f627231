#include "io/vtu.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "assembly/stress.hpp"
#include "common/c_locale.hpp"
#include "common/checked.hpp"
#include "common/error.hpp"
#include "common/atomic_file.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// XML attribute text: markup characters escaped, tab, newline and carriage
// return as character references; the other control characters cannot be
// represented in XML 1.0 at all (not even as references): refused.
std::string xml_attribute(const char *s, const std::string &name) {
  std::string out;
  for (const char *c = s; *c; ++c) {
    const unsigned char u = static_cast<unsigned char>(*c);
    switch (u) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      case '\t': out += "&#9;"; break;
      case '\n': out += "&#10;"; break;
      case '\r': out += "&#13;"; break;
      default:
        if (u < 0x20)
          fail(ND_ERR_VALUE, name + " contains control character " + std::to_string(u) + " at byte " +
                                 std::to_string(c - s) + ", which XML 1.0 cannot represent");
        out += *c;
    }
  }
  return out;
}

// VTK cell types and the VTK order of our local nodes (vertices, then edges
// (0,1),(0,2),...,(1,2),... lexicographically).
struct VtkCell {
  int type;
  std::vector<int> order;
};
VtkCell vtk_cell(int dim, int degree, int cell_type) {
  if (cell_type != ND_CELL_SIMPLEX) {  // (the local order is VTK's: fem/simplex.hpp)
    std::vector<int> order(static_cast<size_t>(degree == 1 ? 1 << dim : dim == 2 ? 9 : 27));
    for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
    return {degree == 1 ? (dim == 2 ? 9 : 12) : (dim == 2 ? 28 : 29), order};
  }
  if (degree == 1) return {dim == 1 ? 3 : dim == 2 ? 5 : 10, dim == 1 ? std::vector<int>{0, 1} : dim == 2 ? std::vector<int>{0, 1, 2} : std::vector<int>{0, 1, 2, 3}};
  if (dim == 1) return {21, {0, 1, 2}};
  if (dim == 2) return {22, {0, 1, 2, 3, 5, 4}};        // edges (0,1),(1,2),(2,0)
  return {24, {0, 1, 2, 3, 4, 7, 5, 6, 8, 9}};           // (0,1),(1,2),(2,0),(0,3),(1,3),(2,3)
}
// vertex, line, triangle or quadrilateral
int vtk_facet_type(const Mesh &m) { return m.dim == 1 ? 1 : m.dim == 2 ? 3 : m.all_simplices() ? 5 : 9; }

void write_vector_field(FILE *f, const char *name, const std::vector<double> &full, int dim, int64_t n) {
  std::fprintf(f, "        <DataArray type=\"Float64\" Name=\"%s\" NumberOfComponents=\"3\" format=\"ascii\">\n", name);
  for (int64_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) std::fprintf(f, "%.17g%c", k < dim ? full[i * dim + k] : 0.0, k == 2 ? '\n' : ' ');
  std::fprintf(f, "        </DataArray>\n");
}

}  // namespace

void write_vtu(const VtuSnapshot &snap, const char *path) {
  const ClassicNumericLocale c_locale;  // VTK wants '.' as the decimal point
  const Space &s = *snap.space;
  const Mesh &m = *s.mesh;
  const int d = s.dim;
  const std::vector<double> &U = snap.U, &V = snap.V;
  // mean contact pressure per contact facet
  const ContactPoints &cp = *snap.contact;
  const std::vector<double> &lam = snap.pressure;
  std::map<int64_t, std::pair<double, double>> facet_pressure;  // facet -> (sum w lambda, sum w)
  for (size_t q = 0; q < cp.size(); ++q) {
    auto &acc = facet_pressure[cp.facet[q]];
    acc.first += cp.w[q] * lam[q];
    acc.second += cp.w[q];
  }
  // (each cell its type's: a mixed mesh's triangles and quadrilaterals)
  const VtkCell cells[2] = {vtk_cell(d, s.degree, ND_CELL_SIMPLEX), vtk_cell(d, s.degree, d == 1 ? 0 : d - 1)};
  auto cell_of = [&](int64_t c) -> const VtkCell & { return cells[m.simplicial(c) ? 0 : 1]; };
  const int facet_size = m.facet_size();
  const int64_t n_cells = m.n_cells, n_facets = static_cast<int64_t>(facet_pressure.size());
  AtomicFile f(path);
  FILE *o = f.get();
  std::fprintf(o, "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
  // the time and step index, as ParaView and VisIt read them from FieldData
  std::fprintf(o, "  <UnstructuredGrid>\n    <FieldData>\n");
  std::fprintf(o, "      <DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"ascii\">%.17g</DataArray>\n",
               snap.time);
  std::fprintf(o, "      <DataArray type=\"Int64\" Name=\"CYCLE\" NumberOfTuples=\"1\" format=\"ascii\">%lld</DataArray>\n",
               static_cast<long long>(snap.step));
  std::fprintf(o, "    </FieldData>\n    <Piece NumberOfPoints=\"%lld\" NumberOfCells=\"%lld\">\n",
               static_cast<long long>(s.n_nodes), static_cast<long long>(n_cells + n_facets));
  std::fprintf(o, "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
  for (int64_t i = 0; i < s.n_nodes; ++i)
    for (int k = 0; k < 3; ++k) std::fprintf(o, "%.17g%c", k < d ? s.node_x(i)[k] : 0.0, k == 2 ? '\n' : ' ');
  std::fprintf(o, "        </DataArray>\n      </Points>\n      <Cells>\n");
  std::fprintf(o, "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (int64_t c = 0; c < n_cells; ++c) {
    const VtkCell &cell = cell_of(c);
    for (size_t k = 0; k < cell.order.size(); ++k)
      std::fprintf(o, "%lld%c", static_cast<long long>(s.nodes_of(c)[cell.order[k]]), k + 1 == cell.order.size() ? '\n' : ' ');
  }
  for (auto &fp : facet_pressure) {  // contact facets through their vertices
    const auto v = m.facet_vertices(m.boundary[fp.first]);
    for (int k = 0; k < facet_size; ++k)
      std::fprintf(o, "%lld%c", static_cast<long long>(v[k]), k + 1 == facet_size ? '\n' : ' ');
  }
  std::fprintf(o, "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  int64_t offset = 0;
  for (int64_t c = 0; c < n_cells; ++c)
    std::fprintf(o, "%lld\n", static_cast<long long>(offset += static_cast<int64_t>(cell_of(c).order.size())));
  for (int64_t k = 0; k < n_facets; ++k) std::fprintf(o, "%lld\n", static_cast<long long>(offset += facet_size));
  std::fprintf(o, "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (int64_t c = 0; c < n_cells; ++c) std::fprintf(o, "%d\n", cell_of(c).type);
  for (int64_t k = 0; k < n_facets; ++k) std::fprintf(o, "%d\n", vtk_facet_type(m));
  std::fprintf(o, "        </DataArray>\n      </Cells>\n      <PointData Vectors=\"displacement\">\n");
  write_vector_field(o, "displacement", U, d, s.n_nodes);
  write_vector_field(o, "velocity", V, d, s.n_nodes);
  std::fprintf(o, "      </PointData>\n      <CellData Scalars=\"contact_pressure\"%s>\n", d == 1 ? "" : " Tensors=\"stress\"");
  std::fprintf(o, "        <DataArray type=\"Float64\" Name=\"contact_pressure\" format=\"ascii\">\n");
  for (int64_t c = 0; c < n_cells; ++c) std::fprintf(o, "0\n");
  for (auto &fp : facet_pressure) std::fprintf(o, "%.17g\n", fp.second.first / fp.second.second);
  std::fprintf(o, "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"contact_facet\" format=\"ascii\">\n");
  for (int64_t c = 0; c < n_cells + n_facets; ++c) std::fprintf(o, "%d\n", c >= n_cells ? 1 : 0);
  // the Cauchy stress at each cell's centroid (constant on a P1 cell; of a
  // quadrilateral or hexahedron: its reference centre's image); the
  // contact facets get zeros. 1D: sigma_xx alone; 2D/3D: 3x3, row-major.
  const int n_comp = d == 1 ? 1 : 9;
  std::fprintf(o, "        </DataArray>\n        <DataArray type=\"Float64\" Name=\"stress\" NumberOfComponents=\"%d\" format=\"ascii\">\n", n_comp);
  const double simplex_centre[3] = {1.0 / (d + 1), 1.0 / (d + 1), 1.0 / (d + 1)}, cube_centre[3] = {0.5, 0.5, 0.5};
  for (int64_t c = 0; c < n_cells; ++c) {
    double sigma[9];
    cell_stress(s, *snap.material, U.data(), c, m.simplicial(c) ? simplex_centre : cube_centre, sigma);
    for (int k = 0; k < n_comp; ++k) std::fprintf(o, "%.17g%c", sigma[k], k + 1 == n_comp ? '\n' : ' ');
  }
  for (int64_t k = 0; k < n_facets; ++k)
    for (int j = 0; j < n_comp; ++j) std::fprintf(o, "0%c", j + 1 == n_comp ? '\n' : ' ');
  std::fprintf(o, "        </DataArray>\n      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
  f.commit();
}

void write_pvd(const char *path, int64_t n, const char *const *files, const double *times) {
  std::vector<std::string> names;
  names.reserve(checked_count<std::string>(n, "n"));
  for (int64_t i = 0; i < n; ++i) {
    const std::string name = "vtu_files[" + std::to_string(i) + "]";
    if (!files[i]) fail(ND_ERR_NULL, name + " is NULL");
    if (!std::isfinite(times[i])) fail(ND_ERR_NONFINITE, "times[" + std::to_string(i) + "] is not finite");
    names.push_back(xml_attribute(files[i], name));
  }
  const ClassicNumericLocale c_locale;
  AtomicFile f(path);
  std::fprintf(f.get(), "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n");
  for (int64_t i = 0; i < n; ++i)
    std::fprintf(f.get(), "    <DataSet timestep=\"%.17g\" part=\"0\" file=\"%s\"/>\n", times[i], names[i].c_str());
  std::fprintf(f.get(), "  </Collection>\n</VTKFile>\n");
  f.commit();
}

}  // namespace nd
