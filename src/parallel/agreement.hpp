// The exception barrier between a rank's own work and the ranks' next
// collective call. Work a rank does alone (its rows or cells of an assembly,
// its part of a PETSc matrix, a caller's arguments) may fail on that rank
// only; were it to leave with its error, the other ranks would wait for it
// in their next collective call for ever. So each rank catches its failure,
// the ranks exchange their statuses (one reduction), and all fail together:
// the failing rank with its own error, the others with the worst status and
// a message that points to it.
#pragma once
#include <exception>
#include <functional>

#include "parallel/communicator.hpp"

namespace nd {

// The ND_ERR_* code of a caught exception (ND_ERR_NOMEM for bad_alloc,
// ND_ERR_INTERNAL for what is not an nd::Error).
int status_of(const std::exception_ptr &e);

// `worst`: the lowest status over the ranks (worst_status) of `failure`'s.
// Rethrows this rank's failure, or fails with `worst` when another rank
// failed ("<what> failed on another rank (...); <consequence>: see that
// rank's error"); returns when every rank succeeded.
void agree_on_outcome(int worst, const std::exception_ptr &failure, const char *what, const char *consequence);

// Runs `local` on this rank, then agrees on the outcome (above), the worst
// status from worst_of(this rank's). Collective as worst_of is.
void on_every_rank(const std::function<int(int)> &worst_of, const std::function<void()> &local, const char *what,
                   const char *consequence);
// The same over c's ranks (worst_status). Collective with a communicator;
// just `local` without one.
void on_every_rank(const Communicator *c, const std::function<void()> &local, const char *what,
                   const char *consequence);

}  // namespace nd
