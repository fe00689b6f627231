// The communicator of builds with MPI (ND_WITH_PETSC): what it holds.
#pragma once
#include <mpi.h>

#include <string>

#include "parallel/communicator.hpp"

namespace nd {

struct Communicator {
  explicit Communicator(MPI_Comm own) : comm(own) {}
  ~Communicator();  // frees the duplicate unless MPI is finalized
  Communicator(const Communicator &) = delete;
  Communicator &operator=(const Communicator &) = delete;
  MPI_Comm comm;  // ours (MPI_Comm_dup of the caller's), errors returned as codes (MPI_ERRORS_RETURN)
  // agree_on_call: the exchanges made on it, and where one timed out (empty:
  // none; then the communicator is lost for the problem's collective calls)
  mutable uint64_t calls = 0;
  mutable std::string lost_at;
};

// Checks and duplicates the caller's communicator: ND_ERR_VALUE for
// MPI_COMM_NULL or an intercommunicator, ND_ERR_STATE when MPI is not running.
CommunicatorPtr communicator_from_c(MPI_Comm comm);
// The communicator's MPI_Comm; PETSC_COMM_SELF's MPI_COMM_SELF when null.
MPI_Comm mpi_comm(const Communicator *c);

}  // namespace nd
