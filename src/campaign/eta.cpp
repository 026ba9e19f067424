#include "campaign/eta.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::campaign {
namespace {
bool measured(const EtaInput::Rate& r) { return r.cost > 0 && r.rank_seconds > 0; }
bool reported(const EtaInput::Running& r) {
  return r.reported && r.call_share > 0 && r.call_seconds > 0;
}
}  // namespace

double estimate_eta(const EtaInput& in) {
  EtaInput::Rate all{std::max(0.0, in.done_cost), std::max(0.0, in.done_rank_seconds)};
  std::map<std::string, EtaInput::Rate> by_point = in.done_by_point;
  for (const auto& r : in.running)
    if (reported(r)) {
      const double cost = r.cost * r.call_share,
                   rank_seconds = r.call_seconds * std::max(1, r.ranks);
      all.cost += cost;
      all.rank_seconds += rank_seconds;
      if (!r.point.empty()) {
        by_point[r.point].cost += cost;
        by_point[r.point].rank_seconds += rank_seconds;
      }
    }
  if (!measured(all)) return NAN;
  // Cost per rank-second: the point's own once measured, else all points' together.
  const auto rate = [&](const std::string& point) {
    const auto it = point.empty() ? by_point.end() : by_point.find(point);
    const EtaInput::Rate& r = it != by_point.end() && measured(it->second) ? it->second : all;
    return r.cost / r.rank_seconds;
  };
  double rank_seconds = in.queued_cost / rate("");
  for (const auto& [point, cost] : in.queued_by_point) rank_seconds += cost / rate(point);
  const double per_file = std::max(0.0, in.rank_seconds_per_file);
  rank_seconds += std::max(0, in.queued_files) * per_file;
  double longest = 0;
  for (const auto& r : in.running) {
    const int k = std::max(1, r.ranks);
    if (reported(r)) {
      const double per_second = r.call_share / r.call_seconds;  // its own share per second
      const double share_left = std::max(0.0, 1 - r.done_share - per_second * r.since_report);
      rank_seconds += share_left / per_second * k;
      longest = std::max(longest, share_left / per_second);
      continue;
    }
    const double p = rate(r.point);
    // A case whose protocol began (reported once, no rate of its own yet) is credited from its
    // share done at that report; one that did not report, with its age.
    const double rest = r.preparing ? r.cost
                        : r.reported
                            ? std::max(0.0, r.cost * (1 - r.done_share) - p * k * r.since_report)
                            : std::max(0.0, r.cost - p * k * r.age);
    // (rank-seconds; a preparation that runs past its measure is taken to end now)
    const double preparation_left =
        r.preparing ? std::max(0.0, r.files * per_file - r.preparing_for * k) : 0.0;
    rank_seconds += rest / p + preparation_left;
    longest = std::max(longest, (rest / p + preparation_left) / k);
  }
  return std::max(rank_seconds / std::max(1, in.ranks), longest);
}

}  // namespace tumble::campaign
