#pragma once
// A request to stop a run early and cleanly, made by a signal: SIGUSR1 (what a batch system sends
// ahead of a job's time limit, e.g. Slurm's `--signal=USR1@300`, and what mpirun passes on to
// every rank), SIGTERM or SIGINT (Ctrl-C). The handler only records the signal; the run loop
// notices it at its next neighbour rebuild, writes a checkpoint there, and ends with StopRequest
// (run/checkpoint_observer.hpp), so that `tumble run --resume` or the campaign's rerun goes on
// from it bitwise as if never stopped. A second SIGTERM or SIGINT ends the process at once, with
// the signal's default action (a user who presses Ctrl-C twice means it).
//
// One process-wide flag: every case that a campaign's rank runs stops at the same request.
#include <mpi.h>

#include <stdexcept>
#include <string>

namespace tumble {

// The run stopped on request after writing its checkpoint; neither a failure nor a finished run.
struct StopRequest : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Installs the handlers (once; later calls do nothing).
void install_stop_handlers();
// The signal that asked this process to stop, 0 if none.
int stop_signal();
// The signal any rank of `comm` has seen (the largest number), 0 if none. Collective over comm
// (MPI_COMM_NULL: this process alone).
int agreed_stop_signal(MPI_Comm comm);
// Ends a phase that keeps nothing worth a checkpoint (settling a bed, which takes minutes; the
// repose angle's turn keeps its own: run/repose_measure.hpp) at once with StopRequest naming
// `what` if any rank has seen a stop signal; collective.
void stop_if_requested(MPI_Comm comm, const std::string& what);
// "SIGUSR1", "SIGTERM", "SIGINT", or "signal N".
std::string signal_name(int signal);

}  // namespace tumble
