#include "neighbor/contact_history.hpp"

#include <algorithm>
#include <utility>

namespace tumble::neighbor {

void ContactHistory::save(std::int64_t id_i, std::int64_t id_j, const double* h,
                          const Vec3& anchor) {
  const int w = layout_.width;
  if (!is_live(h, w)) return;
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

std::size_t ContactHistory::slot_of(std::int64_t lo, std::int64_t hi) const {
  // A multiplicative mix of both ids (Fibonacci hashing); the top bits are the best mixed.
  std::uint64_t h = static_cast<std::uint64_t>(lo) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<std::uint64_t>(hi) + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2);
  h *= 0x9E3779B97F4A7C15ull;
  return static_cast<std::size_t>(h >> 32) & (slots_.size() - 1);
}

void ContactHistory::finalize() {
  std::size_t size = 16;
  while (size < 2 * saved_.size()) size *= 2;
  slots_.assign(size, 0);
  first_.assign(saved_.size(), 0);
  const std::size_t mask = size - 1;
  for (std::size_t k = 0; k < saved_.size(); ++k) {
    std::size_t at = slot_of(saved_[k].lo, saved_[k].hi);
    // A pair saved twice (a border pair received from both of its ranks: the same spring) keeps
    // its first record.
    bool seen = false;
    for (; slots_[at] != 0; at = (at + 1) & mask) {
      const SavedSpring& other = saved_[slots_[at] - 1];
      if (other.lo == saved_[k].lo && other.hi == saved_[k].hi) {
        seen = true;
        break;
      }
    }
    if (!seen) {
      slots_[at] = static_cast<std::uint32_t>(k + 1);
      first_[k] = 1;
    }
  }
}

void ContactHistory::sort_by_ids() {
  std::sort(saved_.begin(), saved_.end(), [](const SavedSpring& a, const SavedSpring& b) {
    return a.lo != b.lo ? a.lo < b.lo : a.hi < b.hi;
  });
  finalize();
}

void ContactHistory::lookup(std::int64_t id_i, std::int64_t id_j, double* out) const {
  find(id_i, id_j, out);
}

std::int64_t ContactHistory::find(std::int64_t id_i, std::int64_t id_j, double* out) const {
  const int w = layout_.width;
  const bool flip = id_i > id_j;
  const std::int64_t lo = flip ? id_j : id_i, hi = flip ? id_i : id_j;
  if (!slots_.empty()) {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t at = slot_of(lo, hi); slots_[at] != 0; at = (at + 1) & mask) {
      const SavedSpring& s = saved_[slots_[at] - 1];
      if (s.lo != lo || s.hi != hi) continue;
      for (int d = 0; d < w; ++d)
        out[d] = flip ? layout_.other_side(d, s.history[d]) : s.history[d];
      return static_cast<std::int64_t>(slots_[at]) - 1;
    }
  }
  for (int d = 0; d < w; ++d) out[d] = 0.0;
  return -1;
}

bool ContactHistory::indexed(std::size_t k) const { return k < first_.size() && first_[k] != 0; }

}  // namespace tumble::neighbor
