// Reading a scene file (TOML, toml++): every table has a fixed set of keys,
// an unknown key is an error, and every error names the file, the line and
// the key.
#include "scene.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <algorithm>
#include <map>
#include <sstream>
#include <toml++/toml.h>

#include "nitschedyn.h"
#include "step_count.h"

namespace ndcli {
namespace {

// The keys of every table (the regions table has names chosen by the user).
const std::map<std::string, std::vector<std::string>> &table_keys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"", {"title", "mesh", "regions", "material", "loads", "dirichlet", "obstacle", "contact_pair", "nitsche",
            "scheme", "time", "solver", "initial", "output", "guards", "checkpoint"}},
      {"mesh", {"gmsh", "generate", "cells", "cell_type", "lo", "hi", "degree"}},
      {"regions.NAME", {"id", "lo", "hi"}},
      {"material", {"E", "nu", "rho", "damping", "plane_stress", "region", "lo", "hi"}},
      {"loads", {"body_force", "traction", "nodal"}},
      {"loads.traction", {"region", "value"}},
      {"loads.nodal", {"node", "value"}},
      {"dirichlet", {"regions", "motion"}},
      {"dirichlet.motion", {"region", "displacement"}},
      {"obstacle", {"region", "shape", "point", "normal", "center", "radius", "axis", "inside", "velocity", "position",
                    "rotation", "friction"}},
      {"obstacle.friction", {"law", "coefficient", "threshold"}},
      {"contact_pair", {"slave", "master", "friction"}},
      {"contact_pair.friction", {"law", "coefficient", "threshold"}},
      {"nitsche", {"Theta", "gamma0"}},
      {"scheme", {"name", "theta", "beta", "gamma", "rho_inf"}},
      {"time", {"tau", "T", "tolerance", "tau_min", "tau_max"}},
      {"solver", {"linear", "newton_rtol", "newton_atol", "newton_max_iter", "mass_lumping", "mass_redistribution"}},
      {"initial", {"displacement", "velocity"}},
      {"output", {"history", "paraview", "interval"}},
      {"guards", {"energy", "energy_balance", "penetration", "critical_timestep", "unstable_scheme", "coercivity",
                  "initial_penetration"}},
      {"checkpoint", {"file", "every"}},
  };
  return keys;
}

// --- the text, before toml++ sees it --------------------------------------

// "path:line:col" of the byte at i (columns count characters, as toml++'s do)
std::string place(std::string_view text, size_t i, const std::string &path) {
  size_t line = 1, col = 1;
  for (size_t k = 0; k < i && k < text.size(); ++k) {
    if (text[k] == '\n') {
      ++line;
      col = 1;
    } else if ((static_cast<unsigned char>(text[k]) & 0xC0) != 0x80) {
      ++col;
    }
  }
  return path + ":" + std::to_string(line) + ":" + std::to_string(col);
}

// "the character U+00A7" for the UTF-8 sequence at i, or "the byte 0xFF"
// when it is not one (the character itself is not printed)
std::string character_at(std::string_view text, size_t i) {
  const auto b = [&](size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u; };
  const unsigned lead = b(i);
  const int n = lead >= 0xF0 && lead < 0xF5 ? 4 : lead >= 0xE0 ? (lead < 0xF0 ? 3 : 0) : lead >= 0xC2 ? 2 : 0;
  char buf[64];
  if (n == 0) {
    std::snprintf(buf, sizeof buf, "the byte 0x%02X", lead);
    return buf;
  }
  unsigned long cp = lead & (0x7Fu >> n);
  for (int k = 1; k < n; ++k) {
    if ((b(i + k) & 0xC0) != 0x80) {
      std::snprintf(buf, sizeof buf, "the byte 0x%02X", lead);
      return buf;
    }
    cp = (cp << 6) | (b(i + k) & 0x3F);
  }
  std::snprintf(buf, sizeof buf, "the character U+%04lX", cp);
  return buf;
}

// YYYY-MM-DD
bool is_date(std::string_view s) {
  for (size_t k = 0; k < 10; ++k)
    if (k == 4 || k == 7 ? s[k] != '-' : !(s[k] >= '0' && s[k] <= '9')) return false;
  return true;
}

bool bare_key_char(unsigned char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

// Refuses what toml++ 3.3.0 must not see. TOML allows none of it but the
// first (a scene needs none of it), and each was found to crash toml++ or to
// reach undefined behaviour in it (by the fuzz target tests/fuzz/fuzz_scene,
// which runs it with its assertions on, and by parsing every character in
// 56 contexts):
//  - a dotted key or table name of more than kMaxKeyParts parts (its tables
//    nest once per part: a 50,000-part key overflows the stack), and arrays
//    and inline tables nested more than kMaxNesting deep;
//  - a non-ASCII character outside strings and comments, and in a
//    multi-line basic string right after a backslash or after the white
//    space that follows a line-ending backslash: there toml++ asks whether
//    it is white space, and is_non_ascii_horizontal_whitespace reaches
//    __builtin_unreachable for the 3019 characters of U+00A1-U+0499,
//    U+2C5E-U+2FFF, U+3001-U+3057 and U+FB26-U+FEFE (in a table name any
//    non-ASCII character also fails an assertion);
//  - a quote after a digit or a sign with no value terminator (white space,
//    ',', ']', '}' or '#') between them: toml++ reads a number, date or
//    time on to the next terminator before it looks at it (2"...",
//    1=["..."), so what follows is not a string to it;
//  - a lone digit after a number or date and one space (1979-05-27 0, a
//    date-time with a space cut short), a date and 'T' not followed by a
//    digit (1979-05-27Tx), a table header that does not begin
//    with a name ([$x]), and a bracket closed by the other kind ([}): toml++
//    asserts against each, and its assertions are assumptions
//    (__builtin_assume) in release builds.
void check_text(std::string_view text, const std::string &path) {
  if (text.size() > kMaxSceneBytes)
    throw SceneError(path + ": the scene is " + std::to_string(text.size()) + " bytes; at most " +
                     std::to_string(kMaxSceneBytes) + " (1 MiB) are read");
  enum { normal, comment, basic, literal, ml_basic, ml_literal } state = normal;
  enum { none, after_backslash, skipping } escape = none;  // in a multi-line basic string
  int depth = 0, parts = 1;
  char open[kMaxNesting];  // the brackets open, innermost last
  bool number = false;  // a digit or sign since the last value terminator (outside strings)
  size_t number_space = std::string_view::npos;  // a space right after such a run
  bool line_start = true;  // nothing but spaces and tabs yet on this line (outside strings)
  const auto fail = [&](size_t i, const std::string &msg) { throw SceneError(place(text, i, path) + ": " + msg); };
  const auto non_ascii = [&](size_t i, const char *where) {
    fail(i, character_at(text, i) + " " + where +
                ": only ASCII may be written there (bare keys are A-Za-z0-9_-; quote a key or a value that "
                "needs other characters)");
  };
  // the end of a multi-line string at i ("""), with up to two more quotes in it
  const auto close_multi_line = [&](size_t &i, char q) {
    if (!(i + 2 < text.size() && text[i + 1] == q && text[i + 2] == q)) return false;
    i += 2;
    for (int extra = 0; extra < 2 && i + 1 < text.size() && text[i + 1] == q; ++extra) ++i;
    return true;
  };
  size_t i = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a byte-order mark, which toml++ skips
  for (; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    switch (state) {
    case normal:
      if (c >= 0x80) non_ascii(i, "outside a quoted string or a comment");
      if (c == '[' && line_start && depth == 0) {  // a table header: [name] or [[name]]
        size_t j = i + 1;
        if (j < text.size() && text[j] == '[') ++j;
        while (j < text.size() && (text[j] == ' ' || text[j] == '\t')) ++j;
        const unsigned char n = j < text.size() ? static_cast<unsigned char>(text[j]) : ']';
        if (!bare_key_char(n) && n != '"' && n != '\'' && n != ']' && n < 0x80)
          fail(j, "a table header must begin with a name (A-Za-z0-9_- or a quoted string)");
      }
      if (c == '\n') line_start = true;
      else if (c != ' ' && c != '\t') line_start = false;
      if (c >= '0' && c <= '9' && i > 0 && number_space == i - 1) {
        const char n = i + 1 < text.size() ? text[i + 1] : 'x';
        if (n == ' ' || (n >= '\t' && n <= '\r') || n == ']' || n == '}' || n == ',' || n == '#')
          fail(i, "a single digit after a number or a date and a space (a time is written HH:MM:SS)");
      }
      if ((c == 'T' || c == 't') && i >= 10 && is_date(text.substr(i - 10, 10)) &&
          !(i + 1 < text.size() && text[i + 1] >= '0' && text[i + 1] <= '9'))
        fail(i + 1, "a date and 'T' must be followed by a time (HH:MM:SS)");
      if (c == ' ' && number) number_space = i;
      if (c == ' ' || (c >= '\t' && c <= '\r') || c == ']' || c == '}' || c == ',' || c == '#')
        number = false;  // toml++'s is_value_terminator
      else if ((c >= '0' && c <= '9') || c == '+' || c == '-')
        number = true;
      if (c == '#') {
        state = comment;
      } else if ((c == '"' || c == '\'') && number) {
        fail(i, "a quote after a digit or a sign with no space, ',', ']' or '}' between them (toml++ would read it as "
                "part of a number, a date or a time)");
      } else if (c == '"' || c == '\'') {
        const bool multi = i + 2 < text.size() && text[i + 1] == char(c) && text[i + 2] == char(c);
        state = c == '"' ? (multi ? ml_basic : basic) : (multi ? ml_literal : literal);
        escape = none;
        if (multi) i += 2;
      } else if (c == '.') {
        if (++parts > kMaxKeyParts)
          fail(i, "a dotted key or table name of more than " + std::to_string(kMaxKeyParts) +
                      " parts (a scene's keys have at most 3)");
      } else if (!bare_key_char(c) && c != ' ' && c != '\t') {
        parts = 1;  // anything else ends a dotted key
        if (c == '[' || c == '{') {
          if (depth == kMaxNesting)
            fail(i, "arrays and inline tables nested more than " + std::to_string(kMaxNesting) + " deep");
          open[depth++] = static_cast<char>(c);
        } else if ((c == ']' || c == '}') && depth > 0) {
          if (open[depth - 1] != (c == ']' ? '[' : '{'))
            fail(i, std::string("'") + static_cast<char>(c) + "' closes a '" + open[depth - 1] + "'");
          --depth;
        }
      }
      break;
    case comment:
      if (c == '\n') state = normal, parts = 1, line_start = true;
      break;
    case basic:  // toml++ refuses a line break in it
      if (c == '\\') ++i;
      else if (c == '"' || c == '\n') state = normal;
      break;
    case literal:
      if (c == '\'' || c == '\n') state = normal;
      break;
    case ml_literal:
      if (c == '\'' && close_multi_line(i, '\'')) state = normal;
      break;
    case ml_basic: {
      const bool space = c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
      if (escape == after_backslash) {  // the escaped character, or a line-ending backslash's whitespace
        if (c >= 0x80) non_ascii(i, "after a backslash in a multi-line string");
        escape = space ? skipping : none;
        break;
      }
      if (escape == skipping) {  // toml++ skips whitespace and line breaks
        if (space) break;
        if (c >= 0x80) non_ascii(i, "after a line-ending backslash in a multi-line string");
        escape = none;
      }
      if (c == '\\') escape = after_backslash;
      else if (c == '"' && close_multi_line(i, '"')) state = normal;
      break;
    }
    }
  }
}

const char *type_name(const toml::node &n) {
  switch (n.type()) {
  case toml::node_type::string: return "a string";
  case toml::node_type::integer: return "an integer";
  case toml::node_type::floating_point: return "a floating-point number";
  case toml::node_type::boolean: return "a boolean";
  case toml::node_type::date: return "a date";
  case toml::node_type::time: return "a time";
  case toml::node_type::date_time: return "a date-time";
  case toml::node_type::array: return "an array";
  case toml::node_type::table: return "a table";
  default: return "nothing";
  }
}

// One table of the scene and its dotted name ("loads.traction[2]").
class Reader {
 public:
  Reader(std::string file) : file_(std::move(file)) {}

  std::string where(const toml::source_region &src) const {
    std::ostringstream os;
    os << file_;
    if (src.begin.line > 0) os << ':' << src.begin.line << ':' << src.begin.column;
    return os.str();
  }
  [[noreturn]] void fail(const toml::source_region &src, const std::string &msg) const {
    throw SceneError(where(src) + ": " + msg);
  }
  static std::string dotted(const std::string &table, const std::string &key) {
    return table.empty() ? key : table + "." + key;
  }
  static std::string header(const std::string &table) { return table.empty() ? "the top level" : "[" + table + "]"; }

  // Unknown keys are errors: the first one is reported at its line.
  void check_keys(const toml::table &t, const std::string &name, const std::string &kind) const {
    const auto &allowed = table_keys().at(kind);
    for (auto &&[k, v] : t) {
      bool ok = false;
      for (const auto &a : allowed) ok = ok || a == k.str();
      if (!ok) {
        std::string list;
        for (const auto &a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(k.source(), "unknown key '" + dotted(name, std::string(k.str())) + "' (the keys of " + header(name) +
                             " are: " + list + ")");
      }
    }
  }

  const toml::node *find(const toml::table &t, const std::string &key) const { return t.get(key); }

  [[noreturn]] void missing(const toml::table &t, const std::string &table, const std::string &key,
                            const std::string &what) const {
    fail(t.source(), header(table) + " has no key '" + key + "' (required: " + what + ")");
  }
  [[noreturn]] void wrong_type(const toml::node &n, const std::string &table, const std::string &key,
                               const std::string &want) const {
    fail(n.source(), "'" + dotted(table, key) + "' must be " + want + ", not " + type_name(n));
  }

  double number(const toml::node &n, const std::string &table, const std::string &key) const {
    if (!n.is_number()) wrong_type(n, table, key, "a number");
    const double x = *n.value<double>();
    if (!std::isfinite(x) && !allow_infinite_) fail(n.source(), "'" + dotted(table, key) + "' must be finite");
    return x;
  }
  double number(const toml::table &t, const std::string &table, const std::string &key, const double *fallback,
                const std::string &what = "a number") const {
    const toml::node *n = find(t, key);
    if (!n) {
      if (!fallback) missing(t, table, key, what);
      return *fallback;
    }
    return number(*n, table, key);
  }
  // Every integer of the scene is read here: within [lo, hi], so that it can
  // be narrowed to the type it is used as.
  int64_t integer(const toml::node &n, const std::string &table, const std::string &key, int64_t lo,
                  int64_t hi) const {
    if (!n.is_integer()) wrong_type(n, table, key, "an integer");
    const int64_t x = n.as_integer()->get();
    if (x < lo || x > hi)
      fail(n.source(), "'" + dotted(table, key) + "' must be an integer from " + std::to_string(lo) + " to " +
                           std::to_string(hi) + ", not " + std::to_string(x));
    return x;
  }
  // A string without NUL characters (a NUL would end a path or a title early).
  std::string string(const toml::node &n, const std::string &table, const std::string &key) const {
    if (!n.is_string()) wrong_type(n, table, key, "a string");
    std::string s = n.as_string()->get();
    if (s.find('\0') != std::string::npos)
      fail(n.source(), "'" + dotted(table, key) + "' contains a NUL character (\\u0000)");
    return s;
  }
  // The name of an output file, under --out: relative and without a '..'
  // component, so that it cannot leave the output directory.
  std::string output_file(const toml::node &n, const std::string &table, const std::string &key) const {
    const std::string s = string(n, table, key);
    if (s.empty()) fail(n.source(), "'" + dotted(table, key) + "' is empty");
    const std::filesystem::path p(s);
    if (p.is_absolute() || s[0] == '/')
      fail(n.source(), "'" + dotted(table, key) + "' is an absolute path: output files are written under --out (a "
                           "relative path)");
    for (const auto &part : p)
      if (part == "..")
        fail(n.source(), "'" + dotted(table, key) + "' has a '..' component: output files stay under --out");
    return s;
  }
  std::vector<double> vector(const toml::node &n, const std::string &table, const std::string &key) const {
    const toml::array *a = n.as_array();
    if (!a) wrong_type(n, table, key, "an array of numbers");
    if (a->empty() || a->size() > 3)
      fail(n.source(), "'" + dotted(table, key) + "' must have 1 to 3 components, not " + std::to_string(a->size()));
    std::vector<double> v;
    for (size_t i = 0; i < a->size(); ++i) v.push_back(number((*a)[i], table, key + "[" + std::to_string(i) + "]"));
    return v;
  }
  std::vector<double> vector(const toml::table &t, const std::string &table, const std::string &key,
                             const std::string &what) const {
    const toml::node *n = find(t, key);
    if (!n) missing(t, table, key, what);
    return vector(*n, table, key);
  }
  // A value in time (time_value.hpp): an array of 1 to 3 components, each a
  // number or an expression in t (a string), or a table { table = [[t, v_1,
  // .., v_n], ...] } with increasing t. `scalar`: one component, which may
  // also be written alone (a number or a string).
  TimeValue time_value(const toml::node &n, const std::string &table, const std::string &key,
                       bool scalar = false) const {
    const std::string name = dotted(table, key);
    auto part = [&](const toml::node &c, const std::string &k) {
      if (c.is_number()) return Expression(number(c, table, k));
      if (!c.is_string()) wrong_type(c, table, k, "a number or an expression in t (a string)");
      try {
        return Expression::parse(string(c, table, k));
      } catch (const std::invalid_argument &e) {
        fail(c.source(), "'" + dotted(table, k) + "': the expression " + e.what());
      }
    };
    TimeValue v;
    if (scalar && (n.is_number() || n.is_string())) {
      v.parts.push_back(part(n, key));
      return v;
    }
    if (const toml::table *t = n.as_table()) {
      for (auto &&[k, x] : *t)
        if (k.str() != "table") fail(k.source(), "'" + name + "." + std::string(k.str()) + "': the only key is 'table'");
      const toml::node *rows = t->get("table");
      if (!rows) missing(*t, name, "table", "rows [t, value...] of the value in time");
      const toml::array *a = rows->as_array();
      if (!a || a->empty()) fail(rows->source(), "'" + name + ".table' must be a non-empty array of rows [t, value...]");
      for (size_t i = 0; i < a->size(); ++i) {
        const std::string row = name + ".table[" + std::to_string(i) + "]";
        const toml::array *r = (*a)[i].as_array();
        const size_t want = v.rows.empty() ? (scalar ? 2 : 0) : v.rows[0].size() + 1;
        if (!r || r->size() < 2 || r->size() > 4 || (want && r->size() != want))
          fail((*a)[i].source(), "'" + row + "' must be a row [t, value" + (scalar ? "" : "s (1 to 3)") + "]" +
                                     (want ? " of " + std::to_string(want) + " numbers, as the first" : ""));
        std::vector<double> x;
        for (size_t j = 0; j < r->size(); ++j) x.push_back(number((*r)[j], table, key + ".table[" + std::to_string(i) + "]"));
        if (!v.times.empty() && !(x[0] > v.times.back()))
          fail((*a)[i].source(), "'" + row + "': the times must increase from row to row");
        v.times.push_back(x[0]);
        v.rows.emplace_back(x.begin() + 1, x.end());
      }
      return v;
    }
    const toml::array *a = n.as_array();
    if (!a) wrong_type(n, table, key, scalar ? "a number, an expression in t or { table = [[t, value], ...] }"
                                             : "an array of numbers or expressions in t, or { table = [[t, ...], ...] }");
    if (a->empty() || a->size() > (scalar ? 1u : 3u))
      fail(n.source(), "'" + name + "' must have " + (scalar ? "1 component" : "1 to 3 components") + ", not " +
                           std::to_string(a->size()));
    for (size_t i = 0; i < a->size(); ++i) v.parts.push_back(part((*a)[i], key + "[" + std::to_string(i) + "]"));
    return v;
  }

  // The key's node, which must be there (else the table's place and `what`).
  const toml::node &required(const toml::table &t, const std::string &table, const std::string &key,
                             const std::string &what) const {
    const toml::node *n = find(t, key);
    if (!n) missing(t, table, key, what);
    return *n;
  }
  // f(entry, "parent.key[i]") for each table of the array parent.key (if
  // given), its keys checked against those of "parent.key"
  template <class F>
  void each_table(const toml::table &t, const std::string &parent, const std::string &key, const std::string &form,
                  F &&f) const {
    const toml::node *n = t.get(key);
    if (!n) return;
    const toml::array *a = n->as_array();
    if (!a) wrong_type(*n, parent, key, "an array of tables " + form);
    for (size_t i = 0; i < a->size(); ++i) {
      const std::string entry = key + "[" + std::to_string(i) + "]";
      const toml::table &e = table((*a)[i], parent, entry);
      check_keys(e, dotted(parent, entry), dotted(parent, key));
      f(e, dotted(parent, entry));
    }
  }

  // the array of tables parent.key, each { region, `value` } (RegionValue)
  void region_values(const toml::table &t, const std::string &parent, const std::string &key, const std::string &value,
                     const std::string &what_region, const std::string &what_value, std::vector<RegionValue> &out) const {
    each_table(t, parent, key, "{ region, " + value + " }", [&](const toml::table &e, const std::string &name) {
      RegionValue v;
      v.region = region(required(e, name, "region", what_region), name, "region");
      v.value = time_value(required(e, name, value, what_value), name, value);
      v.at = where(e.source());
      out.push_back(std::move(v));
    });
  }

  // a top-level key given as one table, or as an array of them ([[key]])
  std::vector<const toml::table *> tables(const toml::node &n, const std::string &key) const {
    std::vector<const toml::table *> all;
    if (const toml::array *a = n.as_array()) {
      for (size_t i = 0; i < a->size(); ++i) all.push_back(&table((*a)[i], "", key + "[" + std::to_string(i) + "]"));
    } else {
      all.push_back(&table(n, "", key));
    }
    return all;
  }
  const toml::table &table(const toml::node &n, const std::string &parent, const std::string &key) const {
    const toml::table *t = n.as_table();
    if (!t) wrong_type(n, parent, key, "a table");
    return *t;
  }
  RegionRef region(const toml::node &n, const std::string &table, const std::string &key) const {
    RegionRef r;
    r.at = where(n.source());
    if (n.is_integer()) {
      r.id = static_cast<int>(integer(n, table, key, 0, 1000000000));
    } else if (n.is_string()) {
      r.name = string(n, table, key);
    } else {
      wrong_type(n, table, key, "a region number or the name of a region of [regions]");
    }
    return r;
  }

  void allow_infinite(bool on) { allow_infinite_ = on; }

 private:
  std::string file_;
  bool allow_infinite_ = false;
};

// a region's friction law, the table `parent`.friction
FrictionEntry read_friction(const Reader &r, const toml::node &fr, const std::string &parent) {
  const std::string table = parent + ".friction";
  FrictionEntry e;
  const toml::table &f = r.table(fr, parent, "friction");
  r.check_keys(f, table, table);
  const toml::node *law = f.get("law");
  if (!law) r.missing(f, table, "law", "\"coulomb\", \"tresca\" or \"none\"");
  const std::string name = r.string(*law, table, "law");
  const std::map<std::string, std::pair<int, const char *>> laws = {{"none", {ND_FRICTION_NONE, nullptr}},
                                                                     {"coulomb", {ND_FRICTION_COULOMB, "coefficient"}},
                                                                     {"tresca", {ND_FRICTION_TRESCA, "threshold"}}};
  const auto it = laws.find(name);
  if (it == laws.end())
    r.fail(law->source(), "'" + table + ".law' must be \"coulomb\", \"tresca\" or \"none\", not \"" + name + "\"");
  e.law = it->second.first;
  for (const char *key : {"coefficient", "threshold"})
    if (f.get(key) && (!it->second.second || std::string(key) != it->second.second))
      r.fail(f.get(key)->source(), "'" + table + "." + key + "' is not a parameter of the law \"" + name + "\"" +
                                       (it->second.second ? std::string(" (its: ") + it->second.second + ")" : ""));
  if (it->second.second)
    e.parameter = r.number(f, table, it->second.second, nullptr,
                           e.law == ND_FRICTION_COULOMB ? "the friction coefficient F" : "the threshold s, a stress");
  e.at = r.where(fr.source());
  return e;
}

void read_mesh(const Reader &r, const toml::table &t, Scene &s) {
  r.check_keys(t, "mesh", "mesh");
  s.mesh_at = r.where(t.source());
  const toml::node *gmsh = t.get("gmsh"), *gen = t.get("generate");
  if (gmsh && gen) r.fail(gen->source(), "[mesh] names a Gmsh file and a generated mesh: keep one");
  if (!gmsh && !gen)
    r.fail(t.source(), "[mesh] has neither 'gmsh' (a Gmsh file) nor 'generate' (interval, rectangle or box)");
  if (gmsh) {
    for (const char *k : {"cells", "cell_type", "lo", "hi"})
      if (const toml::node *n = t.get(k)) r.fail(n->source(), std::string("'mesh.") + k + "' is for a generated mesh");
    const std::filesystem::path p = r.string(*gmsh, "mesh", "gmsh");
    if (p.empty()) r.fail(gmsh->source(), "'mesh.gmsh' is empty");
    s.gmsh_at = r.where(gmsh->source());
    s.gmsh = p.is_absolute() ? p.string() : (std::filesystem::path(s.file).parent_path() / p).lexically_normal().string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(s.gmsh, ec))
      r.fail(gmsh->source(), "'mesh.gmsh': no mesh file " + s.gmsh + " (a path relative to the scene file)");
  } else {
    s.generate = r.string(*gen, "mesh", "generate");
    s.dim = s.generate == "interval" ? 1 : s.generate == "rectangle" ? 2 : s.generate == "box" ? 3 : 0;
    if (s.dim == 0)
      r.fail(gen->source(), "'mesh.generate' is \"" + s.generate + "\": use interval, rectangle or box");
    const toml::node *cells = t.get("cells");
    if (!cells) r.missing(t, "mesh", "cells", "the number of cells in each direction");
    const toml::array *a = cells->as_array();
    if (!a) r.wrong_type(*cells, "mesh", "cells", "an array of integers");
    if ((int)a->size() != s.dim)
      r.fail(cells->source(), "'mesh.cells' has " + std::to_string(a->size()) + " entries; a " + s.generate +
                                  " needs " + std::to_string(s.dim));
    int64_t total = 1;
    for (size_t i = 0; i < a->size(); ++i) {
      const int64_t n = r.integer((*a)[i], "mesh", "cells[" + std::to_string(i) + "]", 1, kMaxCellsPerDirection);
      total *= n;  // at most 10^18: no overflow
      if (total > kMaxCells)
        r.fail(cells->source(), "'mesh.cells' makes more than " + std::to_string(kMaxCells) +
                                    " cells (the product of the entries): use a Gmsh mesh for larger ones");
      s.cells.push_back(n);
    }
    s.lo = r.vector(t, "mesh", "lo", "the lower corner of the mesh");
    s.hi = r.vector(t, "mesh", "hi", "the upper corner of the mesh");
    for (const auto *v : {&s.lo, &s.hi})
      if ((int)v->size() != s.dim)
        r.fail(t.get(v == &s.lo ? "lo" : "hi")->source(),
               std::string("'mesh.") + (v == &s.lo ? "lo" : "hi") + "' must have " + std::to_string(s.dim) +
                   " components for a " + s.generate);
    for (int k = 0; k < s.dim; ++k)
      if (!(s.lo[k] < s.hi[k])) r.fail(t.get("hi")->source(), "'mesh.hi' must exceed 'mesh.lo' in every component");
    if (const toml::node *c = t.get("cell_type")) {  // the generator's cells: simplices (default) or whole
      const std::string type = r.string(*c, "mesh", "cell_type");
      const char *whole = s.dim == 2 ? "quadrilateral" : s.dim == 3 ? "hexahedron" : nullptr;
      if (type == "simplex") s.cell_type = ND_CELL_SIMPLEX;
      else if (whole && type == whole) s.cell_type = s.dim == 2 ? ND_CELL_QUADRILATERAL : ND_CELL_HEXAHEDRON;
      else
        r.fail(c->source(), "'mesh.cell_type' is \"" + type + "\": " + (s.dim == 1 ? "an " : "a ") + s.generate + " takes \"simplex\"" +
                                (whole ? std::string(" or \"") + whole + "\"" : std::string()));
    }
  }
  if (const toml::node *d = t.get("degree")) {
    s.degree = static_cast<int>(r.integer(*d, "mesh", "degree", 1, 2));
  }
}

void read_regions(Reader &r, const toml::table &t, Scene &s) {
  for (auto &&[k, v] : t) {
    const std::string name(k.str());
    const std::string key = "regions." + name;
    if (v.is_integer()) {  // a name for a region of the mesh (a Gmsh physical group)
      const RegionRef ref = r.region(v, "regions", name);
      s.names.emplace_back(name, ref.id);
      continue;
    }
    if (!v.is_table()) r.wrong_type(v, "regions", name, "a region number or a table { id, lo, hi }");
    const toml::table &b = *v.as_table();
    r.check_keys(b, key, "regions.NAME");
    const toml::node *id = b.get("id");
    if (!id) r.missing(b, key, "id", "the region number");
    RegionBox box;
    box.name = name;
    box.id = r.region(*id, key, "id").id;
    r.allow_infinite(true);  // a box may be a half-space or a slab
    box.lo = r.vector(b, key, "lo", "the lower corner of the box");
    box.hi = r.vector(b, key, "hi", "the upper corner of the box");
    r.allow_infinite(false);
    if (box.lo.size() != box.hi.size())
      r.fail(b.get("hi")->source(), "'" + key + ".lo' and '" + key + ".hi' differ in length");
    box.at = r.where(b.source());
    s.boxes.push_back(box);
    s.names.emplace_back(name, box.id);
  }
}

int scheme_id(const std::string &name) {
  return name == "hybrid" ? ND_SCHEME_HYBRID : name == "newmark" ? ND_SCHEME_NEWMARK
       : name == "theta"  ? ND_SCHEME_THETA  : name == "galpha"  ? ND_SCHEME_GENERALIZED_ALPHA : 0;
}

void read_scheme(const Reader &r, const toml::table &t, Scene &s) {
  r.check_keys(t, "scheme", "scheme");
  s.scheme_at = r.where(t.source());
  const toml::node *n = t.get("name");
  if (!n) r.missing(t, "scheme", "name", "hybrid, newmark, theta or galpha");
  s.scheme = r.string(*n, "scheme", "name");
  s.scheme_id = scheme_id(s.scheme);
  if (!s.scheme_id) r.fail(n->source(), "'scheme.name' is \"" + s.scheme + "\": use hybrid, newmark, theta or galpha");
  // the parameters of the scheme, and no other
  const std::map<std::string, std::vector<std::string>> params = {
      {"hybrid", {}}, {"newmark", {"beta", "gamma"}}, {"theta", {"theta"}}, {"galpha", {"rho_inf"}}};
  for (auto &&[k, v] : t) {
    const std::string key(k.str());
    if (key == "name") continue;
    bool ok = false;
    for (const auto &p : params.at(s.scheme)) ok = ok || p == key;
    if (!ok) r.fail(k.source(), "'scheme." + key + "' is not a parameter of the " + s.scheme + " scheme");
  }
  const double beta = 0.25, gamma = 0.5, theta = 0.5, rho_inf = 0.8;
  if (s.scheme == "newmark") s.params = {{r.number(t, "scheme", "beta", &beta), r.number(t, "scheme", "gamma", &gamma)}};
  if (s.scheme == "theta") s.params = {{r.number(t, "scheme", "theta", &theta), 0}};
  if (s.scheme == "galpha") s.params = {{r.number(t, "scheme", "rho_inf", &rho_inf), 0}};
}

// indexed by ND_SOLVER_* value
const char *const solver_names[] = {"auto", "dense", "banded", "cholmod", "umfpack", "klu", "petsc_mumps", "petsc_gamg"};

void read_solver(const Reader &r, const toml::table &t, Scene &s) {
  r.check_keys(t, "solver", "solver");
  s.solver_at = r.where(t.source());
  if (const toml::node *n = t.get("linear")) {
    s.linear = r.string(*n, "solver", "linear");
    s.solver_id = -1;
    for (int k = 0; k < 6; ++k)
      if (s.linear == solver_names[k]) s.solver_id = k;
    if (s.solver_id < 0)
      r.fail(n->source(), "'solver.linear' is \"" + s.linear + "\": use auto, dense, banded, cholmod, umfpack, klu, "
                                "petsc_mumps or petsc_gamg");
  }
  const double rtol = s.newton_rtol, atol = s.newton_atol;
  s.newton_given = t.get("newton_rtol") || t.get("newton_atol") || t.get("newton_max_iter");
  s.newton_rtol = r.number(t, "solver", "newton_rtol", &rtol);
  s.newton_atol = r.number(t, "solver", "newton_atol", &atol);
  if (const toml::node *n = t.get("newton_max_iter"))
    s.newton_max_iter = r.integer(*n, "solver", "newton_max_iter", 1, std::numeric_limits<int>::max());
  if (const toml::node *n = t.get("mass_lumping")) {
    if (!n->is_boolean()) r.wrong_type(*n, "solver", "mass_lumping", "true or false");
    s.mass_lumping = *n->value<bool>();
  }
  if (const toml::node *n = t.get("mass_redistribution")) {
    if (!n->is_boolean()) r.wrong_type(*n, "solver", "mass_redistribution", "true or false");
    s.mass_redistribution = *n->value<bool>();
  }
}

void read_output(const Reader &r, const toml::table &t, Scene &s) {
  r.check_keys(t, "output", "output");
  s.output_at = r.where(t.source());
  if (const toml::node *n = t.get("history")) s.history = r.output_file(*n, "output", "history");
  if (const toml::node *n = t.get("paraview")) {
    s.paraview = r.output_file(*n, "output", "paraview");
    if (s.paraview.back() == '/')
      r.fail(n->source(), "'output.paraview' must be a file prefix (such as \"vtu/disk\")");
  }
  if (const toml::node *n = t.get("interval")) {
    s.interval = r.number(*n, "output", "interval");
    if (s.interval < 0) r.fail(n->source(), "'output.interval' must be >= 0 (0: every step)");
  }
}

// [guards]: factors (numbers >= 0, 0 off) and switches (true/false)
void read_guards(const Reader &r, const toml::table &t, Scene &s) {
  r.check_keys(t, "guards", "guards");
  struct Kind {
    const char *key;
    int id;
    bool factor;
  };
  static const Kind kinds[] = {{"energy", ND_GUARD_ENERGY, true},
                               {"penetration", ND_GUARD_PENETRATION, true},
                               {"critical_timestep", ND_GUARD_CRITICAL_TIMESTEP, false},
                               {"unstable_scheme", ND_GUARD_UNSTABLE_SCHEME, false},
                               {"coercivity", ND_GUARD_COERCIVITY, false},
                               {"initial_penetration", ND_GUARD_INITIAL_PENETRATION, false},
                               {"energy_balance", ND_GUARD_ENERGY_BALANCE, true}};
  for (const Kind &k : kinds) {
    const toml::node *n = t.get(k.key);
    if (!n) continue;
    Guard g;
    g.id = k.id;
    g.key = std::string("guards.") + k.key;
    g.at = r.where(n->source());
    if (k.factor) {
      g.value = r.number(*n, "guards", k.key);
      if (!(g.value >= 0)) r.fail(n->source(), "'" + g.key + "' must be >= 0 (0: off)");
    } else {
      if (!n->is_boolean()) r.wrong_type(*n, "guards", k.key, "true or false");
      g.value = *n->value<bool>() ? 1 : 0;
    }
    s.guards.push_back(g);
  }
}

// [material] (the default), or [[material]]: one entry without 'region' (the
// default) and one per cell region with its own material
void read_materials(const Reader &r, const toml::node &node, Scene &s) {
  std::vector<const toml::table *> entries;
  if (const toml::array *a = node.as_array()) {
    for (size_t i = 0; i < a->size(); ++i) entries.push_back(&r.table((*a)[i], "", "material[" + std::to_string(i) + "]"));
  } else {
    entries.push_back(&r.table(node, "", "material"));
  }
  bool have_default = false;
  for (const toml::table *t : entries) {
    r.check_keys(*t, "material", "material");
    RegionMaterial m;
    m.at = r.where(t->source());
    m.young = r.number(*t, "material", "E", nullptr, "Young's modulus");
    m.density = r.number(*t, "material", "rho", nullptr, "the density");
    m.poisson_given = t->get("nu") != nullptr;
    const double zero = 0;
    m.poisson = r.number(*t, "material", "nu", &zero);
    if (!m.poisson_given && s.dim > 1) r.missing(*t, "material", "nu", "Poisson's ratio");
    const toml::node *reg = t->get("region");
    for (const char *k : {"lo", "hi"})
      if (t->get(k) && !reg) r.fail(t->get(k)->source(), std::string("'material.") + k + "' needs 'material.region' (the cell region of the cells in [lo, hi])");
    if (t->get("lo") || t->get("hi")) {
      m.lo = r.vector(*t, "material", "lo", "the box's low corner (with 'hi')");
      m.hi = r.vector(*t, "material", "hi", "the box's high corner (with 'lo')");
    }
    for (const char *k : {"damping", "plane_stress"})  // (the body's, not a region's)
      if (t->get(k) && reg)
        r.fail(t->get(k)->source(), std::string("'material.") + k + "' is the whole body's: give it in the default "
                                                                     "[[material]] (the entry without 'region')");
    if (const toml::node *n = t->get("damping")) {  // Rayleigh: [alpha, beta], C = alpha M + beta K
      const std::vector<double> ab = r.vector(*n, "material", "damping");
      if (ab.size() != 2)
        r.fail(n->source(), "'material.damping' is [alpha, beta] (C = alpha M + beta K), not " +
                                std::to_string(ab.size()) + " numbers");
      s.damping = {ab[0], ab[1]};
      s.damping_at = r.where(n->source());
    }
    if (const toml::node *n = t->get("plane_stress")) {
      if (!n->is_boolean()) r.wrong_type(*n, "material", "plane_stress", "true or false");
      s.plane_stress = *n->value<bool>();
    }
    if (!reg) {
      if (have_default)
        r.fail(t->source(), "a second [[material]] without 'region': one entry is the default, the others name a cell region");
      have_default = true;
      s.material_at = m.at, s.young = m.young, s.poisson = m.poisson, s.density = m.density;
      s.poisson_given = m.poisson_given;
      continue;
    }
    m.region = static_cast<int>(r.integer(*reg, "material", "region", 1, std::numeric_limits<int>::max()));
    for (const RegionMaterial &o : s.region_materials)
      if (o.region == m.region) r.fail(reg->source(), "cell region " + std::to_string(m.region) + " has a material already (" + o.at + ")");
    s.region_materials.push_back(m);
  }
  if (!have_default)
    throw SceneError(r.where(node.source()) + ": no default material: one [[material]] entry without 'region' "
                     "(the cells of no region with a material of their own)");
}

void read_checkpoint(const Reader &r, const toml::table &t, Scene &s) {
  r.check_keys(t, "checkpoint", "checkpoint");
  s.checkpoint_at = r.where(t.source());
  const toml::node *f = t.get("file");
  if (!f) r.missing(t, "checkpoint", "file", "the checkpoint file");
  s.checkpoint = r.output_file(*f, "checkpoint", "file");
  if (s.checkpoint.back() == '/') r.fail(f->source(), "'checkpoint.file' must be a file name");
  if (const toml::node *n = t.get("every"))  // 0: at the end only
    s.checkpoint_every = r.integer(*n, "checkpoint", "every", 0, std::numeric_limits<int64_t>::max());
}

}  // namespace

Scene read_scene(const std::string &path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw SceneError(path + ": no such scene file");
  std::ifstream in(path, std::ios::binary);
  std::string text(kMaxSceneBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (in.bad()) throw SceneError(path + ": cannot read the scene file");
  text.resize(static_cast<size_t>(in.gcount()));
  if (text.size() > kMaxSceneBytes)
    throw SceneError(path + ": the scene file is larger than " + std::to_string(kMaxSceneBytes) + " bytes (1 MiB)");
  return parse_scene(text, path);
}

Scene parse_scene(std::string_view text, const std::string &path) {
  Scene s;
  s.file = path;
  check_text(text, path);
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error &e) {
    std::ostringstream os;
    std::string what(e.description());
    for (size_t i = 0; (i = what.find('\n', i)) != std::string::npos;) what.replace(i, 1, "\\n");
    os << path << ':' << e.source().begin.line << ':' << e.source().begin.column << ": " << what;
    throw SceneError(os.str());
  }
  Reader r(path);
  r.check_keys(root, "", "");

  if (const toml::node *n = root.get("title")) s.title = r.string(*n, "", "title");  // printed through printable()

  const toml::node *mesh = root.get("mesh");
  if (!mesh) throw SceneError(path + ": no [mesh] table (required: 'gmsh' = a Gmsh file, or 'generate' = ...)");
  read_mesh(r, r.table(*mesh, "", "mesh"), s);

  if (const toml::node *n = root.get("regions")) read_regions(r, r.table(*n, "", "regions"), s);

  const toml::node *mat = root.get("material");
  if (!mat) throw SceneError(path + ": no [material] table (required: E, nu, rho)");
  read_materials(r, *mat, s);

  if (const toml::node *n = root.get("loads")) {
    const toml::table &t = r.table(*n, "", "loads");
    r.check_keys(t, "loads", "loads");
    if (const toml::node *b = t.get("body_force")) {
      s.body_force = r.time_value(*b, "loads", "body_force");
      s.body_force_at = r.where(b->source());
    }
    r.region_values(t, "loads", "traction", "value", "the region the traction acts on", "the traction vector",
                    s.tractions);
    r.each_table(t, "loads", "nodal", "{ node, value }", [&](const toml::table &e, const std::string &name) {
      NodalLoad l;
      l.node = r.integer(r.required(e, name, "node", "the FE node the force acts on (from 0)"), name, "node", 0,
                         std::numeric_limits<int64_t>::max());
      l.value = r.time_value(r.required(e, name, "value", "the force"), name, "value");
      l.at = r.where(e.source());
      s.nodal.push_back(std::move(l));
    });
  }

  if (const toml::node *n = root.get("dirichlet")) {
    const toml::table &t = r.table(*n, "", "dirichlet");
    r.check_keys(t, "dirichlet", "dirichlet");
    if (const toml::node *regs = t.get("regions")) {
      const toml::array *a = regs->as_array();
      if (!a) r.wrong_type(*regs, "dirichlet", "regions", "an array of regions");
      for (size_t i = 0; i < a->size(); ++i)
        s.clamped.push_back(r.region((*a)[i], "dirichlet", "regions[" + std::to_string(i) + "]"));
    }
    r.region_values(t, "dirichlet", "motion", "displacement", "a clamped region of dirichlet.regions",
                    "the region's displacement", s.motions);
  }

  if (const toml::node *n = root.get("obstacle")) {
    for (const toml::table *t : r.tables(*n, "obstacle")) {
      r.check_keys(*t, "obstacle", "obstacle");
      const toml::node *reg = t->get("region");
      if (!reg) r.missing(*t, "obstacle", "region", "the contact region");
      Obstacle o;
      o.region = r.region(*reg, "obstacle", "region");
      if (const toml::node *sh = t->get("shape")) {
        o.shape = r.string(*sh, "obstacle", "shape");
        if (o.shape != "plane" && o.shape != "sphere" && o.shape != "cylinder")
          r.fail(sh->source(), "'obstacle.shape' must be \"plane\", \"sphere\" or \"cylinder\", not \"" + o.shape + "\"");
      }
      // the keys of each shape (region and shape are every shape's)
      const std::map<std::string, std::vector<std::string>> shape_keys = {
          {"plane", {"point", "normal"}}, {"sphere", {"center", "radius", "inside"}},
          {"cylinder", {"point", "axis", "radius", "inside"}}};
      for (auto &&[k, v] : *t) {
        const std::string key(k.str());
        if (key == "region" || key == "shape" || key == "velocity" || key == "position" || key == "rotation" ||
            key == "friction")
          continue;
        const std::vector<std::string> &mine = shape_keys.at(o.shape);
        if (std::find(mine.begin(), mine.end(), key) == mine.end())
          r.fail(k.source(), "'obstacle." + key + "' is not a key of a " + o.shape +
                                 " (its keys: region, shape, velocity, position, rotation, friction, " +
                                 [&] {
                                   std::string list;
                                   for (const auto &m : mine) list += (list.empty() ? "" : ", ") + m;
                                   return list;
                                 }() + ")");
      }
      if (o.shape == "plane") {
        o.point = r.vector(*t, "obstacle", "point", "a point of the plane");
        o.normal = r.vector(*t, "obstacle", "normal", "the plane's normal, from the obstacle towards the body");
      } else {
        if (o.shape == "sphere") {
          o.center = r.vector(*t, "obstacle", "center", "the sphere's centre");
        } else {
          o.point = r.vector(*t, "obstacle", "point", "a point of the cylinder's axis");
          o.axis = r.vector(*t, "obstacle", "axis", "the direction of the cylinder's axis");
        }
        o.radius = r.number(*t, "obstacle", "radius", nullptr, "the radius");
        if (!(o.radius > 0)) r.fail(t->get("radius")->source(), "'obstacle.radius' must be positive");
        if (const toml::node *in = t->get("inside")) {
          if (!in->is_boolean()) r.wrong_type(*in, "obstacle", "inside", "true or false");
          o.inside = *in->value<bool>();
        }
      }
      if (t->get("velocity")) o.velocity = r.vector(*t, "obstacle", "velocity", "the obstacle's velocity");
      if (const toml::node *fr = t->get("friction")) o.friction = read_friction(r, *fr, "obstacle");
      if (const toml::node *pos = t->get("position")) {
        if (t->get("velocity")) r.fail(pos->source(), "'obstacle.position' and 'obstacle.velocity' both move it: keep one");
        o.position = r.time_value(*pos, "obstacle", "position");
      }
      if (const toml::node *rot = t->get("rotation")) {
        if (o.shape == "plane")
          r.fail(rot->source(), "'obstacle.rotation': a plane moves by translation only (a turned plane is another "
                                "obstacle); give it 'position'");
        o.rotation = r.time_value(*rot, "obstacle", "rotation", true);
      }
      o.at = r.where(t->source());
      s.obstacles.push_back(o);
    }
  }

  if (const toml::node *n = root.get("contact_pair")) {  // two bodies
    for (const toml::table *t : r.tables(*n, "contact_pair")) {
      r.check_keys(*t, "contact_pair", "contact_pair");
      ContactPairEntry e;
      const toml::node *slave = t->get("slave"), *master = t->get("master");
      if (!slave) r.missing(*t, "contact_pair", "slave", "the region whose points meet the master's surface");
      if (!master) r.missing(*t, "contact_pair", "master", "the region of the other body's surface");
      e.slave = r.region(*slave, "contact_pair", "slave");
      e.master = r.region(*master, "contact_pair", "master");
      if (const toml::node *fr = t->get("friction")) e.friction = read_friction(r, *fr, "contact_pair");
      e.at = r.where(t->source());
      s.pairs.push_back(e);
    }
  }

  if (const toml::node *n = root.get("nitsche")) {
    const toml::table &t = r.table(*n, "", "nitsche");
    r.check_keys(t, "nitsche", "nitsche");
    s.nitsche_at = r.where(t.source());
    const double one = 1;
    s.Theta = r.number(t, "nitsche", "Theta", &one);
    if (const toml::node *g = t.get("gamma0")) {
      if (g->is_string()) {
        if (*g->value<std::string>() != "auto")
          r.fail(g->source(), "'nitsche.gamma0' must be a number >= 0 or \"auto\"");
        s.gamma0 = 0;
      } else {
        s.gamma0 = r.number(*g, "nitsche", "gamma0");
        if (s.gamma0 < 0) r.fail(g->source(), "'nitsche.gamma0' must be >= 0 (0 or \"auto\": automatic)");
      }
    }
  }

  if (const toml::node *n = root.get("scheme")) read_scheme(r, r.table(*n, "", "scheme"), s);
  else s.scheme_id = ND_SCHEME_HYBRID;

  if (const toml::node *n = root.get("time")) {
    const toml::table &t = r.table(*n, "", "time");
    r.check_keys(t, "time", "time");
    if (const toml::node *tau = t.get("tau")) {
      s.tau = r.number(*tau, "time", "tau");
      s.tau_given = true;
      s.tau_at = r.where(tau->source());
      if (!(s.tau > 0)) r.fail(tau->source(), "'time.tau' must be positive");
    }
    if (const toml::node *T = t.get("T")) {
      s.T = r.number(*T, "time", "T");
      s.T_given = true;
      s.T_at = r.where(T->source());
      if (s.T < 0) r.fail(T->source(), "'time.T' must be >= 0");
    }
    // adaptive steps: the library checks the values (nd_problem_set_adaptive_timestep)
    if (const toml::node *tol = t.get("tolerance")) {
      s.tolerance = r.number(*tol, "time", "tolerance");
      s.tolerance_at = r.where(tol->source());
    }
    if (const toml::node *lo = t.get("tau_min")) s.tau_min = r.number(*lo, "time", "tau_min");
    if (const toml::node *hi = t.get("tau_max")) s.tau_max = r.number(*hi, "time", "tau_max");
  }

  if (const toml::node *n = root.get("solver")) read_solver(r, r.table(*n, "", "solver"), s);
  else s.solver_id = ND_SOLVER_AUTO;

  if (const toml::node *n = root.get("initial")) {
    const toml::table &t = r.table(*n, "", "initial");
    r.check_keys(t, "initial", "initial");
    if (const toml::node *u = t.get("displacement")) {
      s.u0 = r.vector(*u, "initial", "displacement");
      s.u0_at = r.where(u->source());
    }
    if (const toml::node *v = t.get("velocity")) {
      s.v0 = r.vector(*v, "initial", "velocity");
      s.v0_at = r.where(v->source());
    }
  }

  if (const toml::node *n = root.get("output")) read_output(r, r.table(*n, "", "output"), s);
  if (const toml::node *n = root.get("guards")) read_guards(r, r.table(*n, "", "guards"), s);
  if (const toml::node *n = root.get("checkpoint")) read_checkpoint(r, r.table(*n, "", "checkpoint"), s);

  // every name used is defined
  auto check_ref = [&](const RegionRef &ref) { region_id(s, ref); };
  for (const auto &t : s.tractions) check_ref(t.region);
  for (const auto &c : s.clamped) check_ref(c);
  for (const auto &m : s.motions) check_ref(m.region);
  for (const auto &o : s.obstacles) check_ref(o.region);
  if (s.dim > 0) check_dimension(s, s.dim);
  return s;
}

int64_t step_count(const Scene &s) {
  const int64_t steps = nd_step_count(s.T, s.tau);
  if (steps < 0) {
    const double ratio = s.T / s.tau;
    std::ostringstream os;
    os << (s.T_at.empty() ? s.file : s.T_at) << ": T / tau = " << s.T << " / " << s.tau << " is "
       << (std::isfinite(ratio) ? "more steps than a run can count" : "not a finite number of steps")
       << " (at most 2^63 - 1 = 9223372036854775807 steps): raise 'time.tau' or lower 'time.T'";
    throw SceneError(os.str());
  }
  return steps;
}

std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\t' || c == '\n' || c == '\r') {
      out += ' ';
    } else if (c < 0x20 || c == 0x7F) {
      out += '?';
    } else if (c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) >= 0x80 &&
               static_cast<unsigned char>(text[i + 1]) <= 0x9F) {
      out += '?';  // U+0080-U+009F, the C1 controls (CSI is U+009B)
      ++i;
    } else if (c >= 0x80 && c <= 0x9F && (i == 0 || static_cast<unsigned char>(text[i - 1]) < 0x80)) {
      out += '?';  // a lone C1 byte (not UTF-8: never from toml++, but from a message)
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

int region_id(const Scene &s, const RegionRef &r) {
  if (r.name.empty()) return r.id;
  for (const auto &n : s.names)
    if (n.first == r.name) return n.second;
  std::string list;
  for (const auto &n : s.names) list += (list.empty() ? "" : ", ") + n.first;
  throw SceneError(r.at + ": no region named '" + r.name + "' in [regions]" +
                   (list.empty() ? std::string(" (there is no [regions] table)") : " (defined: " + list + ")"));
}

void check_dimension(const Scene &s, int dim) {
  auto check = [&](const auto &v, const std::string &at, const std::string &key) {
    if (!v.empty() && (int)v.size() != dim)
      throw SceneError(at + ": '" + key + "' has " + std::to_string(v.size()) + " components; the mesh is " +
                       std::to_string(dim) + "D");
  };
  check(s.body_force, s.body_force_at, "loads.body_force");
  check(s.u0, s.u0_at, "initial.displacement");
  check(s.v0, s.v0_at, "initial.velocity");
  for (const auto &t : s.tractions) check(t.value, t.at, "loads.traction.value");
  for (const auto &l : s.nodal) check(l.value, l.at, "loads.nodal.value");
  for (const auto &m : s.motions) check(m.value, m.at, "dirichlet.motion.displacement");
  for (const auto &o : s.obstacles) {
    check(o.point, o.at, "obstacle.point");
    check(o.normal, o.at, "obstacle.normal");
    check(o.center, o.at, "obstacle.center");
    check(o.axis, o.at, "obstacle.axis");
    check(o.velocity, o.at, "obstacle.velocity");
    check(o.position, o.at, "obstacle.position");
    // (the library refuses a sphere in 1D and a cylinder outside 3D, with its reason)
  }
  for (const auto &b : s.boxes) {
    check(b.lo, b.at, "regions." + b.name + ".lo");
    check(b.hi, b.at, "regions." + b.name + ".hi");
  }
  if (dim > 1 && !s.poisson_given) throw SceneError(s.material_at + ": [material] has no key 'nu' (required in " +
                                                    std::to_string(dim) + "D: Poisson's ratio)");
  for (const RegionMaterial &m : s.region_materials) {
    check(m.lo, m.at, "material.lo");
    check(m.hi, m.at, "material.hi");
    if (dim > 1 && !m.poisson_given)
      throw SceneError(m.at + ": [[material]] of region " + std::to_string(m.region) + " has no key 'nu' (required in " +
                       std::to_string(dim) + "D: Poisson's ratio)");
  }
}

std::vector<std::string> documented_keys() {
  std::vector<std::string> out;
  for (const auto &[table, keys] : table_keys())
    for (const auto &k : keys) out.push_back(table.empty() ? k : table + "." + k);
  return out;
}

}  // namespace ndcli
