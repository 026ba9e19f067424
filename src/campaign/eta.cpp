#include "campaign/eta.hpp"

#include <algorithm>
#include <cmath>

namespace tumble::campaign {

double estimate_eta(const EtaInput& in) {
  if (!(in.done_cost > 0) || !(in.done_rank_seconds > 0)) return NAN;
  const double rate = in.done_cost / in.done_rank_seconds;  // cost per rank-second
  double left = in.queued_cost, longest = 0;
  for (const auto& r : in.running) {
    const double rest = std::max(0.0, r.cost - rate * r.ranks * r.age);
    left += rest;
    longest = std::max(longest, rest / (rate * std::max(1, r.ranks)));
  }
  return std::max(left / (rate * std::max(1, in.ranks)), longest);
}

}  // namespace tumble::campaign
