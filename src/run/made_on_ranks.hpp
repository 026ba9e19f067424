#pragma once
// The words a log line adds about the rank count a cached result was made on (a settled bed, a
// measured β): one job of ranks makes it for every later job, and another count would have made
// another one in round-off (docs/guarantees.md, "Reproducible").
#include <string>

namespace tumble {

// ", <made> on N rank(s)", and " (this run has M: <otherwise>; the cache keeps the first)" where
// this run's count differs; "" for made_on <= 0 (a file written before the count was kept).
inline std::string made_on_ranks(const std::string& made, long long made_on, int here,
                                 const std::string& otherwise) {
  if (made_on <= 0) return "";
  std::string s =
      ", " + made + " on " + std::to_string(made_on) + (made_on == 1 ? " rank" : " ranks");
  if (made_on != here)
    s += " (this run has " + std::to_string(here) + ": " + otherwise +
         "; the cache keeps the first)";
  return s;
}

}  // namespace tumble
