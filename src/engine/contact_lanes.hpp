#pragma once
// The touching contacts of one step, laid out for kernels that compute several contacts at once
// (one per SIMD lane), and the lane kernels the CPU can run.
//
// The engine's optimised pair path (engine/simulation.cpp, pair_forces_lanes) works in three
// passes: a scan of the Verlet list that keeps only the touching pairs (no branch per pair: the
// touching state of a pair is close to random along the list, so a branch on it is mispredicted
// often), a lane kernel that computes the force and torques of every touching contact into the
// arrays below, and a pass that adds them to the particles in exactly the order of the plain loop.
// Each lane does the operations of the plain kernel in the same order, without fused
// multiply-adds, so the two paths agree bitwise on a build without -march=native
// (tests/test_lane_kernels.cpp).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble::engine {

// Lanes per block: every array of TouchingContacts holds a multiple of this many entries (the last
// block padded with copies of the last contact, whose results are not used).
inline constexpr std::size_t kLaneBlock = 4;

// One step's touching contacts in list order (row by row), structure of arrays.
struct TouchingContacts {
  std::vector<std::uint32_t> i, j, k;    // row particle, partner, index in the Verlet list
  std::vector<std::int32_t> type;        // coefficient set: 2 species(i) + species(j)
  std::vector<std::uint32_t> row_start;  // contacts of row r: [row_start[r], row_start[r + 1])
  std::size_t count = 0;                 // real contacts (the arrays hold padded())
  std::size_t padded() const { return (count + kLaneBlock - 1) / kLaneBlock * kLaneBlock; }
  // Results per contact, nine arrays of padded() doubles: force on i (x, y, z), torque on i
  // (x, y, z), torque on j (x, y, z); the force on j is minus the force on i.
  std::vector<double> out;
};

// What a lane kernel reads and writes. Vec3 arrays are passed as doubles (x, y, z per particle).
struct LaneInput {
  TouchingContacts* contacts = nullptr;  // read; its `out` is written
  const double* x = nullptr;
  const double* v = nullptr;
  const double* w = nullptr;
  const double* radius = nullptr;
  double* history = nullptr;  // 3 doubles per Verlet-list pair (the tangential spring)
  // Coefficients per type (2 species(i) + species(j)): the law's Pair, as arrays of 4.
  const double* kn = nullptr;
  const double* dn = nullptr;
  const double* kt = nullptr;
  const double* dt_tangential = nullptr;
  const double* mu = nullptr;
  double dt = 0;      // time step
  double period = 0;  // axial period (periodic scenes), else unused
};

using LaneKernel = void (*)(const LaneInput&);

// The Yu 2022 law's lane kernel for these options, or nullptr when this CPU cannot run one (no
// AVX2) or TUMBLE_PLAIN_KERNELS=1 asks for the plain loop. `name` says which was chosen.
LaneKernel yu2022_lane_kernel(bool friction, bool periodic, const char*& name);

// The kernels themselves (engine/yu2022_lanes_avx2.cpp, compiled for AVX2): call only on a CPU
// that has it.
LaneKernel yu2022_lanes_avx2(bool friction, bool periodic);

}  // namespace tumble::engine
