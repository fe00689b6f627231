#include "problem/checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "common/error.hpp"
#include "common/hash.hpp"
#include "nitschedyn.h"
#include "solve/tangent_solver.hpp"

namespace nd {
namespace {

constexpr char kMagic[8] = {'N', 'D', 'S', 'T', 'A', 'T', 'E', '\0'};
// 2: the obstacle (gaps, work), the clamped load and the reactions; 3: the
// applied contact term phi; 4: the tangent's history, and every vector that
// may be absent in its full room, so that a problem's checkpoints have one
// size; 5: the history's room grows with the contact points
// (updown_max_updates), from 256 columns; 6: the definition's fingerprints
// (DefinitionPrint) open the payload, and every field is checked for its
// meaning (versions 3 to 5 are still read, without the definition's check);
// 7: with curved obstacles (StateSizes::n_positions > 0) the frozen normals
// and the obstacles' positions at t^n follow (without, version 6 is written);
// 8 (always written): after the obstacle's work the damping's dissipation
// (State::D_damping) and a byte of flags saying which sections follow the
// tangent's history: 1, the normals and positions of 7 (curved obstacles);
// 2, the friction's (StateSizes::n_slip > 0: the slip references, the
// applied tangential values, D_f and the sliding and sticking points); then
// always the prescribed motion: the clamped DOFs' U, V, A and W_prescribed;
// 9 (always written): the curved obstacles' section ends with W_geometry,
// and without curved obstacles the friction section with the planes' points
// at t^n (StateSizes::n_places); 10 (always written): flag 4, the contact
// pairs' section after the friction's: each point's pairing (kPairingValues:
// the facet, then 3 coordinates: barycentric, or a hexahedron's face's (s,
// t, 0), contact/pairing.hpp; the same size whatever the cells), then (without
// the curved obstacles' section) the frozen normals and W_geometry; 11
// (always written): after W_prescribed the energy-balance guard's state
// (GuardState: balance, its lowest value, E_top, exchange, in contact), and
// flag 8, adaptive time steps (StateSizes::adaptive): the step control
// (StepControl: tau_next, tau_last, ratio, scale, hold, the mean acceleration);
// 12 (always written): the friction section ends with each contact region's
// D_f, sliding and sticking points (State::by_region; read from 8 to 11 only
// with one contact region, whose values are the whole problem's)
constexpr uint32_t kVersion = 12;
uint32_t version_for(const StateSizes &) { return kVersion; }

class Writer {
 public:
  template <class T>
  void value(const T &x) {
    const unsigned char *p = reinterpret_cast<const unsigned char *>(&x);
    out.insert(out.end(), p, p + sizeof x);
  }
  template <class T>
  void vec(const std::vector<T> &v) {
    value(static_cast<uint64_t>(v.size()));
    const unsigned char *p = reinterpret_cast<const unsigned char *>(v.data());
    out.insert(out.end(), p, p + v.size() * sizeof(T));
  }
  // v's size, its values, then zeros up to `most` values: a field whose
  // bytes do not depend on its length (the checkpoint's size is the problem's)
  template <class T>
  void padded(const std::vector<T> &v, uint64_t most) {
    if (v.size() > most) fail(ND_ERR_INTERNAL, "a checkpoint field is longer than its room");
    vec(v);
    out.insert(out.end(), (most - v.size()) * sizeof(T), 0);
  }
  std::vector<unsigned char> out;
};

class Reader {
 public:
  Reader(const unsigned char *p, size_t n) : p_(p), n_(n) {}
  template <class T>
  T value() {
    T x;
    need(sizeof x);
    std::memcpy(&x, p_ + at_, sizeof x);
    at_ += sizeof x;
    return x;
  }
  // a vector of exactly `expected` doubles (or 0, for an empty load)
  std::vector<double> vec(int64_t expected, bool may_be_empty, const char *what) {
    const uint64_t n = value<uint64_t>();
    if (n != static_cast<uint64_t>(expected) && !(may_be_empty && n == 0))
      fail(ND_ERR_FORMAT, std::string("the checkpoint's ") + what + " has " + std::to_string(n) + " values, expected " +
                              std::to_string(expected));
    return values<double>(n);
  }
  // a vector of at most `most` values of T
  template <class T>
  std::vector<T> bounded(uint64_t most, const char *what) {
    const uint64_t n = value<uint64_t>();
    if (n > most)
      fail(ND_ERR_FORMAT, std::string("the checkpoint's ") + what + " has " + std::to_string(n) +
                              " values, more than the " + std::to_string(most) + " it can have");
    return values<T>(n);
  }
  // what Writer::padded wrote
  template <class T>
  std::vector<T> padded(uint64_t most, const char *what) {
    std::vector<T> v = bounded<T>(most, what);
    const uint64_t pad = (most - v.size()) * sizeof(T);
    need(pad);
    for (uint64_t k = 0; k < pad; ++k)
      if (p_[at_ + k] != 0) fail(ND_ERR_FORMAT, std::string("the checkpoint's ") + what + " has non-zero padding");
    at_ += pad;
    return v;
  }
  size_t at() const { return at_; }

 private:
  // n values of T (n already bounded by the caller: n sizeof(T) does not overflow)
  template <class T>
  std::vector<T> values(uint64_t n) {
    need(n * sizeof(T));
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), p_ + at_, n * sizeof(T));
    at_ += n * sizeof(T);
    return v;
  }
  void need(size_t k) {
    if (k > n_ - at_) fail(ND_ERR_FORMAT, "the checkpoint is truncated");
  }
  const unsigned char *p_;
  size_t n_, at_ = 0;
};

}  // namespace

uint64_t state_checksum(const unsigned char *buf, size_t n) {
  Hash h;
  h.bytes(buf, n);
  return h.h;
}

DefinitionPrint definition_print(const Definition &def, const Discretization &d) {
  DefinitionPrint print{};
  auto done = [&print](int aspect, const Hash &h) { print[aspect] = h.h == 0 ? 1 : h.h; };  // 0: not given
  {
    Hash h;
    h.value(def.material.young), h.value(def.material.poisson), h.value(def.material.density);
    if (def.material.plane_stress) h.value(uint8_t{1});  // (only when on: older prints still match)
    for (const auto &[region, m] : def.region_materials)  // (none: the print of one material)
      h.value(region), h.value(m.young), h.value(m.poisson), h.value(m.density);
    done(kPrintMaterial, h);
  }
  if (def.given & kNitsche) {
    Hash h;
    h.value(def.theta), h.value(d.gamma0);
    // (friction only when there is some: a frictionless problem's print is as before)
    for (const Definition::Friction &f : def.friction) h.value(f.region), h.value(f.law), h.value(f.parameter);
    done(kPrintNitsche, h);
  }
  if (def.given & kScheme) {
    Hash h;
    h.value(def.scheme);
    h.vec(def.scheme_params);
    done(kPrintScheme, h);
  }
  if (def.given & kTimestep) {
    Hash h;
    // (adaptive steps: the sizes they may take; the size now is the state's)
    if (def.adaptive.on()) h.value(def.adaptive.tolerance), h.value(def.adaptive.tau_min), h.value(def.adaptive.tau_max);
    else h.value(def.tau);
    done(kPrintTimestep, h);
  }
  {
    Hash h;
    h.value(uint8_t{def.lumped}), h.value(uint8_t{def.redistributed});
    done(kPrintMass, h);
  }
  {
    std::vector<int> regions = def.dirichlet;  // a set: neither order nor repetition counts
    std::sort(regions.begin(), regions.end());
    regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
    Hash h;
    h.vec(regions);
    done(kPrintDirichlet, h);
  }
  {
    std::vector<const ContactPlane *> planes;
    for (const ContactPlane &pl : def.planes) planes.push_back(&pl);
    std::sort(planes.begin(), planes.end(), [](const ContactPlane *a, const ContactPlane *b) { return a->region < b->region; });
    Hash h;
    h.value(static_cast<uint64_t>(planes.size()));
    for (const ContactPlane *pl : planes) h.value(pl->region), h.bytes(pl->normal, sizeof pl->normal);
    // the added obstacles, by what they are (where they are may change, as a plane's point)
    if (!def.obstacles.empty()) h.value(static_cast<uint64_t>(def.obstacles.size()));
    for (const Obstacle &o : def.obstacles) h.value(o.region), o.shape->fingerprint(h);
    // the contact pairs (none: the digest as before)
    if (!def.pairs.empty()) h.value(static_cast<uint64_t>(def.pairs.size()));
    for (const ContactPair &pair : def.pairs) h.value(pair.slave), h.value(pair.master);
    done(kPrintPlanes, h);
  }
  return print;
}

uint64_t state_fingerprint(const Space &s, const Discretization &d) {
  Hash h;
  h.value(s.dim);
  h.value(s.degree);
  h.vec(s.mesh->coords);
  h.vec(s.mesh->cells);
  if (s.mesh->cell_type) h.value(s.mesh->cell_type);  // (simplices: the digest as before)
  h.vec(d.dofs.free);
  h.vec(d.contact.w);
  h.vec(d.contact.x);
  // the mass: only when redistributed, so that older checkpoints still match
  if (!d.massless.empty()) h.value(uint8_t{1});
  return h.h;
}

namespace {
// the most values a TangentLog of n_contact points holds (tangent_solver.hpp);
// version 4 gave every problem room for 256 updated columns
int64_t log_updates(int64_t n_contact, uint32_t version) {
  return version == 4 ? 256 : updown_max_updates(n_contact);
}
uint64_t log_indices(int64_t n_contact, uint32_t version) {
  return static_cast<uint64_t>(1 + n_contact + 2 * log_updates(n_contact, version));
}
uint64_t log_values(int64_t n_contact, uint32_t version) {
  return static_cast<uint64_t>(n_contact + log_updates(n_contact, version));
}
}  // namespace

std::vector<unsigned char> encode_state(const State &s, uint64_t fingerprint, const DefinitionPrint &print,
                                        const StateSizes &sizes) {
  const int64_t n_contact = sizes.n_contact;
  const uint64_t n_free = static_cast<uint64_t>(sizes.n_free), n_clamped = static_cast<uint64_t>(sizes.n_clamped);
  Writer payload;
  for (uint64_t x : print) payload.value(x);
  payload.value(s.t);
  payload.value(s.n);
  payload.value(s.t_ref);
  payload.value(s.tau_ref);
  payload.value(s.n_ref);
  payload.vec(s.U);
  payload.vec(s.V);
  payload.vec(s.A);
  payload.padded(s.load(), n_free);
  payload.value(static_cast<uint8_t>(s.A_valid));
  payload.value(s.W);
  payload.value(static_cast<int64_t>(s.last_iterations));
  payload.value(s.total_iterations);
  payload.value(s.guard.E0);
  payload.value(s.guard.budget);
  payload.padded(s.F_fixed, n_clamped);
  payload.padded(s.gap, static_cast<uint64_t>(n_contact));
  payload.value(s.W_obstacle);
  const uint32_t version = version_for(sizes);
  payload.value(s.D_damping);
  const bool positions = sizes.n_positions > 0, friction = sizes.n_slip > 0, pairs = sizes.pairs;
  payload.value(static_cast<uint8_t>((positions ? 1 : 0) | (friction ? 2 : 0) | (pairs ? 4 : 0) |
                                     (sizes.adaptive ? 8 : 0)));
  payload.padded(s.reaction, n_clamped);
  payload.padded(s.phi, static_cast<uint64_t>(n_contact));
  payload.padded(s.tangent_log.i, log_indices(n_contact, version));
  payload.padded(s.tangent_log.x, log_values(n_contact, version));
  if (positions) {
    payload.padded(s.normal, static_cast<uint64_t>(3 * n_contact));
    payload.padded(s.positions, static_cast<uint64_t>(sizes.n_positions));
    payload.value(s.W_geometry);
  }
  if (friction) {
    payload.padded(s.slip, static_cast<uint64_t>(sizes.n_slip));
    payload.padded(s.phi_t, static_cast<uint64_t>(sizes.n_slip));
    payload.value(s.D_friction);
    payload.value(s.sliding);
    payload.value(s.sticking);
    payload.padded(s.by_region, static_cast<uint64_t>(sizes.n_by_region));
    if (sizes.n_places > 0) payload.padded(s.positions, static_cast<uint64_t>(sizes.n_places));
  }
  if (pairs) {
    payload.padded(s.pairing, static_cast<uint64_t>(kPairingValues * n_contact));
    if (!positions) {
      payload.padded(s.normal, static_cast<uint64_t>(3 * n_contact));
      payload.value(s.W_geometry);
    }
  }
  payload.padded(s.Uc, n_clamped);
  payload.padded(s.Vc, n_clamped);
  payload.padded(s.Ac, n_clamped);
  payload.value(s.W_prescribed);
  const GuardState &g = s.guard;
  for (double x : {g.balance, g.balance_low, g.E_top, g.exchange}) payload.value(x);
  payload.value(static_cast<uint8_t>(g.in_contact));
  if (sizes.adaptive) {
    const StepControl &c = s.control;
    for (double x : {c.tau_next, c.tau_last, c.ratio, c.scale, c.hold}) payload.value(x);
    payload.padded(c.a_mean, n_free);
  }
  Writer w;
  w.out.assign(kMagic, kMagic + sizeof kMagic);
  w.value(version);
  w.value(uint32_t{0});
  w.value(fingerprint);
  w.value(static_cast<uint64_t>(payload.out.size()));
  w.out.insert(w.out.end(), payload.out.begin(), payload.out.end());
  w.value(state_checksum(w.out.data(), w.out.size()));
  return std::move(w.out);
}

namespace {
struct Header {
  uint32_t version;
  uint64_t fingerprint, payload_size;
};
// magic and version checked; the rest unchecked until the checksum is
Header read_header(Reader &r, const unsigned char *buf, int64_t nbytes) {
  if (nbytes < static_cast<int64_t>(sizeof kMagic) || std::memcmp(buf, kMagic, sizeof kMagic) != 0)
    fail(ND_ERR_FORMAT, "not a checkpoint of this library (bad magic number)");
  r.value<std::array<char, 8>>();
  const uint32_t version = r.value<uint32_t>();
  if (version < 3 || version > kVersion)
    fail(ND_ERR_FORMAT, "the checkpoint has version " + std::to_string(version) + "; this library reads versions 3 to " +
                            std::to_string(kVersion));
  if (r.value<uint32_t>() != 0) fail(ND_ERR_FORMAT, "the checkpoint's reserved header field is not 0");
  Header h;
  h.version = version;
  h.fingerprint = r.value<uint64_t>();
  h.payload_size = r.value<uint64_t>();
  return h;
}
}  // namespace

void refuse_oversized_state(const unsigned char *head, int64_t nbytes, uint64_t fingerprint, uint64_t size,
                            uint64_t max_size) {
  Reader r(head, static_cast<size_t>(nbytes));
  if (read_header(r, head, nbytes).fingerprint != fingerprint)
    fail(ND_ERR_STATE, "the checkpoint is of another problem (mesh, degree, clamped DOFs or contact points differ)");
  fail(ND_ERR_FORMAT, "the checkpoint has " + std::to_string(size) + " bytes, more than the " +
                          std::to_string(max_size) + " of any checkpoint of this problem");
}

int64_t max_state_size(const StateSizes &sizes) {
  State s;  // every vector at its full length: the layout's size, without a second copy of it
  s.U.resize(static_cast<size_t>(sizes.n_free));
  s.V = s.A = s.U;
  s.F = std::make_shared<const std::vector<double>>(s.U);
  s.F_fixed.resize(static_cast<size_t>(sizes.n_clamped));
  s.reaction = s.F_fixed;
  s.gap.resize(static_cast<size_t>(sizes.n_contact));
  s.phi = s.gap;
  if (sizes.n_positions > 0) {
    s.normal.resize(static_cast<size_t>(3 * sizes.n_contact));
    s.positions.resize(static_cast<size_t>(sizes.n_positions));
  }
  if (sizes.n_places > 0) s.positions.resize(static_cast<size_t>(sizes.n_places));
  s.slip.resize(static_cast<size_t>(sizes.n_slip));
  s.phi_t = s.slip;
  s.by_region.resize(static_cast<size_t>(sizes.n_by_region));
  if (sizes.pairs) {
    s.pairing.resize(static_cast<size_t>(kPairingValues * sizes.n_contact));
    s.normal.resize(static_cast<size_t>(3 * sizes.n_contact));
  }
  s.Uc = s.Vc = s.Ac = s.F_fixed;
  if (sizes.adaptive) s.control.a_mean = s.U;
  return static_cast<int64_t>(encode_state(s, 0, DefinitionPrint{}, sizes).size());
}

namespace {
const char *const kAspectNames[kPrintAspects] = {
    "material (nd_problem_set_material, nd_problem_set_material_region)",
    "Nitsche parameters (Theta, gamma0 in use)",
    "time scheme or its parameters",
    "time step",
    "mass (lumping, redistribution)",
    "clamped regions (Dirichlet)",
    "contact planes and obstacles (regions, normals, shapes)",
};

// what differs between the checkpoint's definition and the problem's, in
// the aspects both have been given
void refuse_other_definition(const DefinitionPrint &saved, const DefinitionPrint &now) {
  std::string differ;
  for (int k = 0; k < kPrintAspects; ++k)
    if (saved[k] != 0 && now[k] != 0 && saved[k] != now[k]) differ += (differ.empty() ? "" : ", ") + std::string(kAspectNames[k]);
  if (!differ.empty())
    fail(ND_ERR_STATE, "the checkpoint is of a problem defined otherwise: its " + differ +
                           " differ from this problem's; define the problem as it was saved, load, then change "
                           "what a restart may change (the scheme, the time step: as between steps)");
}

void need_finite(double x, const char *what) {
  if (!std::isfinite(x)) fail(ND_ERR_FORMAT, std::string("the checkpoint's ") + what + " is not finite");
}
void need_finite(const std::vector<double> &v, const char *what) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      fail(ND_ERR_FORMAT, std::string("the checkpoint's ") + what + " has a value that is not finite (entry " +
                              std::to_string(i) + ")");
}
}  // namespace

void decode_state(const unsigned char *buf, int64_t nbytes, uint64_t fingerprint, const DefinitionPrint &print,
                  const StateSizes &sizes, State &out) {
  const int64_t n_free = sizes.n_free;
  Reader r(buf, static_cast<size_t>(nbytes));
  const Header head = read_header(r, buf, nbytes);
  const uint64_t structure = head.fingerprint, size = head.payload_size;
  const size_t end = r.at() + size;
  if (size > static_cast<uint64_t>(nbytes) || end + sizeof(uint64_t) != static_cast<size_t>(nbytes))
    fail(ND_ERR_FORMAT, "the checkpoint is truncated or has trailing bytes (" + std::to_string(nbytes) + " bytes)");
  uint64_t sum;
  std::memcpy(&sum, buf + end, sizeof sum);
  if (sum != state_checksum(buf, end)) fail(ND_ERR_FORMAT, "the checkpoint is corrupted (checksum mismatch)");
  if (structure != fingerprint)
    fail(ND_ERR_STATE, "the checkpoint is of another problem (mesh, degree, clamped DOFs, contact points or mass redistribution differ)");
  if (head.version >= 6) {
    DefinitionPrint saved;
    for (uint64_t &x : saved) x = r.value<uint64_t>();
    refuse_other_definition(saved, print);
  }
  // a vector that may be absent: since version 4 in its full room (padded)
  auto optional = [&](int64_t expected, const char *what) {
    if (head.version < 4) return r.vec(expected, true, what);
    std::vector<double> v = r.padded<double>(static_cast<uint64_t>(expected), what);
    if (!v.empty() && static_cast<int64_t>(v.size()) != expected)
      fail(ND_ERR_FORMAT, std::string("the checkpoint's ") + what + " has " + std::to_string(v.size()) +
                              " values, expected " + std::to_string(expected));
    return v;
  };
  State s;
  s.t = r.value<double>();
  s.n = r.value<int64_t>();
  s.t_ref = r.value<double>();
  s.tau_ref = r.value<double>();
  s.n_ref = r.value<int64_t>();
  // every field's meaning, in the order of the layout
  if (s.n < 0) fail(ND_ERR_FORMAT, "the checkpoint's step count is " + std::to_string(s.n) + ", negative");
  need_finite(s.t, "time");
  need_finite(s.t_ref, "time of the last change of the time step (t_ref)");
  need_finite(s.tau_ref, "time step since its last change (tau_ref)");
  if (s.n_ref < 0 || s.n_ref > s.n)
    fail(ND_ERR_FORMAT, "the checkpoint's step of the last change of the time step (n_ref = " + std::to_string(s.n_ref) +
                            ") is outside [0, n = " + std::to_string(s.n) + "]");
  if (s.tau_ref < 0 || (s.n > 0 && !(s.tau_ref > 0)))
    fail(ND_ERR_FORMAT, "the checkpoint's time step since its last change (tau_ref) is not positive");
  {  // t = t_ref + (n - n_ref) tau_ref, as a step computes it (to round-off: another compiler may contract it)
    const double steps = static_cast<double>(s.n - s.n_ref) * s.tau_ref, t = s.t_ref + steps;
    if (!std::isfinite(t) || std::fabs(s.t - t) > 1e-12 * (std::fabs(s.t_ref) + std::fabs(steps)))
      fail(ND_ERR_FORMAT, "the checkpoint's time is not t_ref + (n - n_ref) tau_ref");
  }
  s.U = r.vec(n_free, false, "displacement");
  need_finite(s.U, "displacement");
  s.V = r.vec(n_free, false, "velocity");
  need_finite(s.V, "velocity");
  s.A = r.vec(n_free, false, "acceleration");
  need_finite(s.A, "acceleration");
  std::vector<double> F = optional(n_free, "load");
  need_finite(F, "load");
  s.F = std::make_shared<const std::vector<double>>(std::move(F));
  const uint8_t A_valid = r.value<uint8_t>();
  if (A_valid > 1) fail(ND_ERR_FORMAT, "the checkpoint's acceleration flag is " + std::to_string(A_valid) + ", not 0 or 1");
  s.A_valid = A_valid != 0;
  s.W = r.value<double>();
  need_finite(s.W, "work of the loads (W)");
  const int64_t last = r.value<int64_t>();
  if (last < 0 || last > std::numeric_limits<int>::max())
    fail(ND_ERR_FORMAT, "the checkpoint's Newton iteration count of the last step is " + std::to_string(last) +
                            ", outside [0, " + std::to_string(std::numeric_limits<int>::max()) + "]");
  s.last_iterations = static_cast<int>(last);
  s.total_iterations = r.value<int64_t>();
  if (s.total_iterations < 0)
    fail(ND_ERR_FORMAT, "the checkpoint's total of Newton iterations is " + std::to_string(s.total_iterations) + ", negative");
  s.guard.E0 = r.value<double>();
  s.guard.budget = r.value<double>();
  // (E0 may be negative: nd_problem_set_state counts a loss of energy into it)
  need_finite(s.guard.E0, "energy guard's initial energy (E0)");
  need_finite(s.guard.budget, "energy guard's budget");
  if (!(s.guard.budget >= s.guard.E0))
    fail(ND_ERR_FORMAT, "the checkpoint's energy guard's budget is below its initial energy (E0)");
  s.F_fixed = optional(sizes.n_clamped, "load on the clamped DOFs");
  need_finite(s.F_fixed, "load on the clamped DOFs");
  s.gap = optional(sizes.n_contact, "obstacle gaps");
  need_finite(s.gap, "obstacle gaps");
  s.W_obstacle = r.value<double>();
  need_finite(s.W_obstacle, "work of the obstacle (W_obstacle)");
  bool positions = head.version == 7, friction = false, pairs = false, control = false;
  if (head.version >= 8) {
    s.D_damping = r.value<double>();
    need_finite(s.D_damping, "dissipation of the damping");
    const uint8_t flags = r.value<uint8_t>();
    const unsigned most = head.version >= 11 ? 15 : head.version >= 10 ? 7 : 3;
    if (flags > most)
      fail(ND_ERR_FORMAT, "the checkpoint's section flags are " + std::to_string(flags) + ", not 0 to " +
                              std::to_string(most));
    positions = (flags & 1) != 0;
    friction = (flags & 2) != 0;
    pairs = (flags & 4) != 0;
    control = (flags & 8) != 0;
  }
  s.reaction = optional(sizes.n_clamped, "reactions");
  need_finite(s.reaction, "reactions");
  s.phi = optional(sizes.n_contact, "applied contact term");
  need_finite(s.phi, "applied contact term");
  if (head.version >= 4) {
    s.tangent_log.i = r.padded<int64_t>(log_indices(sizes.n_contact, head.version), "tangent history");
    s.tangent_log.x = r.padded<double>(log_values(sizes.n_contact, head.version), "tangent history");
    // (points in range and increasing, coefficients finite and positive, counts within the room)
    if (!tangent_log_well_formed(s.tangent_log, sizes.n_contact))
      fail(ND_ERR_FORMAT, "the checkpoint's tangent history is malformed");
  }
  if (positions) {
    s.normal = optional(3 * sizes.n_contact, "frozen contact normals");
    need_finite(s.normal, "frozen contact normals");
    s.positions = optional(sizes.n_positions, "obstacles' positions");
    need_finite(s.positions, "obstacles' positions");
    if (head.version >= 9) {
      s.W_geometry = r.value<double>();
      need_finite(s.W_geometry, "re-linearisation energy of the curved obstacles (W_geometry)");
    }
  }
  if (friction) {
    s.slip = optional(sizes.n_slip, "slip references (friction)");
    need_finite(s.slip, "slip references (friction)");
    s.phi_t = optional(sizes.n_slip, "applied tangential values (friction)");
    need_finite(s.phi_t, "applied tangential values (friction)");
    s.D_friction = r.value<double>();
    need_finite(s.D_friction, "frictional dissipation");
    if (!(s.D_friction >= 0)) fail(ND_ERR_FORMAT, "the checkpoint's frictional dissipation is negative");
    s.sliding = r.value<int64_t>();
    s.sticking = r.value<int64_t>();
    if (s.sliding < 0 || s.sticking < 0 || s.sliding > sizes.n_contact || s.sticking > sizes.n_contact - s.sliding)
      fail(ND_ERR_FORMAT, "the checkpoint's counts of sliding and sticking points are out of range");
    if (head.version >= 12) {
      s.by_region = optional(sizes.n_by_region, "contact regions' friction values");
      need_finite(s.by_region, "contact regions' friction values");
      for (size_t i = 0; i < s.by_region.size(); ++i)
        if (!(s.by_region[i] >= 0) || (i % 3 > 0 && s.by_region[i] != std::floor(s.by_region[i])))
          fail(ND_ERR_FORMAT, "the checkpoint's friction values of contact region " + std::to_string(i / 3) +
                                  " are negative or not counts");
    } else if (sizes.n_by_region == 3) {  // (one region: the problem's values are its)
      s.by_region = {s.D_friction, static_cast<double>(s.sliding), static_cast<double>(s.sticking)};
    }
    // (the planes' points, for the slip's shift; version 8 had none: its
    // friction had static planes, and Problem::prepare takes them where they are)
    if (head.version >= 9 && sizes.n_places > 0 && !positions) {
      s.positions = optional(sizes.n_places, "contact planes' points (friction)");
      need_finite(s.positions, "contact planes' points (friction)");
    }
  }
  if (pairs) {
    s.pairing = optional(kPairingValues * sizes.n_contact, "contact pairings");
    need_finite(s.pairing, "contact pairings");
    // (a facet index, -1 or one of the mesh's: the rows are made from it)
    for (size_t q = 0; q < s.pairing.size(); q += kPairingValues)
      if (s.pairing[q] != std::floor(s.pairing[q]) || s.pairing[q] < -1 || s.pairing[q] >= sizes.n_boundary)
        fail(ND_ERR_FORMAT, "the checkpoint's contact pairing of point " + std::to_string(q / kPairingValues) +
                                " names no boundary facet");
    if (!positions) {
      s.normal = optional(3 * sizes.n_contact, "frozen contact normals");
      need_finite(s.normal, "frozen contact normals");
      s.W_geometry = r.value<double>();
      need_finite(s.W_geometry, "re-linearisation energy of the contact pairs (W_geometry)");
    }
  }
  if (sizes.pairs != pairs || (pairs && (s.pairing.empty() || s.normal.empty())))
    fail(ND_ERR_STATE, sizes.pairs ? "the checkpoint has no contact pairs' state; this problem has contact pairs"
                                   : "the checkpoint has contact pairs; this problem has none");
  if ((sizes.n_slip > 0) != friction || (sizes.n_slip > 0 && s.slip.empty()))
    fail(ND_ERR_STATE, sizes.n_slip > 0 ? "the checkpoint has no friction state; this problem has friction"
                                        : "the checkpoint has a friction state; this problem has no friction");
  if (head.version >= 8) {  // prescribed motion: all three or none
    s.Uc = optional(sizes.n_clamped, "prescribed displacement");
    s.Vc = optional(sizes.n_clamped, "prescribed velocity");
    s.Ac = optional(sizes.n_clamped, "prescribed acceleration");
    for (const std::vector<double> *v : {&s.Uc, &s.Vc, &s.Ac}) need_finite(*v, "prescribed motion");
    if (s.Vc.size() != s.Uc.size() || s.Ac.size() != s.Uc.size())
      fail(ND_ERR_FORMAT, "the checkpoint's prescribed motion has some of U, V, A only");
    s.W_prescribed = r.value<double>();
    need_finite(s.W_prescribed, "work of the prescribed motion (W_prescribed)");
  }
  if (head.version >= 11) {  // the balance guard's state (before: it starts again)
    GuardState &g = s.guard;
    g.balance = r.value<double>(), g.balance_low = r.value<double>();
    g.E_top = r.value<double>(), g.exchange = r.value<double>();
    // (NaN: not evaluated yet; never infinite)
    for (double x : {g.balance, g.balance_low})
      if (std::isinf(x)) fail(ND_ERR_FORMAT, "the checkpoint's energy balance is infinite");
    need_finite(g.E_top, "largest mechanical energy (energy-balance guard)");
    need_finite(g.exchange, "contact exchange (energy-balance guard)");
    const uint8_t in_contact = r.value<uint8_t>();
    if (in_contact > 1) fail(ND_ERR_FORMAT, "the checkpoint's in-contact flag is not 0 or 1");
    g.in_contact = in_contact == 1;
  }
  if (control) {  // (a problem with fixed steps reads and drops it)
    StepControl c;
    c.tau_next = r.value<double>(), c.tau_last = r.value<double>(), c.ratio = r.value<double>();
    c.scale = r.value<double>(), c.hold = r.value<double>();
    for (double x : {c.tau_next, c.tau_last, c.ratio, c.scale, c.hold})
      if (!(std::isfinite(x) && x >= 0)) fail(ND_ERR_FORMAT, "the checkpoint's step control has a value that is negative or not finite");
    c.a_mean = optional(sizes.n_free, "mean acceleration (step control)");
    need_finite(c.a_mean, "mean acceleration (step control)");
    if (sizes.adaptive) s.control = std::move(c);
  }
  if ((sizes.n_positions > 0) != positions || (sizes.n_positions > 0 && s.positions.empty()))
    fail(ND_ERR_STATE, sizes.n_positions > 0 ? "the checkpoint has no curved obstacles (sphere, cylinder, distance); this problem has"
                                             : "the checkpoint has curved obstacles (sphere, cylinder, distance); this problem has none");
  if (r.at() != end) fail(ND_ERR_FORMAT, "the checkpoint's payload has an unexpected size");
  out = std::move(s);
}

}  // namespace nd
