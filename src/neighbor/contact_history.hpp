#pragma once
// Contact history that survives neighbour-list rebuilds and migration between ranks:
// before a rebuild every live contact's history is saved with the global ids of its pair; after
// the rebuild it is matched back by ids. One mechanism, two phases (save / restore), as LAMMPS
// fix neigh/history does.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "base/vec3.hpp"

namespace tumble::neighbor {

// The per-contact history of a law (LAMMPS's `dnum`): `width` doubles per contact, and a sign
// pattern for the pair seen from its other particle (bit d of `flip` set: component d changes
// sign; a tangential displacement flips all of its components). Chosen once per scene from the
// law (Law::kHistoryDoubles, Law::kHistoryFlip, in its file in contact/): the Verlet list
// (VerletList::history), the saved records below, migration messages and the checkpoint's
// `contacts/spring` (`width` columns) all have that width. The three laws of today keep one Vec3:
// width 3, all flipping.
constexpr int kMaxHistoryDoubles = 6;  // the most a law may keep (the capacity of a record)
struct HistoryLayout {
  int width = 3;
  std::uint32_t flip = 0x7;
  // Component d of a history, given as seen from one particle, as seen from the other.
  double other_side(int d, double value) const { return (flip >> d) & 1u ? -value : value; }
};
using HistoryValues = std::array<double, kMaxHistoryDoubles>;  // the first `width` are used

// Whether a contact's `width` doubles of history hold anything: an all-zero spring is no contact
// to carry (saved records, the list's carry-over across rebuilds).
inline bool is_live(const double* h, int width) {
  bool live = false;
  for (int d = 0; d < width; ++d) live = live || h[d] != 0.0;
  return live;
}

struct SavedSpring {
  std::int64_t lo, hi;    // global ids, lo < hi
  HistoryValues history;  // as seen from particle `lo` (zero beyond the width)
  Vec3 anchor;            // position of one of the pair when saved: routes the record between ranks
};

// A record as a row of doubles in migration messages: ids (< 2^53, exact), `width` doubles of
// history, anchor.
constexpr int record_doubles(int width) { return 2 + width + 3; }
inline void append_record(const SavedSpring& s, int width, std::vector<double>& out) {
  out.push_back(static_cast<double>(s.lo));
  out.push_back(static_cast<double>(s.hi));
  out.insert(out.end(), s.history.begin(), s.history.begin() + width);
  out.insert(out.end(), {s.anchor.x, s.anchor.y, s.anchor.z});
}
inline SavedSpring record_from(const double* in, int width) {
  SavedSpring s{};
  s.lo = static_cast<std::int64_t>(in[0]);
  s.hi = static_cast<std::int64_t>(in[1]);
  for (int d = 0; d < width; ++d) s.history[d] = in[2 + d];
  s.anchor = {in[2 + width], in[3 + width], in[4 + width]};
  return s;
}

class ContactHistory {
 public:
  explicit ContactHistory(HistoryLayout layout = {}) : layout_(layout) {}
  const HistoryLayout& layout() const { return layout_; }
  int width() const { return layout_.width; }

  void clear() {
    saved_.clear();
    slots_.clear();
    first_.clear();
  }
  // Phase 1: record the history of pair (id_i, id_j), `width` doubles at `h` as seen from i
  // (skips all-zero histories); `anchor` is where the pair is (the ranks whose domains lie near
  // it receive the record).
  void save(std::int64_t id_i, std::int64_t id_j, const double* h, const Vec3& anchor = {});
  // Room for n records (a checkpoint saves every live spring: reserving them avoids keeping
  // twice their memory, the vector's doubling, at the checkpoint's peak).
  void reserve(std::size_t n) { saved_.reserve(n); }
  // Index the saved records for lookup (call between the phases; their order is kept).
  void finalize();
  // Order the records by (lo, hi) and index them (files: an order that does not depend on the
  // particles' order in memory).
  void sort_by_ids();
  // Phase 2: the history of (id_i, id_j) as seen from i into out[0, width), or zeros if the pair
  // had none.
  void lookup(std::int64_t id_i, std::int64_t id_j, double* out) const;
  // As lookup, and the index of the record found (its pair's first record), or -1 (zeros).
  std::int64_t find(std::int64_t id_i, std::int64_t id_j, double* out) const;
  // Whether record k is the one lookups find for its pair (not a later copy of the same pair).
  bool indexed(std::size_t k) const;
  HistoryValues lookup(std::int64_t id_i, std::int64_t id_j) const {
    HistoryValues h{};
    lookup(id_i, id_j, h.data());
    return h;
  }

  const std::vector<SavedSpring>& records() const { return saved_; }
  // Changes every record's history and anchor in place, fn(history, anchor) (their ids, which the
  // index holds, stay).
  template <class Fn>
  void update(Fn&& fn) {
    for (SavedSpring& r : saved_) fn(r.history, r.anchor);
  }
  // Sets every record's anchor to anchor_of(lo, hi, anchor) (its ids and history stay).
  template <class Fn>
  void set_anchors(Fn&& anchor_of) {
    for (SavedSpring& r : saved_) r.anchor = anchor_of(r.lo, r.hi, r.anchor);
  }
  // Bytes held (capacities).
  std::size_t memory_bytes() const {
    return saved_.capacity() * sizeof(SavedSpring) + slots_.capacity() * sizeof(std::uint32_t) +
           first_.capacity();
  }
  // Hands the records over (this store is left empty).
  std::vector<SavedSpring> take_records() {
    slots_.clear();
    first_.clear();
    return std::move(saved_);
  }
  void set_records(std::vector<SavedSpring> r) {
    saved_ = std::move(r);
    finalize();
  }
  // The records without their index (lookups find nothing until finalize()): a store that is only
  // carried along until the next rebuild merges it with other records.
  void set_records_unindexed(std::vector<SavedSpring> r) {
    saved_ = std::move(r);
    slots_.clear();
    first_.clear();
  }

 private:
  HistoryLayout layout_;
  std::vector<SavedSpring> saved_;
  // Open addressing over the pair's ids: slots_[h] is a record's index + 1 (0: empty), a power of
  // two at least twice the records. A distributed rebuild saves every live spring of the rank and
  // looks each list pair up here; sorting the 88-byte records and searching them was a third of
  // a 2-rank rigid step (docs/performance.md).
  std::vector<std::uint32_t> slots_;
  std::vector<std::uint8_t> first_;  // first_[k]: record k is the one its pair's lookups find
  std::size_t slot_of(std::int64_t lo, std::int64_t hi) const;
};

}  // namespace tumble::neighbor
