#pragma once
// Rank and size of a communicator that may be MPI_COMM_NULL (a serial run: rank 0 of 1), so that
// code shared by serial and decomposed runs asks one question either way.
#include <mpi.h>

namespace tumble {

inline int rank_in(MPI_Comm comm) {
  int r = 0;
  if (comm != MPI_COMM_NULL) MPI_Comm_rank(comm, &r);
  return r;
}

inline int size_of(MPI_Comm comm) {
  int n = 1;
  if (comm != MPI_COMM_NULL) MPI_Comm_size(comm, &n);
  return n;
}

}  // namespace tumble
