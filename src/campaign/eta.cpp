#include "campaign/eta.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::campaign {

double estimate_eta(const EtaInput& in) {
  double cost_done = std::max(0.0, in.done_cost),
         rank_seconds = std::max(0.0, in.done_rank_seconds);
  for (const auto& r : in.running)
    if (r.reported && r.call_share > 0 && r.call_seconds > 0) {
      cost_done += r.cost * r.call_share;
      rank_seconds += r.call_seconds * std::max(1, r.ranks);
    }
  if (!(cost_done > 0) || !(rank_seconds > 0)) return NAN;
  const double rate = cost_done / rank_seconds;  // cost per rank-second
  double left = in.queued_cost, longest = 0;
  for (const auto& r : in.running) {
    if (r.reported && r.call_share > 0 && r.call_seconds > 0) {
      const double per_second = r.call_share / r.call_seconds;  // its own share per second
      const double share_left = std::max(0.0, 1 - r.done_share - per_second * r.since_report);
      left += r.cost * share_left;
      longest = std::max(longest, share_left / per_second);
      continue;
    }
    const double rest = std::max(0.0, r.cost - rate * r.ranks * r.age);
    left += rest;
    longest = std::max(longest, rest / (rate * std::max(1, r.ranks)));
  }
  return std::max(left / (rate * std::max(1, in.ranks)), longest);
}

}  // namespace tumble::campaign
