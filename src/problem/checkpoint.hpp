// The state at t^n as bytes (docs/design.md §8): everything a step reads, so that a
// run resumed from a checkpoint is bitwise the uninterrupted one. Layout
// (little-endian, as the machine writes doubles):
//   magic "NDSTATE\0", u32 version, u32 reserved, u64 fingerprint of the
//   problem's structure, u64 payload size, payload, u64 checksum (FNV-1a of
//   all that precedes it).
// The fingerprint covers what makes a state meaningful for a problem: the
// dimension, degree, mesh, clamped DOFs and contact points, not the scheme
// or the time step (a coupled code may change those between steps).
#pragma once
#include <cstdint>
#include <vector>

#include "fem/space.hpp"
#include "problem/discretization.hpp"
#include "time/state.hpp"

namespace nd {

uint64_t state_fingerprint(const Space &s, const Discretization &d);
// n_free unknowns, n_clamped clamped DOFs, n_contact contact points
struct StateSizes {
  int64_t n_free, n_clamped, n_contact;
};
// Every field that may be absent or grow (the load, the reactions, the
// tangent's history) takes the room of its longest form: a problem's
// checkpoints all have max_state_size(sizes) bytes.
std::vector<unsigned char> encode_state(const State &s, uint64_t fingerprint, const StateSizes &sizes);
// Throws ND_ERR_FORMAT (truncated, corrupted, another version) or ND_ERR_STATE
// (another problem); `out` is written only on success.
void decode_state(const unsigned char *buf, int64_t nbytes, uint64_t fingerprint, const StateSizes &sizes, State &out);
// The size of every checkpoint of a problem of these sizes.
int64_t max_state_size(const StateSizes &sizes);
// A checkpoint file of `size` bytes > max_size, of which `head` holds the
// first nbytes: throws ND_ERR_STATE when its header names another problem,
// else ND_ERR_FORMAT (bad magic, version, or too large).
constexpr int64_t kStateHeaderSize = 32;
[[noreturn]] void refuse_oversized_state(const unsigned char *head, int64_t nbytes, uint64_t fingerprint,
                                         uint64_t size, uint64_t max_size);

}  // namespace nd
