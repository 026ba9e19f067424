#include "islands/dpsi_snapshots.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>

#include "base/error.hpp"

namespace tumble::analysis {

namespace {
ShellDirections directions(const SnapshotData& s, const LambertGrid& grid, double inner) {
  // Snapshots hold the particles in global-id order: the slot of particle i is i.
  std::vector<std::uint32_t> slot(s.size());
  std::iota(slot.begin(), slot.end(), 0u);
  return shell_directions(s.as_particles(), slot, Mat3::identity(), grid, s.R, inner);
}
}  // namespace

SnapshotDisplacement displacement_from_snapshots(const std::vector<SnapshotData>& snaps, double lag,
                                                 double from, double to, const LambertGrid& grid,
                                                 double inner) {
  SnapshotDisplacement out;
  out.map = DisplacementMap(grid.cells());
  std::vector<double> iterations;
  for (const auto& s : snaps) iterations.push_back(s.iteration);
  const std::vector<bool> repeat = repeated_snapshots(iterations);
  for (std::size_t a = 0; a < snaps.size(); ++a) {
    const double n = snaps[a].iteration;
    if (repeat[a]) continue;
    if (n < from - kIterationSlack || n + lag > to + kIterationSlack) continue;
    std::size_t b = a + 1;
    while (b < snaps.size() && snaps[b].iteration < n + lag - kIterationSlack) ++b;
    if (b == snaps.size() || std::fabs(snaps[b].iteration - (n + lag)) > kIterationSlack) continue;
    if (snaps[b].size() != snaps[a].size() || snaps[b].id != snaps[a].id)
      throw CorruptInputError("snapshots '" + snaps[a].path + "' and '" + snaps[b].path +
                              "' hold different particles");
    const ShellDirections start = directions(snaps[a], grid, inner);
    const ShellDirections end = directions(snaps[b], grid, inner);
    out.map.add_interval(start, end.u, snaps[a].species);
    if (out.starts == 0) out.first = n;
    out.last = n;
    ++out.starts;
  }
  return out;
}

DpsiContrast dpsi_contrast(const std::vector<double>& sum, const std::vector<double>& count,
                           const std::vector<double>& coverage) {
  double in_sum = 0, in_w = 0, out_sum = 0, out_w = 0;
  for (std::size_t c = 0; c < sum.size() && c < coverage.size(); ++c) {
    if (!(count[c] > 0)) continue;
    in_sum += coverage[c] * sum[c];
    in_w += coverage[c] * count[c];
    out_sum += (1 - coverage[c]) * sum[c];
    out_w += (1 - coverage[c]) * count[c];
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {in_w > 0 ? in_sum / in_w : nan, out_w > 0 ? out_sum / out_w : nan};
}

}  // namespace tumble::analysis
