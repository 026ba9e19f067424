#include "base/cpu_lanes.hpp"

#include "base/environment.hpp"

namespace tumble {

bool lanes_available() {
  if (env_switch_on("TUMBLE_PLAIN_KERNELS")) return false;
  __builtin_cpu_init();  // this file is compiled for the generic target
  return __builtin_cpu_supports("avx2");
}

}  // namespace tumble
