// libFuzzer target: the Gmsh reader on arbitrary bytes. The bytes become a
// memory file (memfd) read through /proc/self/fd, so nothing touches the
// disk. Oracle: no crash, leak, sanitizer report or timeout (libFuzzer and
// the sanitizers), and the C API's contract on every outcome: a known status,
// the handle NULL on failure, a message exactly when the call failed.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "nitschedyn.h"

namespace {
void require(bool ok, const char *what) {
  if (!ok) {
    std::fprintf(stderr, "fuzz_gmsh: contract violated: %s (last error '%s')\n", what, nd_last_error());
    std::abort();
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const int fd = memfd_create("fuzz.msh", 0);
  if (fd < 0) return 0;
  size_t done = 0;
  while (done < size) {
    const ssize_t w = write(fd, data + done, size - done);
    if (w <= 0) break;
    done += static_cast<size_t>(w);
  }
  char path[64];
  std::snprintf(path, sizeof path, "/proc/self/fd/%d", fd);
  nd_mesh m = reinterpret_cast<nd_mesh>(path);  // must be overwritten
  const int status = nd_mesh_read_gmsh(path, &m);
  close(fd);
  require(std::strcmp(nd_strerror(status), "unknown status code") != 0, "a known status");
  if (status == ND_OK) {
    require(m != nullptr && nd_last_error()[0] == '\0', "a mesh and no message on success");
    int dim = 0;
    int64_t nv = 0, nc = 0, nr = 0;
    require(nd_mesh_get_dimension(m, &dim) == ND_OK && dim >= 1 && dim <= 3, "a dimension");
    require(nd_mesh_get_vertex_count(m, &nv) == ND_OK && nv > dim, "vertices");
    require(nd_mesh_get_cell_count(m, &nc) == ND_OK && nc > 0, "cells");
    for (int r = 0; r < 4; ++r) require(nd_mesh_get_region_size(m, r, &nr) == ND_OK && nr >= 0, "a region size");
    require(nd_mesh_destroy(&m) == ND_OK && m == nullptr, "destroy");
  } else {
    require(status < 0 && m == nullptr, "the handle NULL on failure");
    require(std::strncmp(nd_last_error(), "nd_mesh_read_gmsh: ", 19) == 0, "the message names the call");
    // the reader never blames the system for a malformed file
    require(status == ND_ERR_FORMAT || status == ND_ERR_IO || status == ND_ERR_DEGENERATE ||
                status == ND_ERR_INDEX || status == ND_ERR_REGION || status == ND_ERR_VALUE ||
                status == ND_ERR_NONFINITE || status == ND_ERR_SIZE,
            "a status that describes the file");
  }
  return 0;
}
