// Gmsh MSH 4.1 and 2.2 readers (ASCII). The cells of the top dimension form
// the mesh (only the vertices they use are kept); each physical group of
// facet elements becomes the region with the group's tag, each group of
// cells the cell region with its tag (a cell in several: the largest). Higher-order
// Gmsh elements are read through their corner nodes (straight sides); a
// 9-node quadrilateral's or 27-node hexahedron's other nodes must lie where
// the space puts its Q2 nodes (the means of their edges', faces', cell's
// corners), or the file is refused. The cells are all simplices, or all
// quadrilaterals (hexahedra): a mesh holds one cell type.
//
// A file is untrusted input: it is read whole (a NUL byte, as in a binary
// file or /dev/zero, stops the reading at once), every count in it is
// checked against what the rest of the file can hold before it sizes
// anything, and every loop consumes tokens of the file. A file of n bytes
// therefore costs O(n) memory and O(n log n) time, whatever its counts say.
#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.hpp"
#include "mesh/cell_shape.hpp"
#include "mesh/geometry.hpp"
#include "mesh/mesh.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

std::string text_of(std::string_view t) {
  constexpr size_t kShown = 40;  // a message quotes a bounded part of a token
  return t.size() <= kShown ? std::string(t) : std::string(t.substr(0, kShown)) + "...";
}

// The file's text and its whitespace-separated tokens, with line numbers.
class Tokens {
 public:
  explicit Tokens(const char *path) : path_(path) {
    std::unique_ptr<FILE, int (*)(FILE *)> f(std::fopen(path, "rb"), &std::fclose);
    if (!f) fail(ND_ERR_IO, "cannot open '" + path_ + "'");
    char chunk[1 << 16];
    for (;;) {
      const size_t got = std::fread(chunk, 1, sizeof chunk, f.get());
      for (size_t i = 0; i < got; ++i)
        if (chunk[i] == '\0')
          fail(ND_ERR_FORMAT, path_ + ": byte " + std::to_string(text_.size() + i) +
                                  " is NUL: not an ASCII MSH file");
      text_.append(chunk, got);
      if (got < sizeof chunk) break;
    }
    if (std::ferror(f.get())) fail(ND_ERR_IO, "error reading '" + path_ + "'");
  }
  bool next(std::string_view &tok) {
    while (pos_ < text_.size() && is_space(text_[pos_]))
      if (text_[pos_++] == '\n') ++line_;
    if (pos_ == text_.size()) return false;
    const size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    tok = std::string_view(text_).substr(start, pos_ - start);
    return true;
  }
  std::string_view word(const char *what) {
    std::string_view t;
    if (!next(t)) error(std::string("unexpected end of file, expected ") + what);
    return t;
  }
  void expect(const char *w) {
    const std::string_view t = word(w);
    if (t != w) error(std::string("expected '") + w + "', found '" + text_of(t) + "'");
  }
  int64_t integer(const char *what) {
    const std::string_view t = word(what);
    int64_t v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec == std::errc::result_out_of_range)
      error(std::string(what) + " '" + text_of(t) + "' is out of range");
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      error(std::string("expected ") + what + " (an integer), found '" + text_of(t) + "'");
    return v;
  }
  double real(const char *what) {
    std::string_view t = word(what);
    const std::string_view shown = t;
    if (t.size() > 1 && t[0] == '+') t.remove_prefix(1);  // from_chars takes no '+'
    double v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec == std::errc::result_out_of_range) error(std::string(what) + " '" + text_of(shown) + "' is out of range");
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      error(std::string("expected ") + what + " (a number), found '" + text_of(shown) + "'");
    if (!std::isfinite(v)) error(std::string(what) + " '" + text_of(shown) + "' is not finite");
    return v;
  }
  // A count of items that each take at least `tokens` tokens: never negative
  // and never more than the rest of the file can hold (a token and its
  // separator are at least two bytes).
  int64_t count(const char *what, int64_t tokens) {
    const int64_t n = integer(what);
    if (n < 0) error(std::string(what) + " is negative (" + std::to_string(n) + ")");
    if (n > static_cast<int64_t>(remaining() / (2 * static_cast<size_t>(tokens))))
      error(std::string(what) + " (" + std::to_string(n) + ") is more than the rest of the file (" +
            std::to_string(remaining()) + " bytes) can hold");
    return n;
  }
  // skip to the token after "$End<section>"
  void skip_section(std::string_view name) {
    std::string_view t;
    while (next(t))
      if (t.size() == name.size() + 4 && t.substr(0, 4) == "$End" && t.substr(4) == name) return;
    error("section $" + std::string(name) + " has no $End" + std::string(name));
  }
  size_t remaining() const { return text_.size() - pos_; }
  size_t size() const { return text_.size(); }
  const std::string &path() const { return path_; }
  [[noreturn]] void error(const std::string &what) const {
    fail(ND_ERR_FORMAT, path_ + ":" + std::to_string(line_) + ": " + what);
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
  std::string path_;
  std::string text_;
  size_t pos_ = 0;
  int64_t line_ = 1;
};

struct Element {
  int dim;
  int cell_type;                   // ND_CELL_SIMPLEX, _QUADRILATERAL, _HEXAHEDRON
  int64_t tags;                    // index into RawMesh::tag_lists, -1: no physical group
  std::array<int64_t, 8> nodes;    // corner node tags
  int64_t high = -1;               // 9-node quadrilateral, 27-node hexahedron: its other nodes
                                   // in RawMesh::high_order from here; -1: none
};

struct RawMesh {
  std::map<int64_t, std::array<double, 3>> nodes;  // tag -> xyz
  std::vector<std::vector<int64_t>> tag_lists;      // lists of physical tags, shared by elements
  std::vector<Element> elements;
  std::vector<int64_t> high_order;                  // (Element::high)
};

struct ElementType {
  int dim, nodes, corners, cell_type;
};
// The Gmsh element types we read: points, simplices, quadrilaterals and
// hexahedra, first or second order (dim < 0: not supported).
ElementType element_type(int64_t type) {
  switch (type) {
    case 15: return {0, 1, 1, ND_CELL_SIMPLEX};    // point
    case 1: return {1, 2, 2, ND_CELL_SIMPLEX};     // line
    case 8: return {1, 3, 2, ND_CELL_SIMPLEX};     // line, 2nd order
    case 2: return {2, 3, 3, ND_CELL_SIMPLEX};     // triangle
    case 9: return {2, 6, 3, ND_CELL_SIMPLEX};     // triangle, 2nd order
    case 4: return {3, 4, 4, ND_CELL_SIMPLEX};     // tetrahedron
    case 11: return {3, 10, 4, ND_CELL_SIMPLEX};   // tetrahedron, 2nd order
    case 3: return {2, 4, 4, ND_CELL_QUADRILATERAL};   // quadrilateral
    case 10: return {2, 9, 4, ND_CELL_QUADRILATERAL};  // quadrilateral, 9 nodes
    case 5: return {3, 8, 8, ND_CELL_HEXAHEDRON};      // hexahedron
    case 12: return {3, 27, 8, ND_CELL_HEXAHEDRON};    // hexahedron, 27 nodes
    default: return {-1, 0, 0, 0};
  }
}

// Gmsh's prisms and pyramids (first and second order): what joins
// tetrahedra to hexahedra in a conforming 3D mix
const char *prism_or_pyramid(int64_t type) {
  return type == 6 || type == 13 || type == 18 ? "a prism" : type == 7 || type == 14 || type == 19 ? "a pyramid" : nullptr;
}

ElementType supported(Tokens &tk, int64_t type) {
  const ElementType et = element_type(type);
  if (const char *name = prism_or_pyramid(type))
    tk.error("element type " + std::to_string(type) + " is not supported: it is " + name +
             ", and the library has no prisms or pyramids, so it takes no 3D mix of tetrahedra and hexahedra (mixed "
             "meshes are 2D: triangles and quadrilaterals; see nd_mesh_read_gmsh(3))");
  if (et.dim < 0)
    tk.error("element type " + std::to_string(type) + " is not supported (15, 1, 2, 4, 8, 9, 11; 3, 5, 10, 12" +
             (type == 16 || type == 17 ? std::string("; serendipity elements, 8-node quadrilaterals and 20-node "
                                                     "hexahedra, are not: see nd_mesh_create_cells(3)")
                                       : std::string()) +
             ")");
  return et;
}

Element read_element(Tokens &tk, RawMesh &raw, ElementType et, int64_t tags) {
  Element el{et.dim, et.cell_type, tags, {-1, -1, -1, -1, -1, -1, -1, -1}};
  if (et.nodes > et.corners && et.cell_type != ND_CELL_SIMPLEX) el.high = static_cast<int64_t>(raw.high_order.size());
  for (int k = 0; k < et.nodes; ++k) {
    const int64_t node = tk.integer("a node tag");
    if (k < et.corners)
      el.nodes[k] = node;
    else if (el.high >= 0)
      raw.high_order.push_back(node);
  }
  return el;
}

// Gmsh's 9-node quadrilateral and 27-node hexahedron: the corners whose mean
// each of the other nodes is at (edges, faces, the centre; -1 ends a list)
const int kQuad9[5][8] = {{0, 1, -1}, {1, 2, -1}, {2, 3, -1}, {3, 0, -1}, {0, 1, 2, 3, -1}};
const int kHex27[19][8] = {{0, 1, -1}, {0, 3, -1}, {0, 4, -1}, {1, 2, -1}, {1, 5, -1}, {2, 3, -1}, {2, 6, -1},
                           {3, 7, -1}, {4, 5, -1}, {4, 7, -1}, {5, 6, -1}, {6, 7, -1}, {0, 3, 2, 1, -1},
                           {0, 1, 5, 4, -1}, {0, 4, 7, 3, -1}, {1, 2, 6, 5, -1}, {2, 3, 7, 6, -1},
                           {4, 5, 6, 7, -1}, {0, 1, 2, 3, 4, 5, 6, 7}};

void read_node(Tokens &tk, RawMesh &raw, int64_t tag, const std::array<double, 3> &x) {
  if (!raw.nodes.emplace(tag, x).second) tk.error("node " + std::to_string(tag) + " is defined twice");
}

// A section neither reader needs is skipped; anything else is an error.
void other_section(Tokens &tk, std::string_view t) {
  if (t.size() > 1 && t[0] == '$' && t.substr(0, 4) != "$End")
    tk.skip_section(t.substr(1));
  else
    tk.error("expected a section ($Nodes, $Elements, ...), found '" + text_of(t) + "'");
}

void check_total(Tokens &tk, int64_t declared, int64_t found, const char *what) {
  if (declared != found)
    tk.error("the header declares " + std::to_string(declared) + " " + what + ", the blocks hold " +
             std::to_string(found));
}

void read_v4(Tokens &tk, RawMesh &raw) {
  std::map<std::pair<int, int64_t>, int64_t> entity_tags;  // (dim, tag) -> tag list
  bool nodes = false, elements = false;
  std::string_view t;
  while (tk.next(t)) {
    if (t == "$Entities") {
      int64_t count[4];
      for (auto &c : count) c = tk.count("an entity count", 5);
      for (int d = 0; d < 4; ++d)
        for (int64_t e = 0; e < count[d]; ++e) {
          const int64_t tag = tk.integer("an entity tag");
          for (int k = 0; k < (d == 0 ? 3 : 6); ++k) tk.real("a coordinate");
          const int64_t np = tk.count("the number of physical tags", 1);
          std::vector<int64_t> phys;
          phys.reserve(static_cast<size_t>(np));
          for (int64_t k = 0; k < np; ++k) phys.push_back(tk.integer("a physical tag"));
          if (d > 0) {
            const int64_t nb = tk.count("the number of bounding entities", 1);
            for (int64_t k = 0; k < nb; ++k) tk.integer("a bounding entity");
          }
          if (!entity_tags.emplace(std::make_pair(d, tag), static_cast<int64_t>(raw.tag_lists.size())).second)
            tk.error("entity " + std::to_string(tag) + " of dimension " + std::to_string(d) + " is defined twice");
          raw.tag_lists.push_back(std::move(phys));
        }
      tk.expect("$EndEntities");
    } else if (t == "$Nodes") {
      if (nodes) tk.error("a second $Nodes section");
      nodes = true;
      const int64_t blocks = tk.count("the number of node blocks", 4);
      const int64_t total = tk.count("the number of nodes", 4);
      tk.integer("the minimum node tag");
      tk.integer("the maximum node tag");
      int64_t found = 0;
      std::vector<int64_t> tags;
      for (int64_t b = 0; b < blocks; ++b) {
        tk.integer("an entity dimension");
        tk.integer("an entity tag");
        const int64_t parametric = tk.integer("the parametric flag");
        if (parametric) tk.error("parametric node blocks are not supported");
        const int64_t n = tk.count("the number of nodes in the block", 4);  // tag + 3 coordinates
        tags.clear();
        tags.reserve(static_cast<size_t>(n));
        for (int64_t i = 0; i < n; ++i) tags.push_back(tk.integer("a node tag"));
        for (int64_t tag : tags) {
          std::array<double, 3> x;
          for (auto &c : x) c = tk.real("a node coordinate");
          read_node(tk, raw, tag, x);
        }
        found += n;
      }
      check_total(tk, total, found, "nodes");
      tk.expect("$EndNodes");
    } else if (t == "$Elements") {
      if (elements) tk.error("a second $Elements section");
      elements = true;
      const int64_t blocks = tk.count("the number of element blocks", 4);
      const int64_t total = tk.count("the number of elements", 2);
      tk.integer("the minimum element tag");
      tk.integer("the maximum element tag");
      int64_t found = 0;
      for (int64_t b = 0; b < blocks; ++b) {
        const int64_t edim = tk.integer("an entity dimension");
        const int64_t etag = tk.integer("an entity tag");
        const int64_t type = tk.integer("an element type");
        const ElementType et = element_type(type);
        // an element is its tag and its nodes
        const int64_t n = tk.count("the number of elements in the block", 1 + (et.dim < 0 ? 1 : et.nodes));
        if (n > 0) supported(tk, type);
        if (n > 0 && edim != et.dim)
          tk.error("a block of entity dimension " + std::to_string(edim) + " holds elements of type " +
                   std::to_string(type) + " (dimension " + std::to_string(et.dim) + ")");
        const auto it = entity_tags.find({static_cast<int>(edim), etag});
        const int64_t tags = it == entity_tags.end() || raw.tag_lists[it->second].empty() ? -1 : it->second;
        raw.elements.reserve(raw.elements.size() + static_cast<size_t>(n));
        for (int64_t e = 0; e < n; ++e) {
          tk.integer("an element tag");
          raw.elements.push_back(read_element(tk, raw, et, tags));
        }
        found += n;
      }
      check_total(tk, total, found, "elements");
      tk.expect("$EndElements");
    } else {
      other_section(tk, t);
    }
  }
}

void read_v2(Tokens &tk, RawMesh &raw) {
  std::map<int64_t, int64_t> lists;  // physical tag -> its one-tag list
  bool nodes = false, elements = false;
  std::string_view t;
  while (tk.next(t)) {
    if (t == "$Nodes") {
      if (nodes) tk.error("a second $Nodes section");
      nodes = true;
      const int64_t n = tk.count("the number of nodes", 4);  // tag + 3 coordinates
      for (int64_t i = 0; i < n; ++i) {
        const int64_t tag = tk.integer("a node tag");
        std::array<double, 3> x;
        for (auto &c : x) c = tk.real("a node coordinate");
        read_node(tk, raw, tag, x);
      }
      tk.expect("$EndNodes");
    } else if (t == "$Elements") {
      if (elements) tk.error("a second $Elements section");
      elements = true;
      const int64_t n = tk.count("the number of elements", 4);  // tag, type, tag count, a node
      raw.elements.reserve(static_cast<size_t>(n));
      for (int64_t i = 0; i < n; ++i) {
        tk.integer("an element tag");
        const ElementType et = supported(tk, tk.integer("an element type"));
        const int64_t ntags = tk.count("the number of tags", 1);
        int64_t list = -1;
        for (int64_t k = 0; k < ntags; ++k) {
          const int64_t tag = tk.integer("a tag");
          if (k == 0 && tag != 0) {  // the first tag is the physical group
            auto it = lists.emplace(tag, static_cast<int64_t>(raw.tag_lists.size()));
            if (it.second) raw.tag_lists.push_back({tag});
            list = it.first->second;
          }
        }
        raw.elements.push_back(read_element(tk, raw, et, list));
      }
      tk.expect("$EndElements");
    } else {
      other_section(tk, t);
    }
  }
}

// A 9-node quadrilateral's or 27-node hexahedron's other nodes at the means
// of their corners (to 1e-9 of the cell's extent), where the space's Q2
// nodes are: else the element is curved, which the space cannot represent.
// (Gmsh places them through its curves' parametrizations, to ~1e-12 of a
// curve's length: 1.3e-12 off on a unit cube, gmsh 4.8, more where a curve
// spans many cells; a curved cell's nodes are off by its sagitta, h^2/(8 R).)
template <class Position>
void straight_high_order_nodes(const char *path, const Element &e, const double *const *x, const RawMesh &raw,
                               const Position &position) {
  const int d = e.dim, n = d == 2 ? 5 : 19;
  double extent = 0;
  for (int i = 0; i < (1 << d); ++i)
    for (int k = 0; k < d; ++k) extent = std::max(extent, std::fabs(x[i][k] - x[0][k]));
  for (int j = 0; j < n; ++j) {
    const int *corners = d == 2 ? kQuad9[j] : kHex27[j];
    double mean[3] = {0, 0, 0};
    int m = 0;
    while (m < 8 && corners[m] >= 0) ++m;
    for (int i = 0; i < m; ++i)
      for (int k = 0; k < d; ++k) mean[k] += x[corners[i]][k] / m;
    const int64_t tag = raw.high_order[static_cast<size_t>(e.high + j)];
    const auto &p = position(tag);
    for (int k = 0; k < d; ++k)
      if (!(std::fabs(p[k] - mean[k]) <= 1e-9 * extent))
        fail(ND_ERR_FORMAT, std::string(path) + ": node " + std::to_string(tag) + " of a " +
                                (d == 2 ? "9-node quadrilateral" : "27-node hexahedron") +
                                " is not at the mean of its corners (a curved element): only straight-sided "
                                "Q2 cells are read (the space places their nodes)");
  }
}

}  // namespace

Mesh read_gmsh(const char *path) {
  Tokens tk(path);
  tk.expect("$MeshFormat");
  const std::string_view version = tk.word("the format version");
  const bool v4 = version == "4.1", v2 = version == "2.2" || version == "2.1" || version == "2.0" || version == "2";
  if (!v4 && !v2) tk.error("MSH version " + text_of(version) + " is not supported (4.1 and 2.2 are)");
  if (tk.integer("the file type") != 0) tk.error("binary MSH files are not supported; save as ASCII");
  tk.integer("the data size");
  tk.expect("$EndMeshFormat");
  RawMesh raw;
  if (v4)
    read_v4(tk, raw);
  else
    read_v2(tk, raw);

  int top = -1;
  for (const Element &e : raw.elements) top = std::max(top, e.dim);
  if (top < 1) fail(ND_ERR_FORMAT, std::string(path) + ": no line, triangle, quadrilateral, tetrahedron or hexahedron elements");
  // the top-dimensional elements' types: one, or (2D) triangles and quadrilaterals
  bool has[3] = {false, false, false};
  for (const Element &e : raw.elements)
    if (e.dim == top) has[e.cell_type] = true;
  const bool mixed = top == 2 && has[ND_CELL_SIMPLEX] && has[ND_CELL_QUADRILATERAL];
  if (has[ND_CELL_SIMPLEX] && has[ND_CELL_HEXAHEDRON])
    fail(ND_ERR_FORMAT, std::string(path) + ": the cells mix tetrahedra and hexahedra: a conforming 3D mix needs "
                                            "pyramids or prisms, which this library does not have (mixed meshes are "
                                            "2D: triangles and quadrilaterals)");
  const int cell_type = mixed ? kMixedCells : has[ND_CELL_SIMPLEX] ? ND_CELL_SIMPLEX : top - 1;
  const int stride = mixed ? 4 : cell_type == ND_CELL_SIMPLEX ? top + 1 : 1 << top;  // (padded as Mesh::cells)
  std::vector<int> types;  // each cell's (a mixed mesh's)
  // keep the vertices of top-dimensional cells, numbered by first use
  std::map<int64_t, int64_t> index;
  std::vector<double> coords;
  std::vector<int64_t> cells;
  auto position = [&](int64_t tag) -> const std::array<double, 3> & {
    auto node = raw.nodes.find(tag);
    if (node == raw.nodes.end())
      fail(ND_ERR_FORMAT, std::string(path) + ": an element uses node " + std::to_string(tag) + ", which is not in $Nodes");
    return node->second;
  };
  auto vertex = [&](int64_t tag) {
    auto it = index.find(tag);
    if (it != index.end()) return it->second;
    const int64_t id = static_cast<int64_t>(index.size());
    const auto &x = position(tag);
    index.emplace(tag, id);
    for (int k = 0; k < top; ++k) coords.push_back(x[k]);
    return id;
  };
  std::vector<int> cell_region;  // each cell's largest physical tag, 0: none
  bool any_group = false;         // (none: the mesh keeps no cell regions)
  for (const Element &e : raw.elements) {
    if (e.dim != top) continue;
    int64_t tag = 0;
    if (e.tags >= 0)
      for (int64_t t : raw.tag_lists[e.tags]) tag = std::max(tag, t);
    if (tag > 2147483647)
      fail(ND_ERR_FORMAT, std::string(path) + ": physical tag " + std::to_string(tag) + " is not a valid cell region");
    cell_region.push_back(static_cast<int>(tag));
    any_group = any_group || tag > 0;
    const int nv = e.cell_type == ND_CELL_SIMPLEX ? top + 1 : 1 << top;
    const double *x[8];
    for (int i = 0; i < nv; ++i) x[i] = position(e.nodes[i]).data();
    if (e.high >= 0) straight_high_order_nodes(path, e, x, raw, position);
    double J[9];
    const double centre[3] = {0.5, 0.5, 0.5};
    if (e.cell_type == ND_CELL_SIMPLEX)
      simplex_jacobian(top, x, J);
    else
      cube::jacobian(top, x, centre, J);
    std::array<int64_t, 8> v = e.nodes;
    if (determinant(top, J) < 0) {  // Gmsh does not fix the orientation
      if (e.cell_type == ND_CELL_SIMPLEX) std::swap(v[0], v[1]);
      if (e.cell_type == ND_CELL_QUADRILATERAL) std::swap(v[1], v[3]);
      if (e.cell_type == ND_CELL_HEXAHEDRON) std::swap_ranges(v.begin(), v.begin() + 4, v.begin() + 4);
    }
    for (int i = 0; i < stride; ++i) cells.push_back(i < nv ? vertex(v[i]) : -1);
    types.push_back(e.cell_type);
  }
  // two used nodes at one position: refused with their tags (unused nodes,
  // which Gmsh files may repeat, were left out above)
  {
    std::vector<int64_t> tags(index.size());
    for (const auto &[tag, id] : index) tags[static_cast<size_t>(id)] = tag;
    const int64_t n = static_cast<int64_t>(index.size());
    const std::vector<int64_t> component =
        vertex_components(n, static_cast<int64_t>(types.size()), cells.data(), stride);
    refuse_duplicate_vertices(top, n, coords.data(), std::string(path) + ": ", tags.data(), &component);
  }
  if (mixed) cells.erase(std::remove(cells.begin(), cells.end(), -1), cells.end());  // (each cell's own count)
  const int64_t n_vertices = static_cast<int64_t>(index.size()), n_cells = static_cast<int64_t>(types.size());
  Mesh m = mixed ? make_mixed_mesh(top, n_vertices, coords.data(), n_cells, types.data(), cells.data(),
                                   std::string(path) + ": ")
                 : make_mesh(top, n_vertices, coords.data(), n_cells, cells.data(), std::string(path) + ": ", cell_type);
  if (any_group) m.cell_region = std::move(cell_region);
  // facet elements of physical groups -> regions. Each (facet, group) pair
  // costs memory: a file may name at most as many pairs as it has bytes
  // (a facet element line in a real file is longer than its group count).
  std::map<int64_t, std::vector<int64_t>> facets;
  size_t pairs = 0;
  for (const Element &e : raw.elements) {
    if (e.dim != top - 1 || e.tags < 0) continue;
    const std::vector<int64_t> &tags = raw.tag_lists[e.tags];
    const int nf = m.facet_size();
    if ((e.cell_type == ND_CELL_SIMPLEX ? e.dim + 1 : 1 << e.dim) != nf)
      fail(ND_ERR_FORMAT, std::string(path) + ": a facet of physical group " + std::to_string(tags[0]) +
                              " is not a facet of the cells (" + (nf == 4 ? "a quadrilateral" : "a triangle") +
                              " expected)");
    int64_t v[4];
    for (int i = 0; i < nf; ++i) {
      auto it = index.find(e.nodes[i]);
      if (it == index.end())
        fail(ND_ERR_FORMAT, std::string(path) + ": a facet of physical group " + std::to_string(tags[0]) + " uses a node of no cell");
      v[i] = it->second;
    }
    pairs += tags.size();
    if (pairs > tk.size())
      fail(ND_ERR_FORMAT, std::string(path) + ": the facets name more (facet, physical group) pairs than the file has bytes");
    for (int64_t tag : tags) facets[tag].insert(facets[tag].end(), v, v + nf);
  }
  for (auto &kv : facets)
    if (kv.first < 0 || kv.first > 2147483647)
      fail(ND_ERR_FORMAT, std::string(path) + ": physical tag " + std::to_string(kv.first) + " is not a valid region");
  add_region_groups(m, facets, std::string(path) + ": physical group ");
  return m;
}

}  // namespace nd
