// The scene file of the command-line driver nitschedyn(1): a TOML file read
// into a Scene, validated as far as it can be without the library (keys,
// types, sizes, ranges). Every value keeps where it came from ("file:line:col")
// so that the library's later refusal of a value can still name its line.
#ifndef ND_CLI_SCENE_HPP
#define ND_CLI_SCENE_HPP

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "time_value.hpp"

namespace ndcli {

// A scene that cannot be used: the message starts with "file:line:col: "
// when the place is known. Exit status 2.
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A reference to a region: a number, or a name defined in [regions].
struct RegionRef {
  int id = -1;
  std::string name;  // empty for a number
  std::string at;    // where the reference is written
};

struct RegionBox {  // [regions] name = { id = N, lo = [...], hi = [...] }
  std::string name;
  int id = 0;
  std::vector<double> lo, hi;
  std::string at;
};

// A region's vector in time: a traction ([[loads.traction]] region, value)
// or a clamped region's displacement ([[dirichlet.motion]] region, displacement).
struct RegionValue {
  RegionRef region;
  TimeValue value;
  std::string at;
};
using Traction = RegionValue;
using Motion = RegionValue;

struct NodalLoad {  // [[loads.nodal]] node = N, value = ...: a force on one FE node
  int64_t node = 0;
  TimeValue value;
  std::string at;
};


// friction = { law = "coulomb", coefficient = F } or { law = "tresca", threshold = s }
// (an obstacle's region, or a contact pair's slave region: nd_problem_set_friction)
struct FrictionEntry {
  int law = 0;  // ND_FRICTION_*
  double parameter = 0;
  std::string at;  // empty: not given
};

struct Obstacle {
  RegionRef region;
  std::string shape = "plane";  // plane, sphere, cylinder
  std::vector<double> point, normal;  // plane: point, normal; cylinder: point (of the axis)
  std::vector<double> center, axis;   // sphere: center; cylinder: axis
  double radius = 0;
  bool inside = false;
  std::vector<double> velocity;  // a constant translation velocity (empty: at rest)
  FrictionEntry friction;
  TimeValue position;            // its translation from where it is defined, in time (empty: none)
  TimeValue rotation;            // an angle about the origin (2D) or the z axis (3D), in time (empty: none)
  std::string at;
};

struct ContactPairEntry {  // [[contact_pair]]: two bodies' regions (nd_problem_set_contact_pair)
  RegionRef slave, master;
  FrictionEntry friction;  // the slave region's: friction between the bodies
  std::string at;
};

struct Guard {  // [guards]: an nd_problem_set_guard call
  int id = 0;
  double value = 0;
  std::string key, at;
};

// A [[material]] entry of a cell region (>= 1): a Gmsh physical group of
// cells, or the cells whose centroid lies in [lo, hi] (lo, hi given)
struct RegionMaterial {
  int region = 0;
  double young = 0, poisson = 0, density = 0;
  bool poisson_given = false;
  std::vector<double> lo, hi;  // empty: the mesh's own cell region
  std::string at;
};

struct Scene {
  std::string file;   // the scene file as given
  std::string title;  // optional
  // [mesh]: a Gmsh file or a generated mesh
  std::string gmsh;   // resolved against the scene file's directory
  std::string gmsh_at;
  std::string generate;  // "interval", "rectangle", "box" or empty
  std::vector<int64_t> cells;
  int cell_type = 0;  // ND_CELL_SIMPLEX, or ND_CELL_QUADRILATERAL / ND_CELL_HEXAHEDRON (whole cells)
  std::vector<double> lo, hi;
  int dim = 0;  // known after reading the mesh when it comes from Gmsh
  int degree = 1;
  std::string mesh_at;
  // [regions]
  std::vector<RegionBox> boxes;
  std::vector<std::pair<std::string, int>> names;  // every named region
  // [material], or [[material]]: the entry without a region is the default
  double young = 0, poisson = 0, density = 0;
  bool poisson_given = false;
  std::array<double, 2> damping{0, 0};  // [material] damping = [alpha, beta]
  std::string damping_at;
  bool plane_stress = false;  // [material] plane_stress (2D)
  std::string material_at;
  std::vector<RegionMaterial> region_materials;  // the entries with a region
  // [loads]
  TimeValue body_force;
  std::string body_force_at;
  std::vector<Traction> tractions;
  std::vector<NodalLoad> nodal;
  // [dirichlet]
  std::vector<RegionRef> clamped;
  std::vector<Motion> motions;
  // [obstacle] or [[obstacle]]
  std::vector<Obstacle> obstacles;
  // [contact_pair] or [[contact_pair]]
  std::vector<ContactPairEntry> pairs;
  // [nitsche]
  double Theta = 1, gamma0 = 0;  // gamma0 = 0: automatic
  std::string nitsche_at;
  // [scheme]
  std::string scheme = "hybrid";
  int scheme_id = 0;
  std::array<double, 2> params{{0, 0}};
  std::string scheme_at;
  // [time]
  double tau = 0, T = 0;
  bool tau_given = false, T_given = false;
  std::string tau_at, T_at;
  // adaptive steps (tolerance 0: fixed steps of tau); tau_min, tau_max: 0
  // until given (then 1e-6 tau and tau)
  double tolerance = 0, tau_min = 0, tau_max = 0;
  std::string tolerance_at;
  // [solver]
  std::string linear = "auto";
  int solver_id = 0;
  double newton_rtol = 1e-10, newton_atol = 0;
  int64_t newton_max_iter = 50;
  bool newton_given = false;
  bool mass_lumping = false;
  bool mass_redistribution = false;  // nd_problem_set_mass_redistribution
  std::string solver_at;
  // [initial]
  std::vector<double> u0, v0;
  std::string u0_at, v0_at;
  // [output]
  std::string history;      // CSV path, empty: none
  std::string paraview;     // VTU/PVD prefix, empty: none
  double interval = 0;      // time between ParaView frames; 0: every step
  std::string output_at;
  // [guards], in the order written
  std::vector<Guard> guards;
  // [checkpoint]: nd_problem_save_state_file at the end and every K steps
  std::string checkpoint;   // path (under --out), empty: none
  int64_t checkpoint_every = 0;  // 0: at the end only
  std::string checkpoint_at;
};

// What a scene may be: checked before the TOML parser sees the text (toml++
// 3.3.0 recurses once per part of a dotted key, and reaches
// __builtin_unreachable on some non-ASCII characters outside strings), and
// after it (the sizes of generated meshes, the step count).
constexpr size_t kMaxSceneBytes = size_t(1) << 20;  // 1 MiB
constexpr int kMaxKeyParts = 16;                    // a.b.c = ...: parts of a dotted key or table name
constexpr int kMaxNesting = 32;                     // [ and { open at once
constexpr int64_t kMaxCellsPerDirection = 1000000;  // mesh.cells[i]
constexpr int64_t kMaxCells = 10000000;             // the product of mesh.cells

// Reads a scene file (at most kMaxSceneBytes) and parses it (parse_scene).
// Throws SceneError.
Scene read_scene(const std::string &path);

// Parses and validates the text of a scene file; path names it in messages
// and resolves mesh.gmsh (whose existence is checked; the mesh is not read).
// Throws SceneError.
Scene parse_scene(std::string_view text, const std::string &path);

// The number of steps of the run, round(T / tau), once T and tau are known
// (the scene or the command line): refused unless it is a finite number that
// an int64_t holds. Throws SceneError.
int64_t step_count(const Scene &s);

// Text from the scene made safe to print on a terminal: control characters
// (C0, DEL, C1) become '?', except that tabs and line breaks become spaces.
std::string printable(std::string_view text);

// Checks what needs the space dimension (vector lengths), once it is known.
void check_dimension(const Scene &s, int dim);

// The number of a region reference (a name is looked up). Throws SceneError.
int region_id(const Scene &s, const RegionRef &r);

// The documented keys of every table, for the manual page's test.
std::vector<std::string> documented_keys();

}  // namespace ndcli
#endif
