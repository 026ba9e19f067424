#pragma once
// Tumble's environment variables, read in one place. They serve tests, benchmarks and a user
// chasing a fault (docs/guarantees.md, "Environment variables"); scenes and the command line are
// the interface. `tumble run` and `tumble campaign` check them when they start, so a bad value is
// refused before any work (the engine and the domain read them only after a bed is made), on any
// number of ranks.
#include <mpi.h>

#include <string>

namespace tumble {

// On/off switches: "1" on; unset, empty or "0" off; anything else refused by check_environment.
//   TUMBLE_PLAIN_KERNELS     the plain pair and integrator loops instead of the AVX2 lanes
//   TUMBLE_GENERAL_KERNELS   the pair loop of many species even for one
//   TUMBLE_FULL_HALO         one halo as wide as the largest particles (no thin halo for the small)
//   TUMBLE_REFRESH_MESSAGES  the ghost refresh by messages, not through the node's shared window
bool env_switch_on(const char* name);

// TUMBLE_HALO_NODE_RANKS=k: the halo takes each k consecutive ranks of a node for a node of their
// own (tests of many nodes on one machine; docs/parallel.md).
constexpr int kMaxHaloNodeRanks = 1 << 20;

// k; 0 when unset or empty (the nodes MPI reports); -1 when not a whole number
// 0..kMaxHaloNodeRanks.
int halo_node_ranks_from_environment();

// The message of a bad value: the variable, what it holds and the allowed range.
std::string halo_node_ranks_error();

// Throws InputError naming the first variable above that holds a bad value, and its range. On
// a communicator of several ranks it is collective: every rank throws the message of the lowest
// rank with a bad value (an environment can differ between ranks; a rank that refused alone
// would leave the others waiting in the run's first collective).
void check_environment(MPI_Comm comm = MPI_COMM_NULL);

}  // namespace tumble
