// Work split over the ranks of a communicator, results gathered to every
// rank. The mesh and the state are replicated; what is split
// is the work of a step outside the solves: each contact point is evaluated
// by the rank of its cell, each row of the products M U, M V, M A, K U by
// the rank of its node (parallel/ownership.hpp). A Share lists which items
// (points, rows) each rank computes; gather() then fills the other ranks'
// items from them in one MPI_Allgatherv. Every item has one owner, computed
// there by the same code as on one rank, so the gathered values are bitwise
// those of one process; sums (the energies) are added rank after rank, the
// same on every rank.
//
// No share (null) means this process computes every item. gather() is
// collective: every rank calls it at the same point of a step.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "common/counters.hpp"
#include "common/row_set.hpp"
#include "parallel/communicator.hpp"

namespace nd {

struct Share {
  CommunicatorPtr comm;
  Counters *counters = nullptr;  // values_received (may be null)
  int rank = 0;
  std::vector<int64_t> order;  // the items rank after rank, each rank's ascending
  std::vector<int64_t> first;  // rank r's items are order[first[r] .. first[r+1])
  const int64_t *own_begin() const { return order.data() + first[rank]; }
  const int64_t *own_end() const { return order.data() + first[rank + 1]; }
  int64_t own_count() const { return first[rank + 1] - first[rank]; }
};

// The items a rank reads of a field whose items are computed by their owners
// (a Share), when it reads fewer than all (the contact points a Newton
// pass on split rows reads). The rank computes its own items and
// receives the others it reads from their owners alone (exchange), instead
// of every item from every rank (gather).
struct Halo {
  std::shared_ptr<const Share> share;  // the items' owners
  std::vector<int64_t> read;           // the items right after an exchange: own and received, ascending
  std::vector<int> from, to;           // the ranks this one receives from, sends to (ascending)
  std::vector<int64_t> recv, recv_first;  // the items received, from[k]'s at recv[recv_first[k] ..)
  std::vector<int64_t> send, send_first;  // own items sent, to[k]'s at send[send_first[k] ..)
};

// readers(i, ranks): appends the ranks that read item i (repeats and its
// owner allowed). Every rank computes the same lists from its replicated
// data, so making a halo sends no message.
std::shared_ptr<const Halo> make_halo(std::shared_ptr<const Share> share, int64_t n_items,
                                      const std::function<void(int64_t, std::vector<int> &)> &readers);
// field: over all items, right on this rank's own items; afterwards right on
// h.read too (the other items are not touched). Collective over the ranks
// that share items (point to point); counts values_received.
void exchange(const Halo &h, double *field);

// owner[i]: the rank that computes item i, for the n items (-1: none; n may
// exceed the items listed), from a share: make_share's argument back
std::vector<int> owners(const Share &s, int64_t n);

// The rows a process computes: its own with a share, else all.
inline RowSet own_rows(const Share *s) { return s ? RowSet{s->own_begin(), s->own_count()} : RowSet{}; }

// owner[i]: the rank that computes item i. Null when there is one rank.
std::shared_ptr<const Share> make_share(CommunicatorPtr comm, const std::vector<int> &owner,
                                        Counters *counters = nullptr);


// fields: arrays over all items, filled on this rank's own items; afterwards
// filled on every item. sums (n_sums of them): this rank's partial sums in,
// the totals out (rank 0's + rank 1's + ...), except the last n_max of
// them, which are the largest of the ranks' (a rank's NaN gives NaN).
// Collective.
void gather(const Share &s, const std::vector<double *> &fields, double *sums = nullptr, int n_sums = 0,
            int n_max = 0);

// mine: `width` values per own item, item after item (ascending); on `root`,
// all (width values per item, item-major) afterwards holds every item's,
// each from its owner. Not counted in values_received: it serves a caller's
// read, not a step. Collective.
void gather_items(const Share &s, int root, int width, const double *mine, double *all);

}  // namespace nd
