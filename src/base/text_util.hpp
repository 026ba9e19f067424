#pragma once
// Small text helpers shared by the CLI-facing code: key suggestions and durations.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

namespace tumble {

// Levenshtein distance: suggests the nearest valid key for a typo.
inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    prev.swap(cur);
  }
  return prev[b.size()];
}

// The shortest text (15 to 17 significant digits, %g) that reads back to the same double: 0.15
// stays "0.15", not 0.14999999999999999, and every value has exactly one rendering (a campaign's
// case ids hash it: the form must not change).
inline std::string canonical_number(double v) {
  char buf[40];
  for (int prec = 15; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

// Seconds as h:mm:ss for progress lines ("--:--:--" when unknown).
inline std::string format_hms(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--:--";
  const long t = static_cast<long>(s + 0.5);
  std::ostringstream os;
  os << t / 3600 << ":" << std::setw(2) << std::setfill('0') << (t / 60) % 60 << ":" << std::setw(2)
     << t % 60;
  return os.str();
}

// A number in at most `digits` significant digits, for labels ("0.971", "25").
inline std::string short_number(double v, int digits = 3) {
  std::ostringstream os;
  os << std::setprecision(digits) << v;
  return os.str();
}

}  // namespace tumble
