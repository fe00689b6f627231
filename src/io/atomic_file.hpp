// Files written atomically (VTU, PVD, checkpoints) and a bounded read.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace nd {

// The text goes to a temporary file in the same directory, which is flushed,
// synced and renamed over `path` only by commit(). A failure (a full disk, an
// exception) removes the temporary file and leaves a previous file at `path`
// untouched. Errors throw ND_ERR_IO.
class AtomicFile {
 public:
  explicit AtomicFile(const char *path);
  ~AtomicFile();  // not committed: an error on the way
  AtomicFile(const AtomicFile &) = delete;
  AtomicFile &operator=(const AtomicFile &) = delete;
  FILE *get() const { return f_; }
  void commit();

 private:
  std::string path_, tmp_;
  FILE *f_ = nullptr;
  bool committed_ = false;
};

void write_file_atomically(const char *path, const std::vector<unsigned char> &bytes);

// The first min(size, limit) bytes of the regular file `path`, its size in
// `size`: a file larger than a caller expects is not read whole.
// Missing, unreadable or not a regular file: ND_ERR_IO.
std::vector<unsigned char> read_file_prefix(const char *path, uint64_t limit, uint64_t &size);

}  // namespace nd
