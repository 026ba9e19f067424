#include "base/environment.hpp"

#include <cstdlib>
#include <cstring>

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

void check_environment() {
  for (const char* name : kSwitches)
    if (const char* text = std::getenv(name); !good_switch(text))
      throw InputError(std::string(name) + " = \"" + text +
                       "\": a switch, 1 (on) or 0, empty or unset (off)");
  if (halo_node_ranks_from_environment() < 0) throw InputError(halo_node_ranks_error());
}

}  // namespace tumble
