// The state at t^n as bytes (docs/design.md §8): everything a step reads, so that a
// run resumed from a checkpoint is bitwise the uninterrupted one. Layout
// (little-endian, as the machine writes doubles):
//   magic "NDSTATE\0", u32 version, u32 reserved (0), u64 fingerprint of the
//   problem's structure, u64 payload size, payload, u64 checksum (FNV-1a of
//   all that precedes it: state_checksum). The checksum finds accidents only
//   (anyone can recompute it): decode_state checks every field's meaning.
// The fingerprint covers the problem's structure: the dimension, degree,
// mesh, clamped DOFs and contact points (a state of another structure has
// other sizes and is refused). Since version 6 the payload starts with the
// definition's fingerprints (DefinitionPrint): what else the values mean
// depends on, one per aspect, so that a refusal says what differs.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fem/space.hpp"
#include "problem/discretization.hpp"
#include "time/state.hpp"

namespace nd {

uint64_t state_fingerprint(const Space &s, const Discretization &d);

// The aspects of a definition a state's meaning depends on (the energies,
// the acceleration, the applied contact term and the tangent's history are
// the material's, Theta's and gamma0's, the scheme's and the step's), one
// fingerprint each; 0: an aspect the problem has not been given yet
// (scheme, time step, Nitsche parameters), not compared. Not in it, since a
// restart may change them: the loads' values and the planes' points (they
// change from step to step), the linear solver, Newton's options, the
// guards' factors, the ranks, the initial state (the state replaces it).
enum DefinitionAspect : int {
  kPrintMaterial,
  kPrintNitsche,   // Theta and the gamma0 in use
  kPrintScheme,    // the scheme and its parameters
  kPrintTimestep,  // tau
  kPrintMass,      // lumping, redistribution
  kPrintDirichlet, // the clamped regions
  kPrintPlanes,    // the contact planes' regions and normals
  kPrintAspects
};
using DefinitionPrint = std::array<uint64_t, kPrintAspects>;
DefinitionPrint definition_print(const Definition &def, const Discretization &d);

// FNV-1a of a checkpoint's first n bytes: the checksum written after them
// (the fuzz target reseals its inputs with it)
uint64_t state_checksum(const unsigned char *buf, size_t n);
// n_free unknowns, n_clamped clamped DOFs, n_contact contact points
// and n_positions values of the obstacles' positions (curved obstacles,
// contact/obstacles.hpp; 0: planes alone, whose checkpoints keep version 6)
struct StateSizes {
  int64_t n_free, n_clamped, n_contact;
  int64_t n_positions = 0;
  int64_t n_slip = 0;  // friction: the slip references' values (m - 1 per point), else 0
  int64_t n_by_region = 0;  // friction: State::by_region's values (3 per contact region)
  // friction without curved obstacles: the planes' points at t^n (3 per
  // plane, State::positions), in the friction section; else 0
  int64_t n_places = 0;
  // contact pairs: the pairings (kPairingValues per point) and, without
  // curved obstacles, the frozen normals and W_geometry follow the friction's
  // section; n_boundary, the mesh's boundary facets, bounds a pairing's facet
  bool pairs = false;
  int64_t n_boundary = 0;
  bool adaptive = false;  // adaptive time steps: the step control (State::control) follows
};
// Every field that may be absent or grow (the load, the reactions, the
// tangent's history) takes the room of its longest form: a problem's
// checkpoints all have max_state_size(sizes) bytes.
std::vector<unsigned char> encode_state(const State &s, uint64_t fingerprint, const DefinitionPrint &print,
                                        const StateSizes &sizes);
// Throws ND_ERR_FORMAT (truncated, corrupted, another version, a field out
// of its range: a negative step count, a time, vector, energy or work that
// is not finite, a flag not 0 or 1, ...) or ND_ERR_STATE (another problem:
// structure, or since version 6 an aspect of the definition both give);
// `out` is written only on success.
void decode_state(const unsigned char *buf, int64_t nbytes, uint64_t fingerprint, const DefinitionPrint &print,
                  const StateSizes &sizes, State &out);
// The size of every checkpoint of a problem of these sizes.
int64_t max_state_size(const StateSizes &sizes);
// A checkpoint file of `size` bytes > max_size, of which `head` holds the
// first nbytes: throws ND_ERR_STATE when its header names another problem,
// else ND_ERR_FORMAT (bad magic, version, or too large).
constexpr int64_t kStateHeaderSize = 32;
[[noreturn]] void refuse_oversized_state(const unsigned char *head, int64_t nbytes, uint64_t fingerprint,
                                         uint64_t size, uint64_t max_size);

}  // namespace nd
