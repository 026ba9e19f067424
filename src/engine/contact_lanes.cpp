#include "engine/contact_lanes.hpp"

#include <cstdlib>
#include <string>

namespace tumble::engine {

bool lanes_available() {
  const char* plain = std::getenv("TUMBLE_PLAIN_KERNELS");
  if (plain != nullptr && std::string(plain) == "1") return false;
  // Decided at run time, so that the generic build (no -march) uses the lanes wherever the CPU
  // has them; this file itself is compiled for the generic target.
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

}  // namespace tumble::engine
