#include "engine/contact_lanes.hpp"

#include <cstdlib>
#include <string>

namespace tumble::engine {

LaneKernel yu2022_lane_kernel(bool friction, bool periodic, bool one_species, const char*& name) {
  name = "plain";
  const char* plain = std::getenv("TUMBLE_PLAIN_KERNELS");
  if (plain != nullptr && std::string(plain) == "1") return nullptr;
  // Chosen at run time, so that the generic build (no -march) uses the lanes wherever the CPU has
  // them; this file itself is compiled for the generic target.
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2")) return nullptr;
  name = "avx2 lanes";
  return yu2022_lanes_avx2(friction, periodic, one_species);
}

}  // namespace tumble::engine
