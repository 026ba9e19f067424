#include "neighbor/contact_history.hpp"

#include <algorithm>

namespace tumble::neighbor {

void ContactHistory::save(std::int64_t id_i, std::int64_t id_j, const Vec3& s, const Vec3& anchor) {
  if (s.x == 0.0 && s.y == 0.0 && s.z == 0.0) return;
  if (id_i < id_j)
    saved_.push_back({id_i, id_j, s, anchor});
  else
    saved_.push_back({id_j, id_i, -s, anchor});
}

void ContactHistory::finalize() {
  std::sort(saved_.begin(), saved_.end(), [](const SavedSpring& a, const SavedSpring& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.hi < b.hi;
  });
}

Vec3 ContactHistory::lookup(std::int64_t id_i, std::int64_t id_j) const {
  const bool flip = id_i > id_j;
  const std::int64_t lo = flip ? id_j : id_i, hi = flip ? id_i : id_j;
  auto it = std::lower_bound(saved_.begin(), saved_.end(), SavedSpring{lo, hi, {}, {}},
                             [](const SavedSpring& a, const SavedSpring& b) {
                               return a.lo != b.lo ? a.lo < b.lo : a.hi < b.hi;
                             });
  if (it == saved_.end() || it->lo != lo || it->hi != hi) return {};
  return flip ? -it->spring : it->spring;
}

}  // namespace tumble::neighbor
