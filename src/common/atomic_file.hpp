// Files written safely (VTU, PVD, checkpoints) and a bounded read.
#pragma once
#include <signal.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace nd {

// Writing a file never replaces anything but a regular file:
//  - a symbolic link is followed (its target is written, the link stays);
//    a character device or FIFO is found through links with stat(), for
//    /dev/stdout -> /proc/self/fd/1 -> "pipe:[...]";
//  - a missing file or a regular file with one link is replaced atomically:
//    the text goes to an unnamed temporary file in the target's directory
//    (O_TMPFILE; where the file system cannot, a file ".nd.XXXXXXXX.tmp"),
//    which is flushed, synced and linked or renamed over the target only by
//    commit(). A failure (a full disk, an exception) leaves a previous file
//    untouched, and a killed writer leaves no temporary behind (O_TMPFILE);
//  - a regular file with several hard links is rewritten in place (from its
//    start, then cut to the new length), so its names keep sharing one file;
//  - a character device or a FIFO is written in place, without creating or
//    truncating anything; a FIFO that no process reads is refused at once;
//  - a directory, a socket, a block device: refused.
// Errors throw ND_ERR_IO naming the path.
class AtomicFile {
 public:
  explicit AtomicFile(const char *path);
  ~AtomicFile();  // not committed: an error on the way
  AtomicFile(const AtomicFile &) = delete;
  AtomicFile &operator=(const AtomicFile &) = delete;
  FILE *get() const { return f_; }
  void commit();

 private:
  enum class Mode { replace, in_place, stream };
  void open_temporary();
  void open_in_place(Mode mode);
  void commit_replace();
  std::string path_;    // as given (for messages)
  std::string target_;  // the file written: symbolic links resolved
  std::string dir_;     // its directory
  std::string tmp_;     // the named temporary, if one exists on disk
  Mode mode_ = Mode::replace;
  bool exists_ = false;  // target_ exists (replace: its mode is kept)
  struct stat st_ {};
  int fd_ = -1;           // f_'s descriptor
  bool unnamed_ = false;  // the temporary is an O_TMPFILE
  FILE *f_ = nullptr;
  bool committed_ = false;
  bool sigpipe_blocked_ = false, sigpipe_was_pending_ = false;
  sigset_t old_mask_;
};

void write_file_atomically(const char *path, const std::vector<unsigned char> &bytes);

// The first min(size, limit) bytes of `path`, its size in `size`: a file
// larger than a caller expects is not read whole. A regular file, or a
// character device or FIFO read to its end (at most limit + 1 bytes; `size`
// is what was read); a FIFO no process writes to reads as empty.
// Missing, unreadable, a directory or socket: ND_ERR_IO.
std::vector<unsigned char> read_file_prefix(const char *path, uint64_t limit, uint64_t &size);

}  // namespace nd
