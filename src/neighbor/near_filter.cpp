#include "neighbor/near_filter.hpp"

#include <cmath>

#include "base/cpu_lanes.hpp"

namespace tumble::neighbor {

std::size_t near_filter_plain(const double* x, const double* radius, std::uint32_t lo,
                              std::uint32_t hi, const double* xi, double ri, double skin,
                              double period, std::uint32_t* out) {
  std::size_t m = 0;
  for (std::uint32_t j = lo; j < hi; ++j) {
    const double* xj = x + 3 * std::size_t{j};
    const double cut = (ri + radius[j]) + skin;  // (symmetric: near_filter.hpp)
    const double dx = xi[0] - xj[0], dy = xi[1] - xj[1];
    double dz = xi[2] - xj[2];
    if (period > 0) dz -= period * std::nearbyint(dz / period);
    out[m] = j;
    m += dx * dx + dy * dy + dz * dz < cut * cut;
  }
  return m;
}

NearFilter near_filter() { return lanes_available() ? &near_filter_avx2 : &near_filter_plain; }

}  // namespace tumble::neighbor
