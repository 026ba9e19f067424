#pragma once
// Contact history that survives neighbour-list rebuilds and migration between ranks:
// before a rebuild every live tangential spring is saved with the global ids of its pair; after
// the rebuild the springs are matched back by ids. One mechanism, two phases (save / restore),
// as LAMMPS fix neigh/history does.
#include <cstdint>
#include <vector>

#include "base/vec3.hpp"

namespace tumble::neighbor {

// Doubles of history per contact that the store holds: one Vec3 (the tangential spring), in the
// Verlet list (VerletList::spring), in the saved records below, in migration messages and in
// checkpoints. Each contact law says how many it needs (kHistoryDoubles in its file in contact/);
// the engine checks at compile time that they agree.
constexpr int kHistoryDoubles = 3;

struct SavedSpring {
  std::int64_t lo, hi;  // global ids, lo < hi
  Vec3 spring;          // as seen from particle `lo`
  Vec3 anchor;          // position of one of the pair when saved: routes the record between ranks
};

// A record as a row of doubles in migration messages: ids (< 2^53, exact), history, anchor.
constexpr int kRecordDoubles = 2 + kHistoryDoubles + 3;
inline void append_record(const SavedSpring& s, std::vector<double>& out) {
  out.insert(out.end(), {static_cast<double>(s.lo), static_cast<double>(s.hi), s.spring.x,
                         s.spring.y, s.spring.z, s.anchor.x, s.anchor.y, s.anchor.z});
}
inline SavedSpring record_from(const double* in) {
  return {static_cast<std::int64_t>(in[0]),
          static_cast<std::int64_t>(in[1]),
          {in[2], in[3], in[4]},
          {in[5], in[6], in[7]}};
}
static_assert(kRecordDoubles == 8, "append_record/record_from spell out one Vec3 of history");

class ContactHistory {
 public:
  void clear() { saved_.clear(); }
  // Phase 1: record the spring of pair (id_i, id_j) as seen from i (skips zero springs); `anchor`
  // is where the pair is (the ranks whose domains lie near it receive the record).
  void save(std::int64_t id_i, std::int64_t id_j, const Vec3& spring_i, const Vec3& anchor = {});
  // Sort the saved records for lookup (call between the phases).
  void finalize();
  // Phase 2: the spring of (id_i, id_j) as seen from i, or zero if the pair had none.
  Vec3 lookup(std::int64_t id_i, std::int64_t id_j) const;

  const std::vector<SavedSpring>& records() const { return saved_; }
  std::vector<SavedSpring>& mutable_records() { return saved_; }
  void set_records(std::vector<SavedSpring> r) {
    saved_ = std::move(r);
    finalize();
  }

 private:
  std::vector<SavedSpring> saved_;
};

}  // namespace tumble::neighbor
