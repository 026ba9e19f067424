#pragma once
// The halo's one numeric setting from the environment, read in one place: the domain uses it, and
// the commands check it at start so that a bad value is refused before any work (not after a bed
// of many minutes is made, when the first domain is built).
#include <string>

namespace tumble {

// TUMBLE_HALO_NODE_RANKS=k: the halo takes each k consecutive ranks of a node for a node of their
// own (tests of many nodes on one machine; docs/parallel.md).
constexpr int kMaxHaloNodeRanks = 1 << 20;

// k; 0 when unset or empty (the nodes MPI reports); -1 when not a whole number
// 0..kMaxHaloNodeRanks.
int halo_node_ranks_from_environment();

// The message of a bad value: the variable, what it holds and the allowed range.
std::string halo_node_ranks_error();

// Throws InputError(halo_node_ranks_error()) when the variable holds a bad value.
void check_halo_environment();

}  // namespace tumble
