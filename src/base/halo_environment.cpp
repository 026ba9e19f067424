#include "base/halo_environment.hpp"

#include <cstdlib>

#include "base/error.hpp"

namespace tumble {

namespace {
constexpr const char* kNodeRanks = "TUMBLE_HALO_NODE_RANKS";
}

int halo_node_ranks_from_environment() {
  const char* text = std::getenv(kNodeRanks);
  if (text == nullptr || *text == '\0') return 0;
  char* end = nullptr;
  const long k = std::strtol(text, &end, 10);
  return *end != '\0' || k < 0 || k > kMaxHaloNodeRanks ? -1 : static_cast<int>(k);
}

std::string halo_node_ranks_error() {
  const char* text = std::getenv(kNodeRanks);
  return std::string(kNodeRanks) + " = \"" + (text ? text : "") +
         "\": must be a whole number of ranks per node, 0 (the nodes MPI reports) to " +
         std::to_string(kMaxHaloNodeRanks) + ", the same on every rank";
}

void check_halo_environment() {
  if (halo_node_ranks_from_environment() < 0) throw InputError(halo_node_ranks_error());
}

}  // namespace tumble
