#include "base/cpu_lanes.hpp"

#include <cstdlib>
#include <string>

namespace tumble {

bool lanes_available() {
  const char* plain = std::getenv("TUMBLE_PLAIN_KERNELS");
  if (plain != nullptr && std::string(plain) == "1") return false;
  __builtin_cpu_init();  // this file is compiled for the generic target
  return __builtin_cpu_supports("avx2");
}

}  // namespace tumble
