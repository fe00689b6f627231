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

void gather(const Share &s, const std::vector<double *> &fields, double *sums, int n_sums) {
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
  for (int k = 0; k < n_sums; ++k) sums[k] = 0;
  for (int r = 0; r < size; ++r) {
    const double *block = all.data() + displs[r];
    for (int k = 0; k < n_sums; ++k) sums[k] += block[k];
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

double norm2_rows(const Share *rows, int64_t n, const double *x) {
  if (!rows) return norm2(n, x);
  double sum = 0;
  for (const int64_t *i = rows->own_begin(); i != rows->own_end(); ++i) sum += x[*i] * x[*i];
  gather(*rows, {}, &sum, 1);
  return std::sqrt(sum);
}

}  // namespace nd
