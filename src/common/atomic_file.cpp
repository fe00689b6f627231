#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

std::string quoted(const std::string &path) { return "'" + path + "'"; }

// the directory part of a path ("." for a bare name, "/" for "/name")
std::string dir_of(const std::string &path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
}

// The file a write to `path` reaches: symbolic links followed, at most 40 (as
// the kernel does); a link's relative target is relative to its directory.
// `exists` false: nothing is there (a new file, possibly a dangling link's
// target).
std::string resolve(const std::string &path, bool &exists, struct stat &st) {
  std::string cur = path;
  for (int hops = 0;; ++hops) {
    if (lstat(cur.c_str(), &st) != 0) {
      if (errno != ENOENT) fail(ND_ERR_IO, "cannot stat " + quoted(cur) + ": " + std::strerror(errno));
      exists = false;
      return cur;
    }
    if (!S_ISLNK(st.st_mode)) {
      exists = true;
      return cur;
    }
    if (hops == 40) fail(ND_ERR_IO, "too many levels of symbolic links in " + quoted(path));
    std::vector<char> link(static_cast<size_t>(st.st_size > 0 ? st.st_size : PATH_MAX) + 1);
    const ssize_t k = readlink(cur.c_str(), link.data(), link.size());
    if (k < 0) fail(ND_ERR_IO, "cannot read the symbolic link " + quoted(cur) + ": " + std::strerror(errno));
    if (static_cast<size_t>(k) == link.size() || k == 0)  // changed meanwhile
      fail(ND_ERR_IO, "the symbolic link " + quoted(cur) + " changed while it was read");
    const std::string to(link.data(), static_cast<size_t>(k));
    cur = to[0] == '/' ? to : dir_of(cur) + "/" + to;
  }
}

// mkstemp-like files are 0600: a new file gets the mode a plain fopen would
// give it (0666 & ~umask; the umask read without umask(), which would change
// it for every thread for a moment).
mode_t new_file_mode() {
  mode_t mask = 022;
  if (FILE *f = std::fopen("/proc/self/status", "re")) {
    char line[128];
    unsigned m;
    while (std::fgets(line, sizeof line, f))
      if (std::sscanf(line, "Umask: %o", &m) == 1) mask = static_cast<mode_t>(m);
    std::fclose(f);
  }
  return 0666 & ~mask;
}

// the file that replaces another gets its mode, and its owner and group as
// far as this process may give them (root: both; others: a group of theirs;
// best effort, silently); the mode after, since a chown clears set-id bits
void keep_owner_and_mode(int fd, const struct stat &st) {
  if (fchown(fd, st.st_uid, st.st_gid) != 0 && fchown(fd, static_cast<uid_t>(-1), st.st_gid) != 0) {
  }
  fchmod(fd, st.st_mode & 07777);
}

// "<dir>/.nd.XXXXXXXX.tmp": a short name whatever the length of the target's
// (which may be up to NAME_MAX), recognisable as this library's
std::string temporary_name(const std::string &dir) {
  static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  static std::atomic<uint64_t> counter{0};
  unsigned char r[8];
  if (getrandom(r, sizeof r, GRND_NONBLOCK) != static_cast<ssize_t>(sizeof r)) {
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    uint64_t x = static_cast<uint64_t>(ts.tv_nsec) ^ (static_cast<uint64_t>(ts.tv_sec) << 30) ^
                 (static_cast<uint64_t>(getpid()) << 20) ^ (++counter * 0x9E3779B97F4A7C15ull);
    for (unsigned char &c : r) {
      x ^= x >> 29, x *= 0xBF58476D1CE4E5B9ull, x ^= x >> 32;
      c = static_cast<unsigned char>(x);
    }
  }
  std::string name = (dir == "/" ? "" : dir) + "/.nd.";
  for (unsigned char c : r) name += digits[c % 62];
  return name + ".tmp";
}

}  // namespace

AtomicFile::AtomicFile(const char *path) : path_(path) {
  // A character device or FIFO, also behind links such as /dev/stdout ->
  // /proc/self/fd/1 -> "pipe:[...]" whose text is no path: opened as named
  if (stat(path, &st_) == 0 && (S_ISCHR(st_.st_mode) || S_ISFIFO(st_.st_mode))) {
    exists_ = true;
    target_ = path_;
    open_in_place(Mode::stream);
  } else {
    target_ = resolve(path_, exists_, st_);
    dir_ = dir_of(target_);
    if (target_.empty() || target_.back() == '/')
      fail(ND_ERR_IO, "cannot write " + quoted(path_) + ": not a file name");
    if (!exists_ || (S_ISREG(st_.st_mode) && st_.st_nlink <= 1)) {
      mode_ = Mode::replace;
      open_temporary();
    } else if (S_ISREG(st_.st_mode) || S_ISCHR(st_.st_mode) || S_ISFIFO(st_.st_mode)) {
      open_in_place(S_ISREG(st_.st_mode) ? Mode::in_place : Mode::stream);
    } else {
      const char *what = S_ISDIR(st_.st_mode)    ? "a directory"
                         : S_ISSOCK(st_.st_mode) ? "a socket"
                         : S_ISBLK(st_.st_mode)  ? "a block device"
                                                 : "not a regular file";
      fail(ND_ERR_IO, "cannot write " + quoted(path_) + ": it is " + what +
                          " (a file is written over a regular file, a character device or a FIFO only)");
    }
  }
  f_ = fdopen(fd_, "w");
  if (!f_) {
    const int err = errno;
    close(fd_);
    fd_ = -1;
    if (!tmp_.empty()) unlink(tmp_.c_str());
    tmp_.clear();
    fail(ND_ERR_IO, "cannot open " + quoted(path_) + " for writing: " + std::strerror(err));
  }
  if (mode_ == Mode::stream) {
    // (last: a constructor that throws has no destructor to restore the mask)
    // A reader that goes away makes write() fail with EPIPE, and not kill the
    // process with SIGPIPE: blocked in this thread while it writes (a SIGPIPE
    // it raises is taken back in the destructor)
    sigset_t only_pipe, pending;
    sigemptyset(&only_pipe);
    sigaddset(&only_pipe, SIGPIPE);
    sigemptyset(&pending);
    sigpending(&pending);
    sigpipe_was_pending_ = sigismember(&pending, SIGPIPE) == 1;
    sigpipe_blocked_ = pthread_sigmask(SIG_BLOCK, &only_pipe, &old_mask_) == 0;
  }
}

// In place: never created, never truncated here (no O_CREAT, O_TRUNC); a
// regular file is opened without following a link (target_ is resolved).
// O_NONBLOCK: a FIFO that no process reads is an error at once instead of a
// wait (ENXIO); cleared for writing.
void AtomicFile::open_in_place(Mode mode) {
  mode_ = mode;
  const bool stream = mode == Mode::stream;
  fd_ = open(target_.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC | (stream ? O_NONBLOCK : O_NOFOLLOW));
  if (fd_ < 0) {
    const int err = errno;
    if (err == ENXIO && S_ISFIFO(st_.st_mode))
      fail(ND_ERR_IO, "cannot write " + quoted(path_) + ": it is a FIFO that no process reads");
    fail(ND_ERR_IO, "cannot open " + quoted(path_) + " for writing: " + std::strerror(err));
  }
  struct stat now;
  int err = 0;
  if (fstat(fd_, &now) != 0 || now.st_dev != st_.st_dev || now.st_ino != st_.st_ino)
    err = -1;
  else if (stream) {
    const int flags = fcntl(fd_, F_GETFL);
    if (flags < 0 || fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK) != 0) err = errno;
  }
  if (err != 0) {
    close(fd_);
    fd_ = -1;
    fail(ND_ERR_IO, "cannot write " + quoted(path_) + ": " +
                        (err < 0 ? std::string("it changed while it was opened") : std::strerror(err)));
  }
}

// An unnamed temporary file in the target's directory where the file system
// can (a killed writer leaves nothing), else a named one
void AtomicFile::open_temporary() {
#ifdef O_TMPFILE
  fd_ = open(dir_.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);  // 0666 & ~umask
  if (fd_ >= 0) {
    // linked later through /proc/self/fd (linkat with AT_EMPTY_PATH needs a
    // capability): without /proc, a named temporary instead
    struct stat proc;
    if (stat(("/proc/self/fd/" + std::to_string(fd_)).c_str(), &proc) == 0) {
      unnamed_ = true;
      if (exists_) keep_owner_and_mode(fd_, st_);
      return;
    }
    close(fd_);
    fd_ = -1;
  }
#endif
  for (int attempt = 0; fd_ < 0; ++attempt) {
    tmp_ = temporary_name(dir_);
    fd_ = open(tmp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0600);
    if (fd_ < 0 && (errno != EEXIST || attempt == 100)) {
      const int err = errno;
      tmp_.clear();
      fail(ND_ERR_IO, "cannot create a temporary file in '" + dir_ + "' to write " + quoted(path_) + ": " +
                          std::strerror(err));
    }
  }
  if (exists_)
    keep_owner_and_mode(fd_, st_);
  else
    fchmod(fd_, new_file_mode());
}

AtomicFile::~AtomicFile() {
  if (f_) std::fclose(f_);
  if (!committed_ && !tmp_.empty()) unlink(tmp_.c_str());
  if (sigpipe_blocked_) {
    sigset_t pending;
    sigemptyset(&pending);
    if (!sigpipe_was_pending_ && sigpending(&pending) == 0 && sigismember(&pending, SIGPIPE) == 1) {
      sigset_t only_pipe;
      sigemptyset(&only_pipe);
      sigaddset(&only_pipe, SIGPIPE);
      const struct timespec zero = {0, 0};
      while (sigtimedwait(&only_pipe, nullptr, &zero) < 0 && errno == EINTR) {
      }
    }
    pthread_sigmask(SIG_SETMASK, &old_mask_, nullptr);
  }
}

void AtomicFile::commit() {
  bool bad = std::fflush(f_) != 0 || std::ferror(f_) != 0;
  int err = errno;
  if (!bad && mode_ == Mode::in_place) {  // the rest of a longer old text goes
    const off_t end = ftello(f_);
    bad = end < 0 || ftruncate(fd_, end) != 0;
    err = errno;
  }
  if (!bad && mode_ != Mode::stream) {  // (a device or FIFO may not sync: EINVAL)
    bad = fsync(fd_) != 0;
    err = errno;
  }
  if (bad) fail(ND_ERR_IO, "error writing " + quoted(path_) + ": " + std::strerror(err));
  if (mode_ == Mode::replace) {
    commit_replace();
    return;
  }
  const bool close_bad = std::fclose(f_) != 0;
  err = errno;
  f_ = nullptr;
  if (close_bad) fail(ND_ERR_IO, "error writing " + quoted(path_) + ": " + std::strerror(err));
  committed_ = true;
}

void AtomicFile::commit_replace() {
  if (unnamed_) {
    const std::string proc = "/proc/self/fd/" + std::to_string(fd_);
    // a new file: linked at its name at once (EEXIST: someone made it meanwhile)
    bool linked = !exists_ && linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, target_.c_str(), AT_SYMLINK_FOLLOW) == 0;
    if (!linked && (exists_ || errno == EEXIST)) {
      // over an existing file: a name to rename from (the window between
      // the two calls is the only one in which a kill leaves a temporary)
      for (int attempt = 0; tmp_.empty(); ++attempt) {
        tmp_ = temporary_name(dir_);
        if (linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, tmp_.c_str(), AT_SYMLINK_FOLLOW) != 0) {
          const int err = errno;
          tmp_.clear();
          if (err != EEXIST || attempt == 100)
            fail(ND_ERR_IO, "cannot link a temporary file in '" + dir_ + "' to write " + quoted(path_) + ": " +
                                std::strerror(err));
        }
      }
    } else if (!linked) {
      fail(ND_ERR_IO, "cannot create " + quoted(path_) + ": " + std::strerror(errno));
    }
  }
  if (!tmp_.empty() && std::rename(tmp_.c_str(), target_.c_str()) != 0)
    fail(ND_ERR_IO, "cannot rename a temporary file to " + quoted(path_) + ": " + std::strerror(errno));
  tmp_.clear();
  committed_ = true;
  std::fclose(f_);  // (synced above: nothing left to fail)
  f_ = nullptr;
  // make the rename or link itself durable (best effort: not every file system can)
  const int dfd = open(dir_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    fsync(dfd);
    close(dfd);
  }
}

void write_file_atomically(const char *path, const std::vector<unsigned char> &bytes) {
  AtomicFile f(path);
  if (std::fwrite(bytes.data(), 1, bytes.size(), f.get()) != bytes.size())
    fail(ND_ERR_IO, std::string("error writing '") + path + "': " + std::strerror(errno));
  f.commit();
}

std::vector<unsigned char> read_file_prefix(const char *path, uint64_t limit, uint64_t &size) {
  // O_NONBLOCK: opening a FIFO that no process writes does not wait (it then
  // reads as empty); cleared before reading
  const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) fail(ND_ERR_IO, std::string("cannot open '") + path + "': " + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { close(fd); }
  } closer{fd};
  struct stat st;
  if (fstat(fd, &st) != 0) fail(ND_ERR_IO, std::string("cannot stat '") + path + "': " + std::strerror(errno));
  const bool stream = S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode);
  if (!S_ISREG(st.st_mode) && !stream)
    fail(ND_ERR_IO, std::string("'") + path + "' is not a regular file, character device or FIFO");
  const int flags = fcntl(fd, F_GETFL);
  if (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0)
    fail(ND_ERR_IO, std::string("cannot read '") + path + "': " + std::strerror(errno));
  // a stream's size is what it holds: read up to one byte more than wanted
  const uint64_t want = stream ? limit + 1 : static_cast<uint64_t>(st.st_size);
  std::vector<unsigned char> out(static_cast<size_t>(want < limit ? want : stream ? limit + 1 : limit));
  size_t got = 0;
  while (got < out.size()) {
    const ssize_t k = read(fd, out.data() + got, out.size() - got);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) fail(ND_ERR_IO, std::string("error reading '") + path + "': " + std::strerror(errno));
    if (k == 0) break;  // shrunk meanwhile: the checks of the content report it
    got += static_cast<size_t>(k);
  }
  size = stream ? got : static_cast<uint64_t>(st.st_size);
  out.resize(got < limit ? got : static_cast<size_t>(limit));
  return out;
}

}  // namespace nd
