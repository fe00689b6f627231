// libFuzzer target: the scene loader of nitschedyn(1) (tools/cli/scene.cpp,
// parse_scene) on arbitrary bytes: the pre-scan, toml++ (compiled into this
// target header-only, so that its parser is instrumented and sanitized too)
// and the validation of every table. The scene is named
// examples/scenes/fuzz.toml, so that the seeds' "../meshes/..." paths resolve
// as the example scenes' do; the loader only checks that a mesh file exists
// (it never reads it), and nothing is written. Oracle: no crash, leak,
// sanitizer report or timeout, and the loader's contract: a scene within the
// limits, or a SceneError naming the scene.
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "scene.hpp"

#ifndef ND_FUZZ_SCENE_PATH
#error "ND_FUZZ_SCENE_PATH: the scene's name (tests/fuzz/CMakeLists.txt)"
#endif

namespace {
void require(bool ok, const char *what, const std::string &detail = "") {
  if (!ok) {
    std::fprintf(stderr, "fuzz_scene: contract violated: %s %s\n", what, detail.c_str());
    std::abort();
  }
}

bool has_control(std::string_view s) {
  for (unsigned char c : s)
    if (c < 0x20 || c == 0x7F) return true;
  return s.find("\xC2\x9B") != std::string_view::npos;  // CSI, U+009B
}

// an output file name stays under --out
void require_under_out(const std::string &name, const char *what) {
  if (name.empty()) return;
  const std::filesystem::path p(name);
  require(!p.is_absolute(), what, "is absolute");
  for (const auto &part : p) require(part != "..", what, "has a '..' component");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const std::string_view text(reinterpret_cast<const char *>(data), size);
  // the expression parser on the raw bytes: refused with a message, or a program that evaluates
  try {
    const ndcli::Expression e = ndcli::Expression::parse(text);
    (void)e.at(0.25);
  } catch (const std::invalid_argument &) {
  }
  const std::string path = ND_FUZZ_SCENE_PATH;
  try {
    const ndcli::Scene s = ndcli::parse_scene(text, path);
    require(size <= ndcli::kMaxSceneBytes, "the size limit");
    int64_t cells = 1;
    for (int64_t n : s.cells) {
      require(n >= 1 && n <= ndcli::kMaxCellsPerDirection, "cells per direction");
      cells *= n;
    }
    require(cells <= ndcli::kMaxCells, "the number of cells");
    require(s.degree == 1 || s.degree == 2, "the degree");
    require(s.newton_max_iter >= 1 && s.newton_max_iter <= INT_MAX, "newton_max_iter within int");
    require(s.checkpoint_every >= 0, "checkpoint.every");
    for (const std::string *str : {&s.title, &s.gmsh, &s.history, &s.paraview, &s.checkpoint})
      require(str->find('\0') == std::string::npos, "no NUL in a path or the title");
    require_under_out(s.history, "output.history");
    require_under_out(s.paraview, "output.paraview");
    require_under_out(s.checkpoint, "checkpoint.file");
    require(!has_control(ndcli::printable(s.title)), "a printable title");
    if (s.tau_given && s.T_given) {
      try {
        const int64_t steps = ndcli::step_count(s);
        require(steps >= 0, "a step count >= 0");
      } catch (const ndcli::SceneError &e) {
        require(std::strstr(e.what(), "2^63 - 1") != nullptr, "the step limit named", e.what());
      }
    }
    for (const auto &t : s.tractions) require(ndcli::region_id(s, t.region) >= 0, "a region number");
    for (const auto &c : s.clamped) require(ndcli::region_id(s, c) >= 0, "a region number");
    for (const auto &o : s.obstacles) require(ndcli::region_id(s, o.region) >= 0, "a region number");
    // the values in time evaluate anywhere (any value, NaN included: the library refuses a non-finite one)
    std::vector<const ndcli::TimeValue *> values{&s.body_force};
    for (const auto &t : s.tractions) values.push_back(&t.value);
    for (const auto &l : s.nodal) values.push_back(&l.value);
    for (const auto &m : s.motions) values.push_back(&m.value);
    for (const auto &o : s.obstacles) values.push_back(&o.position), values.push_back(&o.rotation);
    for (const ndcli::TimeValue *v : values)
      for (double t : {0.0, 0.5, -1.0, 1e300, std::nan("")})
        require(v->at(t).size() == v->size(), "a value in time has its components");
  } catch (const ndcli::SceneError &e) {
    const std::string what = e.what();
    require(what.compare(0, path.size(), path) == 0, "the message names the scene:", what);
    require(!has_control(ndcli::printable(what)), "a printable message");
  }
  return 0;
}
