#pragma once
// Half Verlet list (each pair once, j > i in cell-sorted order; on more than one rank a border
// row also holds its interior partners, see add_row) in compressed-row form, with the
// per-pair contact history stored in a parallel strided array (the law's width per pair) so the
// force loop touches it directly.
// Rebuilt when any particle has moved more than half the skin since the last build.
#include <cstdint>
#include <vector>

#include "base/particles.hpp"
#include "neighbor/cell_grid.hpp"
#include "neighbor/contact_history.hpp"
#include "neighbor/id_index.hpp"
#include "neighbor/near_filter.hpp"

namespace tumble::neighbor {

// Which of the two ranks of a border pair computes it (Newton across borders): the owner of the
// particle with id a when this is true, that of b when it is false (for b, a it is the opposite,
// so both ranks agree without a word). The ids alone decide, so the choice changes only when a
// particle changes rank, where its springs travel anyway; the parity of a + b alternates it, so
// that each side of a border computes about half of its pairs even where ids follow position
// (as a filled bed's do). The rule of LAMMPS' half lists with newton on for an atom and a ghost.
inline bool computes_border_pair(std::int64_t a, std::int64_t b) {
  return (a < b) != (((a + b) & 1) != 0);
}

class VerletList {
 public:
  VerletList() = default;
  // `layout`: the doubles of history per pair and their sign pattern (the scene's law).
  VerletList(const CellGrid& grid, double skin, HistoryLayout layout = {})
      : grid_(grid), skin_(skin), layout_(layout), near_(near_filter()) {}

  // Sorts `p` by cell (permuting every per-particle field), rebuilds the list, and carries the
  // histories over (by old index; negated per the layout where the pair is now seen from its
  // other particle). `history`, if non-null, supplies them instead, matched by global id
  // (restart, migration).
  //
  // The rigid bulk (`dormant` non-null; p.bulk_state < 0: frozen): a pair of two frozen particles
  // is left out of the list (no force loop reads it, and no rebuild filters it: a cell's frozen
  // particles are sorted after its moving ones and a frozen row looks at moving partners only).
  // Its spring waits in *dormant, by ids: a pair of the old list whose particles are both frozen
  // now moves there (anchored at its row particle), a pair that comes back into the list (one
  // of its particles thawed) takes its spring from there, and what no pair took stays.
  void rebuild(Particles& p, const ContactHistory* history = nullptr,
               ContactHistory* dormant = nullptr);
  // Domain-decomposed runs, in two phases around the ghost exchange: sort(p) orders the owned
  // particles by cell; build_with_ghosts() then lists, for each of the first `n_local`
  // particles, its owned partners of higher index and every ghost (index >= n_local) in reach,
  // with histories from `history` (matched by global id).
  // With `dormant` (the rigid bulk, as in rebuild(); sort with frozen_last then): *dormant holds
  // the rank's dormant springs (`history` those that arrived, which may be copies of them), and
  // becomes those of both that no pair of the new list took and that have one of this rank's own
  // particles (and, after keep_springs, the kept springs that no pair took, below). Only the
  // dormant springs with a moving particle (or an arrived copy) are indexed and looked up: a pair
  // of two frozen particles is in no list.
  // `border` (one flag per owned particle, in their present order; Domain::mark_border): the
  // particles that may pair with a ghost are sorted after all the others, so the first
  // interior_rows() rows of the list that build_with_ghosts() makes have owned partners only.
  void sort(Particles& p, bool frozen_last = false,
            const std::vector<std::uint8_t>* border = nullptr);
  // (With `dormant`, `history`'s records are taken: those kept become the dormant ones.)
  void build_with_ghosts(const Particles& p, std::size_t n_local, ContactHistory& history,
                         ContactHistory* dormant = nullptr);
  // The ghosts (rows n_local.. of `p`) in the order of their cells, stably: order[k] is the ghost
  // (counted from n_local) that belongs at ghost slot k. Ghosts placed so (Domain::place_ghosts)
  // are one range of rows per cell, which the row scans of build_with_ghosts() filter four at a
  // time like the owned particles, in the same order as one at a time.
  void ghost_order(const Particles& p, std::size_t n_local,
                   std::vector<std::uint32_t>& order) const;
  // A domain-decomposed rebuild that is not a restart carries the springs by index wherever the
  // rank held the pair before, as rebuild() does on one rank, in three calls around the
  // migration. keep_springs(p, n_local), before anything moves: keeps this list's live springs
  // by old index, with the ids of the particles (owned and ghosts) and the owned ones'
  // positions. springs_leaving(p, n_local), after the migration (`p` holds the owned particles):
  // the kept springs of the pairs with an owned particle that left this rank, anchored at their
  // row particle: only the ranks that receive a particle need a spring they did not hold (a rank
  // that owned one of a pair's particles before listed the pair), so only these travel. The next
  // build_with_ghosts() then takes the spring of every pair with a particle this rank owned
  // before from the kept ones, and the others' from `history` (the springs that arrived).
  // With the rigid bulk (`dormant` given to both calls after it; Newton off) the same, and the
  // dormant springs stay with every rank that owns one of their particles: springs_leaving adds
  // those of them with a particle that left, and build_with_ghosts, given this rank's dormant
  // springs and, as `history`, those that arrived, makes the kept springs that no pair took
  // (pairs of two frozen particles now) dormant.
  void keep_springs(const Particles& p, std::size_t n_local);
  // Newton's third law across rank borders (set once per scene, the same on every rank): a
  // border pair of owned particle i and ghost j is listed on i's rank only if
  // computes_border_pair(id_i, id_j), so exactly one of the two ranks lists it, holds its spring
  // and sends the ghost's half of the force to j's owner (Domain::reverse_forces).
  void set_newton(bool on) { newton_ = on; }
  bool newton() const { return newton_; }
  std::vector<SavedSpring> springs_leaving(const Particles& p, std::size_t n_local,
                                           const ContactHistory* dormant = nullptr) const;
  // Makes z periodic with this period (the cell grid must span exactly one period in z).
  void set_period_z(double period);
  double period_z() const { return period_z_; }
  // Saves the live histories of the current list (for a checkpoint, or migration); `out` takes
  // this list's layout. `sorted`: ordered by ids and ready for lookup; otherwise in list order,
  // not indexed (a migration indexes them where they arrive).
  void save_history(const Particles& p, ContactHistory& out, bool sorted = true) const;
  const HistoryLayout& history_layout() const { return layout_; }

  std::vector<std::uint32_t> start;  // size n+1
  std::vector<std::uint32_t> nbr;    // partner indices
  std::vector<std::uint32_t> row;    // row particle of each pair (row[k] = i for start[i] <= k <
                                     // start[i + 1]), for loops over pairs rather than rows
  // History of pair k, as seen from the row particle: history[w k], ..., history[w k + w - 1],
  // w = history_layout().width.
  std::vector<double> history;
  std::uint64_t builds = 0;
  double skin() const { return skin_; }
  // Rows [0, interior_rows()) have no ghost partner (nor a border particle's: a border row holds
  // its pairs with interior particles): the force loop can run them while the ghosts' new
  // positions are still on their way (all rows on one rank; none where the sort was given no
  // border flags).
  std::size_t interior_rows() const { return interior_rows_; }
  // Positions at the last rebuild (the integrator checks displacements while it drifts).
  const std::vector<Vec3>& reference_positions() const { return x_ref_; }
  // Bytes held by the list's arrays (capacities: a rebuild's high-water mark), the previous list
  // kept for carrying the springs over included.
  std::size_t memory_bytes() const;

 private:
  CellGrid grid_;
  double skin_ = 0;
  double period_z_ = 0;  // 0: not periodic
  HistoryLayout layout_;
  // Writes the partners of row i after the first `count` entries of nbr (growing it as needed):
  // owned j > i from the sorted cells, and ghosts if binned. Returns the new count.
  std::size_t add_row(const Particles& p, std::size_t i, bool with_ghosts, std::size_t count);
  NearFilter near_ = &near_filter_plain;  // the distance filter this CPU runs
  // Fills `row` from `start`.
  void fill_rows();
  // The list is valid for local carry-over when it describes the current particles.
  bool old_start_capacity_ok(std::size_t n) const { return start.size() == n + 1; }
  std::vector<Vec3> x_ref_;
  std::vector<std::uint32_t> perm_, cell_start_;
  // The rigid bulk: frozen rows skip frozen partners (the sort puts each border class's frozen
  // particles after its moving ones: CellGrid::sort).
  bool skip_frozen_ = false;
  // Layers of the sort (cell c of layer L is cell L cell_count() + c of cell_start_): per border
  // class 2 with the rigid bulk (moving, frozen), else 1; 1 or 2 border classes (the border
  // particles after the others).
  int per_class_ = 1;
  int layers_ = 1;
  std::size_t interior_rows_ = 0;
  bool newton_ = false;                                     // set_newton()
  std::vector<std::uint32_t> ghost_start_, ghost_of_cell_;  // ghosts binned by cell (not moved)
  bool ghosts_in_cell_order_ = false;  // ... and they lie in cell order (ghost_order())
  // The previous list's live springs (rows, partners, springs) while a rebuild carries them over.
  std::vector<std::uint32_t> old_start_, old_nbr_;
  std::vector<double> old_history_;
  // Copies the live springs of the first `rows` rows into old_start_, old_nbr_, old_history_.
  void keep_live_springs(std::size_t rows);
  // The kept spring of old pair (row, partner) into `to` (seen from the partner if `flip`), and
  // its index among the kept ones; -1, `to` untouched, if that row holds none for the partner.
  std::int64_t carry_spring(std::uint32_t row, std::uint32_t partner, bool flip, double* to) const;
  // keep_springs(): the previous particles' ids (owned first, then ghosts), where each id was,
  // the owned ones' positions, and whether the next build_with_ghosts() carries from them.
  bool carry_kept_ = false;
  std::size_t kept_owned_ = 0;
  std::vector<std::int64_t> kept_id_;
  std::vector<Vec3> kept_x_;
  IdIndex kept_index_;
};

}  // namespace tumble::neighbor
