#pragma once
// A set of global particle ids, asked "is this id in it?" once per record or listed pair at each
// rebuild of the rigid bulk (the ids that leave a rank, the ids with a dormant spring, the ids a
// rank owns). A rank's set holds about its own particles, while ids run over the whole
// realization: a byte per id up to the largest (one load per question) costs the realization's
// size per set and per rebuild on every rank, ~10 MB for 10^7 particles however many ranks share
// them. So a set is a byte per id only where that is at most kDenseBytesPerMember bytes per
// member (a few ranks, or ids that lie close), else an open-addressing table of its ids (~21
// bytes per member, a multiply and a short probe per question).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "neighbor/id_index.hpp"

namespace tumble::neighbor {

class IdSet {
 public:
  // Above this many bytes per member the set is a table, not a byte per id: filling a byte per id
  // costs about what hashing a member does at ~64 bytes per member.
  static constexpr std::uint64_t kDenseBytesPerMember = 64;

  // The ids each(mark) marks (mark(id) for every member, ids >= 0, repeats allowed); `each` is
  // called twice (the size first).
  template <class EachId>
  explicit IdSet(EachId each) {
    std::uint64_t marks = 0;
    each([&](std::int64_t id) {
      top_ = std::max(top_, id);
      ++marks;
    });
    if (top_ < 0) return;
    if (static_cast<std::uint64_t>(top_) + 1 <= kDenseBytesPerMember * marks) {
      flags_.assign(static_cast<std::size_t>(top_) + 1, 0);
      each([&](std::int64_t id) { flags_[static_cast<std::size_t>(id)] = 1; });
      return;
    }
    const std::size_t size = id_table_size(marks);
    keys_.assign(size, -1);
    mask_ = size - 1;
    each([&](std::int64_t id) {
      std::size_t at = slot_of(id);
      while (keys_[at] >= 0 && keys_[at] != id) at = (at + 1) & mask_;
      keys_[at] = id;
    });
  }
  bool operator()(std::int64_t id) const {
    if (id < 0 || id > top_) return false;
    if (!flags_.empty()) return flags_[static_cast<std::size_t>(id)] != 0;
    for (std::size_t at = slot_of(id); keys_[at] >= 0; at = (at + 1) & mask_)
      if (keys_[at] == id) return true;
    return false;
  }
  bool empty() const { return top_ < 0; }
  bool dense() const { return !flags_.empty(); }
  std::size_t memory_bytes() const {
    return flags_.capacity() + keys_.capacity() * sizeof(std::int64_t);
  }
  // Not copyable: a copy made per record (a predicate taken by value) once cost more than the
  // rebuild's other work (docs/performance.md, "A copy per dormant record").
  IdSet(const IdSet&) = delete;
  IdSet& operator=(const IdSet&) = delete;
  IdSet(IdSet&&) = default;
  IdSet& operator=(IdSet&&) = default;

 private:
  std::size_t slot_of(std::int64_t id) const { return id_slot(id) & mask_; }
  std::int64_t top_ = -1;
  std::vector<std::uint8_t> flags_;  // dense: flags_[id]
  std::vector<std::int64_t> keys_;   // a table: -1 empty
  std::size_t mask_ = 0;
};

}  // namespace tumble::neighbor
