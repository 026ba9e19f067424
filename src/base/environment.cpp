#include "base/environment.hpp"

#include <cstdlib>
#include <cstring>

#include "base/agreed_input.hpp"
#include "base/comm.hpp"
#include "base/error.hpp"

namespace tumble {

namespace {
constexpr const char* kSwitches[] = {"TUMBLE_PLAIN_KERNELS", "TUMBLE_GENERAL_KERNELS",
                                     "TUMBLE_FULL_HALO", "TUMBLE_REFRESH_MESSAGES"};
constexpr const char* kNodeRanks = "TUMBLE_HALO_NODE_RANKS";

// A switch's value is good when unset, empty, "0" or "1".
bool good_switch(const char* text) {
  return text == nullptr || *text == '\0' || std::strcmp(text, "0") == 0 ||
         std::strcmp(text, "1") == 0;
}
}  // namespace

bool env_switch_on(const char* name) {
  const char* text = std::getenv(name);
  return text != nullptr && std::strcmp(text, "1") == 0;
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

namespace {
// The message of this rank's first bad value, "" if none.
std::string environment_error() {
  for (const char* name : kSwitches)
    if (const char* text = std::getenv(name); !good_switch(text))
      return std::string(name) + " = \"" + text + "\": a switch, 1 (on) or 0, empty or unset (off)";
  return halo_node_ranks_from_environment() < 0 ? halo_node_ranks_error() : std::string();
}
}  // namespace

void check_environment(MPI_Comm comm) {
  // Agreed over the ranks: a bad value on one rank only (a wrapper that does not pass the
  // environment) is refused on every rank, said once by rank 0.
  int mpi = 0;
  MPI_Initialized(&mpi);  // (`run --check` starts no MPI)
  const bool ranks = mpi != 0 && size_of(comm) > 1;
  agreed_input(comm, [comm, ranks] {
    if (const std::string error = environment_error(); !error.empty())
      throw InputError(ranks ? error + " (in the environment of rank " +
                                   std::to_string(rank_in(comm)) + ")"
                             : error);
  });
}

}  // namespace tumble
