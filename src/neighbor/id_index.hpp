#pragma once
// Where a particle of a global id sat in a previous ordering: an open-addressing table from id to
// index, built once per rebuild and asked once per particle. A domain-decomposed rebuild uses it
// to find, for each particle now on the rank (owned or ghost), its row in the list it had before
// the migration, so that springs are carried by index as on one rank (VerletList::keep_springs)
// instead of being looked up by the pair's ids, one search per listed pair.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tumble::neighbor {

// The open-addressing tables over particle ids (IdIndex here, IdSet in id_set.hpp) share their
// size and hash. Size: a power of two at most 3/4 full (linear probing stays short: ~2.5 probes a
// hit at 3/4); half the memory of "at most half full".
inline std::size_t id_table_size(std::uint64_t n) {
  std::size_t size = 16;
  while (3 * static_cast<std::uint64_t>(size) < 4 * n) size *= 2;
  return size;
}
// Fibonacci hashing: the product's bits from 32 up are well mixed (ids are non-negative).
inline std::size_t id_slot(std::int64_t id) {
  return static_cast<std::size_t>((static_cast<std::uint64_t>(id) * 0x9E3779B97F4A7C15ull) >> 32);
}

class IdIndex {
 public:
  static constexpr std::uint32_t kAbsent = 0xFFFFFFFFu;
  // Indexes ids[0, n): index_of(ids[k]) == k (ids unique).
  void assign(const std::int64_t* ids, std::size_t n) {
    const std::size_t size = id_table_size(n);  // (one lookup per particle a rebuild)
    keys_.assign(size, -1);
    values_.assign(size, kAbsent);
    const std::size_t mask = size - 1;
    for (std::size_t k = 0; k < n; ++k) {
      std::size_t at = slot_of(ids[k]) & mask;
      while (keys_[at] >= 0) at = (at + 1) & mask;
      keys_[at] = ids[k];
      values_[at] = static_cast<std::uint32_t>(k);
    }
  }
  // The index given to `id`, or kAbsent.
  std::uint32_t index_of(std::int64_t id) const {
    if (keys_.empty()) return kAbsent;
    const std::size_t mask = keys_.size() - 1;
    for (std::size_t at = slot_of(id) & mask; keys_[at] >= 0; at = (at + 1) & mask)
      if (keys_[at] == id) return values_[at];
    return kAbsent;
  }
  void clear() {
    keys_.clear();
    values_.clear();
  }
  std::size_t memory_bytes() const {
    return keys_.capacity() * sizeof(std::int64_t) + values_.capacity() * sizeof(std::uint32_t);
  }

 private:
  static std::size_t slot_of(std::int64_t id) { return id_slot(id); }
  std::vector<std::int64_t> keys_;  // -1: empty
  std::vector<std::uint32_t> values_;
};

}  // namespace tumble::neighbor
