#include "neighbor/contact_history.hpp"

#include <algorithm>
#include <utility>

namespace tumble::neighbor {

void ContactHistory::save(std::int64_t id_i, std::int64_t id_j, const double* h,
                          const Vec3& anchor) {
  const int w = layout_.width;
  bool live = false;
  for (int d = 0; d < w; ++d) live |= h[d] != 0.0;
  if (!live) return;
  SavedSpring s{};
  s.anchor = anchor;
  if (id_i < id_j) {
    s.lo = id_i;
    s.hi = id_j;
    for (int d = 0; d < w; ++d) s.history[d] = h[d];
  } else {
    s.lo = id_j;
    s.hi = id_i;
    for (int d = 0; d < w; ++d) s.history[d] = layout_.other_side(d, h[d]);
  }
  saved_.push_back(s);
}

void ContactHistory::finalize() {
  std::sort(saved_.begin(), saved_.end(), [](const SavedSpring& a, const SavedSpring& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.hi < b.hi;
  });
}

void ContactHistory::lookup(std::int64_t id_i, std::int64_t id_j, double* out) const {
  const int w = layout_.width;
  const bool flip = id_i > id_j;
  const std::int64_t lo = flip ? id_j : id_i, hi = flip ? id_i : id_j;
  auto it =
      std::lower_bound(saved_.begin(), saved_.end(), std::make_pair(lo, hi),
                       [](const SavedSpring& a, const std::pair<std::int64_t, std::int64_t>& b) {
                         return a.lo != b.first ? a.lo < b.first : a.hi < b.second;
                       });
  if (it == saved_.end() || it->lo != lo || it->hi != hi) {
    for (int d = 0; d < w; ++d) out[d] = 0.0;
    return;
  }
  for (int d = 0; d < w; ++d)
    out[d] = flip ? layout_.other_side(d, it->history[d]) : it->history[d];
}

}  // namespace tumble::neighbor
