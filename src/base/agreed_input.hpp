#pragma once
// The checks of a command's input (arguments, scene file, paths) under mpirun, agreed over the
// ranks. Every rank reads the same files and arguments, so a bad key fails on all of them: each
// printed the same message, once per rank (64 copies under mpirun -n 64). Where a node differs
// (a scene missing on its disk, less memory available for the estimate) one rank fails alone;
// then the others would wait for it in the run's first collective call. Agreed, every rank leaves
// with the same error and rank 0 alone says it, naming the rank that failed when not all did.
#include <mpi.h>

#include <functional>
#include <string>

namespace tumble {

// Runs `check` on every rank of `comm` (it must make no MPI call) and, if it threw on any rank,
// throws on every rank the error of the lowest one that failed (InputError, CorruptInputError,
// or std::runtime_error for anything else), after silencing std::cerr on ranks other than 0.
// Without MPI (`run --check`) or on one rank, `check` runs as it is.
void agreed_input(MPI_Comm comm, const std::function<void()>& check);

// Runs `work`, collective over `comm`, whose errors every rank throws together by its own
// contract (io::read_checkpoint and the checks after it agree before they throw): if it throws
// InputError, CorruptInputError or RunError, std::cerr is silenced on ranks other than 0 and the
// error goes on, so rank 0 alone says it; any other error each rank that has it says.
void thrown_together(MPI_Comm comm, const std::function<void()>& work);

// For an error every rank of `comm` is about to throw alike (the same input, or rank 0's error
// broadcast): silences std::cerr on ranks other than 0, so that rank 0 alone says it. An error a
// rank has alone must not come this way: it would go unsaid.
void said_by_rank_0(MPI_Comm comm);

// Rank 0's `text` on every rank of `comm` (collective; the others' `text` is ignored). Where rank
// 0 alone did some work while the others waited (a campaign's plan, its statistics), its error
// reaches them this way, so that no rank is left waiting for rank 0 in a later collective call.
std::string from_rank_0(MPI_Comm comm, std::string text);

}  // namespace tumble
