// Gmsh MSH 4.1 and 2.2 readers (ASCII). The cells of the top dimension form
// the mesh (only the vertices they use are kept); each physical group of
// facet elements becomes the region with the group's tag. Higher-order
// Gmsh elements are read through their corner nodes (straight sides).
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/c_locale.hpp"
#include "common/error.hpp"
#include "mesh/geometry.hpp"
#include "mesh/mesh.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// Whitespace-separated tokens with the line each came from.
class Tokens {
 public:
  explicit Tokens(const char *path) : path_(path), in_(path) {
    if (!in_) fail(ND_ERR_IO, std::string("cannot open '") + path + "'");
  }
  bool next(std::string &tok) {
    while (!(line_in_ >> tok)) {
      std::string line;
      if (!std::getline(in_, line)) return false;
      ++line_;
      line_in_.clear();
      line_in_.str(line);
    }
    return true;
  }
  std::string word(const char *what) {
    std::string t;
    if (!next(t)) error(std::string("unexpected end of file, expected ") + what);
    return t;
  }
  void expect(const std::string &w) {
    const std::string t = word(w.c_str());
    if (t != w) error("expected '" + w + "', found '" + t + "'");
  }
  int64_t integer(const char *what) {
    const std::string t = word(what);
    char *end = nullptr;
    const long long v = std::strtoll(t.c_str(), &end, 10);
    if (*end) error(std::string("expected ") + what + " (an integer), found '" + t + "'");
    return v;
  }
  double real(const char *what) {
    const std::string t = word(what);
    char *end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (*end) error(std::string("expected ") + what + " (a number), found '" + t + "'");
    return v;
  }
  // skip to the line after "$End<section>"
  void skip_section(const std::string &name) {
    std::string t;
    while (next(t))
      if (t == "$End" + name) return;
    error("section $" + name + " has no $End" + name);
  }
  [[noreturn]] void error(const std::string &what) const {
    fail(ND_ERR_FORMAT, path_ + ":" + std::to_string(line_) + ": " + what);
  }

 private:
  std::string path_;
  std::ifstream in_;
  std::istringstream line_in_;
  int64_t line_ = 0;
};

struct Element {
  int dim;
  std::vector<int64_t> tags;  // physical tags
  std::vector<int64_t> nodes; // corner node tags
};

struct RawMesh {
  std::map<int64_t, std::array<double, 3>> nodes;  // tag -> xyz
  std::vector<Element> elements;
};

// An element of a given Gmsh type: its dimension, and its node tags of which
// the corners are kept (simplices and points only, first or second order).
Element read_element(Tokens &tk, int64_t type, std::vector<int64_t> tags) {
  int dim, nodes;
  switch (type) {
    case 15: dim = 0, nodes = 1; break;   // point
    case 1: dim = 1, nodes = 2; break;    // line
    case 8: dim = 1, nodes = 3; break;    // line, 2nd order
    case 2: dim = 2, nodes = 3; break;    // triangle
    case 9: dim = 2, nodes = 6; break;    // triangle, 2nd order
    case 4: dim = 3, nodes = 4; break;    // tetrahedron
    case 11: dim = 3, nodes = 10; break;  // tetrahedron, 2nd order
    default:
      tk.error("element type " + std::to_string(type) + " is not supported (simplices only: 15, 1, 2, 4, 8, 9, 11)");
  }
  Element el{dim, std::move(tags), {}};
  for (int k = 0; k < nodes; ++k) {
    const int64_t node = tk.integer("a node tag");
    if (k <= dim) el.nodes.push_back(node);
  }
  return el;
}

// A section neither reader needs is skipped; anything else is an error.
void other_section(Tokens &tk, const std::string &t) {
  if (t.size() > 1 && t[0] == '$' && t.compare(0, 4, "$End") != 0)
    tk.skip_section(t.substr(1));
  else
    tk.error("expected a section ($Nodes, $Elements, ...), found '" + t + "'");
}

void read_v4(Tokens &tk, RawMesh &raw) {
  std::map<std::pair<int, int64_t>, std::vector<int64_t>> entity_tags;  // (dim, tag) -> physical
  std::string t;
  while (tk.next(t)) {
    if (t == "$Entities") {
      int64_t count[4];
      for (auto &c : count) c = tk.integer("an entity count");
      for (int d = 0; d < 4; ++d)
        for (int64_t e = 0; e < count[d]; ++e) {
          const int64_t tag = tk.integer("an entity tag");
          for (int k = 0; k < (d == 0 ? 3 : 6); ++k) tk.real("a coordinate");
          const int64_t np = tk.integer("the number of physical tags");
          auto &phys = entity_tags[{d, tag}];
          for (int64_t k = 0; k < np; ++k) phys.push_back(tk.integer("a physical tag"));
          if (d > 0) {
            const int64_t nb = tk.integer("the number of bounding entities");
            for (int64_t k = 0; k < nb; ++k) tk.integer("a bounding entity");
          }
        }
      tk.expect("$EndEntities");
    } else if (t == "$Nodes") {
      const int64_t blocks = tk.integer("the number of node blocks");
      tk.integer("the number of nodes");
      tk.integer("the minimum node tag");
      tk.integer("the maximum node tag");
      for (int64_t b = 0; b < blocks; ++b) {
        tk.integer("an entity dimension");
        tk.integer("an entity tag");
        const int64_t parametric = tk.integer("the parametric flag");
        const int64_t n = tk.integer("the number of nodes in the block");
        if (parametric) tk.error("parametric node blocks are not supported");
        std::vector<int64_t> tags(n);
        for (auto &tag : tags) tag = tk.integer("a node tag");
        for (int64_t tag : tags) {
          auto &x = raw.nodes[tag];
          for (auto &c : x) c = tk.real("a node coordinate");
        }
      }
      tk.expect("$EndNodes");
    } else if (t == "$Elements") {
      const int64_t blocks = tk.integer("the number of element blocks");
      tk.integer("the number of elements");
      tk.integer("the minimum element tag");
      tk.integer("the maximum element tag");
      for (int64_t b = 0; b < blocks; ++b) {
        const int64_t edim = tk.integer("an entity dimension");
        const int64_t etag = tk.integer("an entity tag");
        const int64_t type = tk.integer("an element type");
        const int64_t n = tk.integer("the number of elements in the block");
        const auto &phys = entity_tags[{static_cast<int>(edim), etag}];
        for (int64_t e = 0; e < n; ++e) {
          tk.integer("an element tag");
          raw.elements.push_back(read_element(tk, type, phys));
        }
      }
      tk.expect("$EndElements");
    } else {
      other_section(tk, t);
    }
  }
}

void read_v2(Tokens &tk, RawMesh &raw) {
  std::string t;
  while (tk.next(t)) {
    if (t == "$Nodes") {
      const int64_t n = tk.integer("the number of nodes");
      for (int64_t i = 0; i < n; ++i) {
        auto &x = raw.nodes[tk.integer("a node tag")];
        for (auto &c : x) c = tk.real("a node coordinate");
      }
      tk.expect("$EndNodes");
    } else if (t == "$Elements") {
      const int64_t n = tk.integer("the number of elements");
      for (int64_t i = 0; i < n; ++i) {
        tk.integer("an element tag");
        const int64_t type = tk.integer("an element type");
        const int64_t ntags = tk.integer("the number of tags");
        std::vector<int64_t> phys;
        for (int64_t k = 0; k < ntags; ++k) {
          const int64_t tag = tk.integer("a tag");
          if (k == 0 && tag != 0) phys.push_back(tag);  // the first tag is the physical group
        }
        raw.elements.push_back(read_element(tk, type, std::move(phys)));
      }
      tk.expect("$EndElements");
    } else {
      other_section(tk, t);
    }
  }
}

}  // namespace

Mesh read_gmsh(const char *path) {
  const ClassicNumericLocale c_locale;  // numbers in the file use '.', whatever the caller's locale
  Tokens tk(path);
  tk.expect("$MeshFormat");
  const std::string version = tk.word("the format version");
  const bool v4 = version == "4.1", v2 = version.compare(0, 2, "2.") == 0;
  if (!v4 && !v2) tk.error("MSH version " + version + " is not supported (4.1 and 2.2 are)");
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
  if (top < 1) fail(ND_ERR_FORMAT, std::string(path) + ": no line, triangle or tetrahedron elements");
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
    index.emplace(tag, id);
    for (int k = 0; k < top; ++k) coords.push_back(position(tag)[k]);
    return id;
  };
  for (const Element &e : raw.elements) {
    if (e.dim != top) continue;
    const double *x[4];
    for (int i = 0; i <= top; ++i) x[i] = position(e.nodes[i]).data();
    double J[9];
    simplex_jacobian(top, x, J);
    std::vector<int64_t> v = e.nodes;
    if (determinant(top, J) < 0) std::swap(v[0], v[1]);  // Gmsh does not fix the orientation
    for (int64_t tag : v) cells.push_back(vertex(tag));
  }
  Mesh m = make_mesh(top, static_cast<int64_t>(index.size()), coords.data(),
                     static_cast<int64_t>(cells.size()) / (top + 1), cells.data(),
                     std::string(path) + ": ");
  // facet elements of physical groups -> regions
  std::map<int64_t, std::vector<int64_t>> facets;
  for (const Element &e : raw.elements) {
    if (e.dim != top - 1 || e.tags.empty()) continue;
    std::vector<int64_t> v;
    for (int64_t tag : e.nodes) {
      auto it = index.find(tag);
      if (it == index.end()) fail(ND_ERR_FORMAT, std::string(path) + ": a facet of physical group " + std::to_string(e.tags[0]) + " uses a node of no cell");
      v.push_back(it->second);
    }
    for (int64_t tag : e.tags) facets[tag].insert(facets[tag].end(), v.begin(), v.end());
  }
  for (auto &kv : facets) {
    if (kv.first < 0 || kv.first > 2147483647) fail(ND_ERR_FORMAT, std::string(path) + ": physical tag " + std::to_string(kv.first) + " is not a valid region");
    add_region_facets(m, static_cast<int>(kv.first), static_cast<int64_t>(kv.second.size()) / top, kv.second.data(),
                      std::string(path) + ": physical group " + std::to_string(kv.first) + ": ");
  }
  return m;
}

}  // namespace nd
