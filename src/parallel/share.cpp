#include "parallel/share.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <string>

#include "common/checked.hpp"

namespace nd {

std::shared_ptr<const Share> make_share(CommunicatorPtr comm, const std::vector<int> &owner,
                                        Counters *counters) {
  const int size = communicator_size(comm.get());
  if (size == 1) return nullptr;
  auto s = std::make_shared<Share>();
  s->counters = counters;
  s->rank = communicator_rank(comm.get());
  s->comm = std::move(comm);
  s->first.assign(static_cast<size_t>(size + 1), 0);
  for (int o : owner) ++s->first[static_cast<size_t>(o) + 1];
  for (int r = 0; r < size; ++r) s->first[r + 1] += s->first[r];
  std::vector<int64_t> next(s->first.begin(), s->first.end() - 1);
  s->order.resize(owner.size());
  for (size_t i = 0; i < owner.size(); ++i) s->order[static_cast<size_t>(next[owner[i]]++)] = static_cast<int64_t>(i);
  return s;
}

namespace {
// The MPI counts and displacements (ints) of blocks of `extra` values per rank
// plus `width` per item.
void blocks(const Share &s, int width, int extra, std::vector<int> &counts, std::vector<int> &displs) {
  const int size = static_cast<int>(s.first.size()) - 1;
  const int64_t values = checked_mul(width, static_cast<int64_t>(s.order.size()), "the values gathered over the ranks");
  const int64_t total = checked_add(int64_t{extra} * size, values, "the values gathered over the ranks");
  if (total > INT_MAX)
    fail(ND_ERR_SIZE, "the values gathered over the ranks (" + std::to_string(total) + ") exceed MPI's int count");
  counts.resize(static_cast<size_t>(size)), displs.resize(static_cast<size_t>(size));
  for (int r = 0; r < size; ++r) {
    counts[r] = static_cast<int>(extra + width * (s.first[r + 1] - s.first[r]));
    displs[r] = static_cast<int>(int64_t{extra} * r + width * s.first[r]);
  }
}
}  // namespace

void gather(const Share &s, const std::vector<double *> &fields, double *sums, int n_sums, int n_max) {
  // a rank's block: its partial sums, then its items' values field after field
  const int width = static_cast<int>(fields.size()), size = static_cast<int>(s.first.size()) - 1;
  std::vector<int> counts, displs;
  blocks(s, width, n_sums, counts, displs);
  std::vector<double> mine, all(static_cast<size_t>(displs[size - 1] + counts[size - 1]));
  mine.reserve(static_cast<size_t>(counts[s.rank]));
  for (int k = 0; k < n_sums; ++k) mine.push_back(sums[k]);
  for (double *f : fields)
    for (const int64_t *i = s.own_begin(); i != s.own_end(); ++i) mine.push_back(f[*i]);
  gatherv(s.comm.get(), kEveryRank, mine, all, counts, displs);
  count(s.counters, &Counters::values_received, static_cast<int64_t>(all.size()) - counts[s.rank]);
  const int added = n_sums - n_max;  // the first ones are added, the last n_max the largest taken
  for (int k = 0; k < n_sums; ++k) sums[k] = k < added ? 0.0 : -INFINITY;
  for (int r = 0; r < size; ++r) {
    const double *block = all.data() + displs[r];
    for (int k = 0; k < added; ++k) sums[k] += block[k];
    for (int k = added; k < n_sums; ++k)
      if (std::isnan(block[k]) || block[k] > sums[k]) sums[k] = block[k];  // (a NaN stays)
    if (r == s.rank) continue;  // own items are already in place
    const int64_t m = s.first[r + 1] - s.first[r];
    const int64_t *items = s.order.data() + s.first[r];
    for (int j = 0; j < width; ++j)
      for (int64_t i = 0; i < m; ++i) fields[static_cast<size_t>(j)][items[i]] = block[n_sums + j * m + i];
  }
}

void gather_items(const Share &s, int root, int width, const double *mine, double *all) {
  std::vector<int> counts, displs;
  blocks(s, width, 0, counts, displs);
  const int size = static_cast<int>(counts.size());
  std::vector<double> sent(mine, mine + counts[s.rank]), got;
  if (s.rank == root) got.resize(static_cast<size_t>(displs[size - 1] + counts[size - 1]));
  gatherv(s.comm.get(), root, sent, got, counts, displs);
  if (s.rank != root) return;
  for (int r = 0; r < size; ++r) {
    const int64_t m = s.first[r + 1] - s.first[r];
    const int64_t *items = s.order.data() + s.first[r];
    for (int64_t i = 0; i < m; ++i) std::copy_n(&got[displs[r] + width * i], width, &all[items[i] * width]);
  }
}

std::vector<int> owners(const Share &s, int64_t n) {
  std::vector<int> owner(static_cast<size_t>(n), -1);
  for (int r = 0, size = static_cast<int>(s.first.size()) - 1; r < size; ++r)
    for (int64_t k = s.first[r]; k < s.first[r + 1]; ++k) owner[s.order[k]] = r;
  return owner;
}

std::shared_ptr<const Halo> make_halo(std::shared_ptr<const Share> share, int64_t n_items,
                                      const std::function<void(int64_t, std::vector<int> &)> &readers) {
  const int size = static_cast<int>(share->first.size()) - 1, me = share->rank;
  const std::vector<int> owner = owners(*share, n_items);
  std::vector<std::vector<int64_t>> sends(size), recvs(size);  // by rank, items ascending
  std::vector<int> ranks;
  auto h = std::make_shared<Halo>();
  for (int64_t i = 0; i < n_items; ++i) {
    ranks.clear();
    readers(i, ranks);
    std::sort(ranks.begin(), ranks.end());
    ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
    const int o = owner[i];
    if (o == me) {
      h->read.push_back(i);
      for (int r : ranks)
        if (r != me) sends[r].push_back(i);
    } else if (std::binary_search(ranks.begin(), ranks.end(), me)) {
      h->read.push_back(i);
      recvs[o].push_back(i);
    }
  }
  auto flatten = [&](const std::vector<std::vector<int64_t>> &by_rank, std::vector<int> &peers,
                     std::vector<int64_t> &items, std::vector<int64_t> &first) {
    first.assign(1, 0);
    for (int r = 0; r < size; ++r) {
      if (by_rank[r].empty()) continue;
      peers.push_back(r);
      items.insert(items.end(), by_rank[r].begin(), by_rank[r].end());
      first.push_back(static_cast<int64_t>(items.size()));
    }
  };
  flatten(sends, h->to, h->send, h->send_first);
  flatten(recvs, h->from, h->recv, h->recv_first);
  h->share = std::move(share);
  return h;
}

void exchange(const Halo &h, double *field) {
  std::vector<double> out(h.send.size()), in(h.recv.size());
  for (size_t k = 0; k < h.send.size(); ++k) out[k] = field[h.send[k]];
  exchange(h.share->comm.get(), h.to, h.send_first, out.data(), h.from, h.recv_first, in.data());
  for (size_t k = 0; k < h.recv.size(); ++k) field[h.recv[k]] = in[k];
  count(h.share->counters, &Counters::values_received, static_cast<int64_t>(in.size()));
}

}  // namespace nd
