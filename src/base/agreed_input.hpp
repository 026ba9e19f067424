#pragma once
// The checks of a command's input (arguments, scene file, paths) under mpirun, agreed over the
// ranks. Every rank reads the same files and arguments, so a bad key fails on all of them: each
// printed the same message, once per rank (64 copies under mpirun -n 64). Where a node differs
// (a scene missing on its disk, less memory available for the estimate) one rank fails alone;
// then the others would wait for it in the run's first collective call. Agreed, every rank leaves
// with the same error and rank 0 alone says it, naming the rank that failed when not all did.
// The same for errors of collective work (thrown_together) and of work rank 0 does alone
// (on_rank_0_agreed).
#include <mpi.h>

#include <functional>

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

// Runs `work` on rank 0 of `comm` alone (it must make no MPI call on `comm`), then `meet` on
// every rank (the others at once: a barrier that sleeps while rank 0 works, or nothing), then
// throws on every rank the error `work` threw, with its type (CorruptInputError, InputError,
// RunError, else std::runtime_error), said by rank 0 alone. For work only rank 0 does (a
// campaign's plan, its statistics, the cached β a case's group reads): thrown on rank 0 alone,
// the others waited for ever for it in their next collective call. One rank (MPI_COMM_NULL
// among them): `work`, then `meet`, as they are.
void on_rank_0_agreed(MPI_Comm comm, const std::function<void()>& work,
                      const std::function<void()>& meet = {});

// Undoes the silencing above once the error has been handled and the process goes on (a
// campaign's next case on the same group): left silenced, a later error that each rank says for
// itself (memory, a scheduler failure) would go unsaid on every rank but 0.
void error_said();

}  // namespace tumble
