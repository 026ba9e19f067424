#pragma once
// The distance filter of the neighbour search: which particles of a run of consecutive indices (one
// cell of the sorted bed) are within reach of particle i. Two versions that return the same
// indices: plain, and four candidates at a time on AVX2 (near_filter_avx2.cpp, used where
// base/cpu_lanes.hpp allows). The list build spends most of its time here.
#include <cstddef>
#include <cstdint>

namespace tumble::neighbor {

// Writes to `out`, in increasing order, every j in [lo, hi) with
// |x_i - x_j|^2 < ((r_i + r_j) + skin)^2 (x: the particles' positions as x, y, z doubles; the z
// difference taken to the nearest image when period > 0) and returns how many. `out` must have
// room for hi - lo + 4 entries. The cutoff is summed in that order so that it is the same bits
// for (i, j) and (j, i): two ranks deciding a border pair each from its own side agree on
// whether it is listed (with (r_i + skin) + r_j a pair at the cutoff could round in on one side
// and out on the other, and with Newton across borders be computed by neither).
using NearFilter = std::size_t (*)(const double* x, const double* radius, std::uint32_t lo,
                                   std::uint32_t hi, const double* xi, double ri, double skin,
                                   double period, std::uint32_t* out);

std::size_t near_filter_plain(const double* x, const double* radius, std::uint32_t lo,
                              std::uint32_t hi, const double* xi, double ri, double skin,
                              double period, std::uint32_t* out);
std::size_t near_filter_avx2(const double* x, const double* radius, std::uint32_t lo,
                             std::uint32_t hi, const double* xi, double ri, double skin,
                             double period, std::uint32_t* out);

// The filter this CPU runs.
NearFilter near_filter();

}  // namespace tumble::neighbor
