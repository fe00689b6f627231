#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "common/error.hpp"
#include "nitschedyn.h"

namespace nd {
namespace {

// mkstemp makes the file 0600: give it the mode of the file it replaces, or
// the one a plain fopen would (0666 & ~umask; the umask read without
// umask(), which would change it for every thread for a moment).
mode_t file_mode(const std::string &path) {
  struct stat st;
  if (stat(path.c_str(), &st) == 0) return st.st_mode & 07777;
  mode_t mask = 022;
  if (FILE *f = std::fopen("/proc/self/status", "r")) {
    char line[128];
    unsigned m;
    while (std::fgets(line, sizeof line, f))
      if (std::sscanf(line, "Umask: %o", &m) == 1) mask = static_cast<mode_t>(m);
    std::fclose(f);
  }
  return 0666 & ~mask;
}

}  // namespace

AtomicFile::AtomicFile(const char *path) : path_(path), tmp_(path_ + ".tmp.XXXXXX") {
  const int fd = mkstemp(&tmp_[0]);
  if (fd < 0) fail(ND_ERR_IO, "cannot create a temporary file next to '" + path_ + "': " + std::strerror(errno));
  f_ = fdopen(fd, "w");
  if (!f_) {
    const int err = errno;
    close(fd);
    unlink(tmp_.c_str());
    fail(ND_ERR_IO, "cannot open '" + tmp_ + "' for writing: " + std::strerror(err));
  }
  fchmod(fd, file_mode(path_));
}

AtomicFile::~AtomicFile() {
  if (f_) std::fclose(f_);
  if (!committed_) unlink(tmp_.c_str());
}

void AtomicFile::commit() {
  const bool bad = std::fflush(f_) != 0 || std::ferror(f_) != 0 || fsync(fileno(f_)) != 0;
  const int err = errno;
  const bool close_bad = std::fclose(f_) != 0;
  f_ = nullptr;
  if (bad || close_bad) fail(ND_ERR_IO, "error writing '" + path_ + "': " + std::strerror(err));
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0)
    fail(ND_ERR_IO, "cannot rename '" + tmp_ + "' to '" + path_ + "': " + std::strerror(errno));
  committed_ = true;
  // make the rename itself durable (best effort: not every file system can)
  const size_t slash = path_.rfind('/');
  const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path_.substr(0, slash);
  const int dfd = open(dir.c_str(), O_RDONLY | O_DIRECTORY);
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
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(ND_ERR_IO, std::string("cannot open '") + path + "': " + std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { close(fd); }
  } closer{fd};
  struct stat st;
  if (fstat(fd, &st) != 0) fail(ND_ERR_IO, std::string("cannot stat '") + path + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) fail(ND_ERR_IO, std::string("'") + path + "' is not a regular file");
  size = static_cast<uint64_t>(st.st_size);
  std::vector<unsigned char> out(static_cast<size_t>(size < limit ? size : limit));
  size_t got = 0;
  while (got < out.size()) {
    const ssize_t k = read(fd, out.data() + got, out.size() - got);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) fail(ND_ERR_IO, std::string("error reading '") + path + "': " + std::strerror(errno));
    if (k == 0) break;  // shrunk meanwhile: the checks of the content report it
    got += static_cast<size_t>(k);
  }
  out.resize(got);
  return out;
}

}  // namespace nd
