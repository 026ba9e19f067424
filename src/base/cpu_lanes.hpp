#pragma once
// Whether the code compiled for AVX2 (base/avx2.hpp: the engine's lane kernels, the neighbour
// search's distance filter) may run: the CPU has AVX2 and TUMBLE_PLAIN_KERNELS=1 does not ask for
// the plain loops (the reference; tests and benchmarks compare the two). Decided at run time, so
// that the generic build uses the lanes wherever the CPU has them.
namespace tumble {

bool lanes_available();

}  // namespace tumble
