#pragma once
// The optimised pair loop: kernels that compute several contacts at once (one per SIMD lane),
// and the choice of the one this CPU can run.
//
// A lane kernel works in three passes over the Verlet list: a scan that keeps only the touching
// pairs (four pairs at a time, no branch per pair: the touching state of a pair is close to random
// along the list, so a branch on it is mispredicted often) and clears the springs of the pairs that
// do not touch; the forces and torques of the touching contacts, four at a time; and their sums
// into the particles in exactly the order of the plain loop (Simulation::pair_forces). Each lane
// does the operations of the plain kernel in the same order, without fused multiply-adds, so the
// two paths agree bitwise on a build without -march=native (tests/test_lane_kernels.cpp).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble::engine {

// Lanes per block: the scratch arrays hold this many entries beyond the list's pairs (the last
// block of contacts is padded with copies of the last contact, whose results are not used).
inline constexpr std::size_t kLaneBlock = 4;

// Scratch of one step, reused from step to step (sized by the caller: the lane kernels use no
// standard-library code).
struct TouchingContacts {
  std::vector<std::uint32_t> i, j, k;  // touching pairs in list order: row, partner, list index
  std::vector<std::uint32_t> miss;     // list indices of the pairs that do not touch
};

// What a lane kernel reads and writes. Vec3 arrays are passed as doubles (x, y, z per particle).
struct LaneInput {
  std::size_t pairs = 0;  // the Verlet list: pairs (row[k], nbr[k]), k < pairs
  const std::uint32_t* row = nullptr;
  const std::uint32_t* nbr = nullptr;
  const double* x = nullptr;
  const double* v = nullptr;
  const double* w = nullptr;
  const double* radius = nullptr;
  const std::int32_t* species = nullptr;
  double* f = nullptr;  // forces and torques, added to
  double* t = nullptr;
  double* history = nullptr;  // 3 doubles per list pair (the tangential spring)
  // The law's coefficients per type 2 species(i) + species(j): each an array of 4 (which
  // coefficient is which: the law's lane file).
  const double* coefficient[8] = {};
  std::int32_t one_type = 0;  // one-species kernels: the type of every contact
  double dt = 0;              // time step
  double period = 0;          // axial period (periodic scenes), else unused
  // Scratch of pairs + kLaneBlock entries each (TouchingContacts): the touching pairs in list
  // order (row, partner, list index) and the list indices of the others.
  std::uint32_t* contact_i = nullptr;
  std::uint32_t* contact_j = nullptr;
  std::uint32_t* contact_k = nullptr;
  std::uint32_t* miss = nullptr;
};

using LaneKernel = void (*)(const LaneInput&);

// The kernels (engine/*_lanes_avx2.cpp, compiled for AVX2): call only if lanes_available()
// (base/cpu_lanes.hpp).
LaneKernel yu2022_lanes_avx2(bool friction, bool periodic, bool one_species);
LaneKernel rapaport2007_lanes_avx2(bool friction, bool periodic, bool one_species);

}  // namespace tumble::engine
