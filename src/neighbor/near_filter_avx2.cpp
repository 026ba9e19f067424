// near_filter on four candidates at a time, AVX2: compiled for AVX2 by the pragma and called only
// where base/cpu_lanes.hpp allows. The same operations as near_filter_plain, in its order: the
// same indices come out.
#pragma GCC target("avx2")
#include "base/avx2.hpp"
#include "neighbor/near_filter.hpp"

namespace tumble::neighbor {

std::size_t near_filter_avx2(const double* x, const double* radius, std::uint32_t lo,
                             std::uint32_t hi, const double* xi, double ri, double skin,
                             double period, std::uint32_t* out) {
  using namespace avx2;
  const V centre{_mm256_set1_pd(xi[0]), _mm256_set1_pd(xi[1]), _mm256_set1_pd(xi[2])};
  const __m256d ri4 = _mm256_set1_pd(ri), skin4 = _mm256_set1_pd(skin);
  const __m256d period4 = _mm256_set1_pd(period);
  std::size_t m = 0;
  std::uint32_t j = lo;
  for (; j + 4 <= hi; j += 4) {
    alignas(16) const std::uint32_t idx[4] = {j, j + 1, j + 2, j + 3};
    V d = centre - load3(x, idx);
    if (period > 0) d.z = d.z - period4 * _mm256_round_pd(d.z / period4, _MM_FROUND_CUR_DIRECTION);
    const __m256d cut = (ri4 + _mm256_loadu_pd(radius + j)) + skin4;
    const int near = _mm256_movemask_pd(_mm256_cmp_pd(dot(d, d), cut * cut, _CMP_LT_OQ));
    pack_store(out + m, load_index(idx), near);
    m += static_cast<std::size_t>(__builtin_popcount(static_cast<unsigned>(near)));
  }
  for (; j < hi; ++j) {  // the last candidates, one at a time
    const double* xj = x + 3 * std::size_t{j};
    const double cut = (ri + radius[j]) + skin;  // (symmetric: near_filter.hpp)
    const double dx = xi[0] - xj[0], dy = xi[1] - xj[1];
    double dz = xi[2] - xj[2];
    if (period > 0) dz -= period * __builtin_nearbyint(dz / period);
    out[m] = j;
    m += dx * dx + dy * dy + dz * dz < cut * cut;
  }
  return m;
}

}  // namespace tumble::neighbor
