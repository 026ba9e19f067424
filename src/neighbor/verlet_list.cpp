#include "neighbor/verlet_list.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "base/growth.hpp"
#include "neighbor/id_set.hpp"

namespace tumble::neighbor {

namespace {
// The ids with a record among `records` (only a pair of two such particles can have one: two
// questions to the set pass most pairs over without a search of the records).
IdSet ids_with_records(const std::vector<SavedSpring>& records) {
  return IdSet([&](auto mark) {
    for (const SavedSpring& r : records) mark(r.lo), mark(r.hi);
  });
}

}  // namespace

void VerletList::save_history(const Particles& p, ContactHistory& out, bool sorted) const {
  out = ContactHistory(layout_);
  const std::size_t n = start.empty() ? 0 : start.size() - 1;
  const std::size_t w = static_cast<std::size_t>(layout_.width);
  std::size_t live = 0;
  for (std::size_t k = 0; k < nbr.size(); ++k)
    live += is_live(history.data() + w * k, layout_.width);
  out.reserve(live);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k)
      out.save(p.id[i], p.id[nbr[k]], history.data() + w * k, p.x[i]);
  if (sorted) out.sort_by_ids();
}

std::size_t VerletList::memory_bytes() const {
  std::size_t bytes = kept_id_.capacity() * sizeof(std::int64_t) +
                      kept_x_.capacity() * sizeof(Vec3) + kept_index_.memory_bytes();
  for (const auto* v : {&start, &nbr, &row, &perm_, &cell_start_, &ghost_start_, &ghost_of_cell_,
                        &old_start_, &old_nbr_})
    bytes += v->capacity() * sizeof(std::uint32_t);
  for (const auto* v : {&history, &old_history_}) bytes += v->capacity() * sizeof(double);
  return bytes + x_ref_.capacity() * sizeof(Vec3);
}

void VerletList::set_period_z(double period) {
  if (period > 0 && grid_.nz() < 3)
    throw std::invalid_argument("a periodic direction needs at least 3 neighbour cells");
  period_z_ = period;
}

std::size_t VerletList::add_row(const Particles& p, std::size_t i, bool with_ghosts,
                                std::size_t count) {
  // A frozen row lists its moving partners only (the rigid bulk: see rebuild()). Those of its own
  // border class lie below it (the sort puts the frozen after them): a frozen interior row, or
  // one of a single rank, lists nothing.
  const bool frozen_row = skip_frozen_ && p.bulk_state[i] < 0;
  // Two border classes (more than one rank, VerletList::sort): an interior row (i <
  // interior_rows_) lists the interior particles j > i only, a border row the border particles
  // j > i and every interior particle in reach (all of lower index): the pairs of the interior
  // rows then read no border particle's row either, and a pair is still listed once. (Scanning
  // the border layers from the interior rows instead cost ~40% more in the row scans: twice the
  // cells for every row.)
  const bool border_row = layers_ > per_class_ && i >= interior_rows_;
  if (frozen_row && !border_row) return count;
  // The layers the row scans (their first cell's index in cell_start_) and whether it takes all
  // of a layer's particles in reach or only those above it; a layer that lies wholly at or below
  // the row is passed over.
  const std::size_t cells = grid_.cell_count();
  struct Scan {
    std::uint32_t first_cell;
    bool all;
  };
  Scan scans[4];
  int scan_count = 0;
  for (int layer = 0; layer < layers_; ++layer) {
    const bool border_layer = layer >= per_class_;
    const bool frozen_layer = skip_frozen_ && layer % per_class_ == 1;
    if ((border_layer && !border_row) || (frozen_row && frozen_layer)) continue;
    const bool all = border_row && !border_layer;
    const auto first_cell = static_cast<std::uint32_t>(static_cast<std::size_t>(layer) * cells);
    if (!all && cell_start_[first_cell + cells] <= i + 1) continue;
    scans[scan_count++] = {first_cell, all};
  }
  int ci, cj, ck;
  grid_.coords(grid_.cell_of(p.x[i]), ci, cj, ck);
  const Vec3 xi = p.x[i];
  const double ri = p.radius[i];
  const double* x = &p.x.data()->x;
  // Room for `more` entries after the first `count` (the filter writes up to 4 beyond its hits).
  auto room = [&](std::size_t more) {
    if (nbr.size() < count + more) resize_with_headroom(nbr, count + more);
  };
  auto filter = [&](std::uint32_t lo, std::uint32_t hi) {
    if (lo >= hi) return;
    room(hi - lo + 4);
    count += near_(x, p.radius.data(), lo, hi, &xi.x, ri, skin_, period_z_, nbr.data() + count);
  };
  // Cells in increasing index order and particles in increasing order within a cell: each row
  // comes out sorted by partner index within each layer without a sort.
  // Periodic in z (axially periodic cylinder): the z neighbours of the end cells wrap and
  // distances use the nearest image. The three wrapped cells are distinct (nz >= 3, checked at
  // construction), so every pair is still found exactly once.
  const int c_lo = period_z_ > 0 ? ck - 1 : std::max(ck - 1, 0);
  const int c_hi = period_z_ > 0 ? ck + 1 : std::min(ck + 1, grid_.nz() - 1);
  // z is the grid's fastest index, so the cells (a, b, c_lo..c_hi) of one layer hold consecutive
  // particles, and ghosts placed in cell order too: a row that does not wrap filters the column's
  // three cells of each layer, and of the ghosts, as one range each (a third of the filter calls
  // and of their one-at-a-time remainders). A border row's pairs then come column by column, not
  // cell by cell (the same pairs in another order); on 16 ranks of the R35 bed, where most rows
  // are border rows, the cell-by-cell scan made a border row cost 2.6 times a serial one. The
  // cell-by-cell path below is left to rows that wrap, frozen border rows and ghosts not in cell
  // order.
  const bool ghost_columns = with_ghosts && ghosts_in_cell_order_ && !frozen_row;
  if ((!with_ghosts || ghost_columns) && c_lo >= 0 && c_hi < grid_.nz()) {
    for (int a = std::max(ci - 1, 0); a <= std::min(ci + 1, grid_.nx() - 1); ++a)
      for (int b = std::max(cj - 1, 0); b <= std::min(cj + 1, grid_.ny() - 1); ++b) {
        for (int s = 0; s < scan_count; ++s) {
          const std::uint32_t lo = cell_start_[scans[s].first_cell + grid_.index(a, b, c_lo)];
          const std::uint32_t hi = cell_start_[scans[s].first_cell + grid_.index(a, b, c_hi) + 1];
          filter(scans[s].all ? lo : std::max<std::uint32_t>(lo, i + 1), hi);
        }
        if (ghost_columns) {
          const std::uint32_t g0 = ghost_start_[grid_.index(a, b, c_lo)];
          const std::uint32_t g1 = ghost_start_[grid_.index(a, b, c_hi) + 1];
          if (g0 < g1) filter(ghost_of_cell_[g0], ghost_of_cell_[g0] + (g1 - g0));
        }
      }
    return count;
  }
  for (int a = std::max(ci - 1, 0); a <= std::min(ci + 1, grid_.nx() - 1); ++a)
    for (int b = std::max(cj - 1, 0); b <= std::min(cj + 1, grid_.ny() - 1); ++b)
      for (int cc = c_lo; cc <= c_hi; ++cc) {
        const int c = (cc + grid_.nz()) % grid_.nz();
        const std::uint32_t cell = grid_.index(a, b, c);
        for (int s = 0; s < scan_count; ++s) {
          const std::uint32_t lo = cell_start_[scans[s].first_cell + cell];
          const std::uint32_t hi = cell_start_[scans[s].first_cell + cell + 1];
          filter(scans[s].all ? lo : std::max<std::uint32_t>(lo, i + 1), hi);
        }
        if (with_ghosts && ghosts_in_cell_order_ && !frozen_row) {
          // (ghost_of_cell_ is then n_local, n_local + 1, ...: the cell's ghosts are one range.)
          const std::uint32_t g0 = ghost_start_[cell], g1 = ghost_start_[cell + 1];
          if (g0 < g1) filter(ghost_of_cell_[g0], ghost_of_cell_[g0] + (g1 - g0));
        } else if (with_ghosts)
          for (std::uint32_t g = ghost_start_[cell]; g < ghost_start_[cell + 1]; ++g) {
            const std::uint32_t j = ghost_of_cell_[g];
            if (frozen_row && p.bulk_state[j] < 0) continue;
            room(1);
            count += near_filter_plain(x, p.radius.data(), j, j + 1, &xi.x, ri, skin_, period_z_,
                                       nbr.data() + count);
          }
      }
  return count;
}

void VerletList::keep_live_springs(std::size_t rows) {
  const std::size_t w = static_cast<std::size_t>(layout_.width);
  const std::size_t pairs = start[rows];
  std::size_t live = 0;
  for (std::size_t k = 0; k < pairs; ++k) live += is_live(history.data() + w * k, layout_.width);
  resize_discarding(old_start_, rows + 1);
  resize_discarding(old_nbr_, live);
  resize_discarding(old_history_, w * live);
  std::size_t at = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    old_start_[i] = static_cast<std::uint32_t>(at);
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
      const double* h = history.data() + w * k;
      if (!is_live(h, layout_.width)) continue;
      old_nbr_[at] = nbr[k];
      for (std::size_t d = 0; d < w; ++d) old_history_[w * at + d] = h[d];
      ++at;
    }
  }
  old_start_[rows] = static_cast<std::uint32_t>(at);
}

std::int64_t VerletList::carry_spring(std::uint32_t row, std::uint32_t partner, bool flip,
                                      double* to) const {
  const std::size_t w = static_cast<std::size_t>(layout_.width);
  for (std::uint32_t q = old_start_[row]; q < old_start_[row + 1]; ++q)
    if (old_nbr_[q] == partner) {
      const double* from = old_history_.data() + w * q;
      for (std::size_t d = 0; d < w; ++d)
        to[d] = flip ? layout_.other_side(static_cast<int>(d), from[d]) : from[d];
      return q;
    }
  return -1;
}

void VerletList::keep_springs(const Particles& p, std::size_t n_local) {
  keep_live_springs(n_local);
  kept_owned_ = n_local;
  kept_id_.assign(p.id.begin(), p.id.end());
  kept_x_.assign(p.x.begin(), p.x.begin() + static_cast<std::ptrdiff_t>(n_local));
  kept_index_.assign(kept_id_.data(), kept_id_.size());
  carry_kept_ = true;
}

std::vector<SavedSpring> VerletList::springs_leaving(const Particles& p, std::size_t n_local,
                                                     const ContactHistory* dormant) const {
  std::vector<std::uint8_t> stays(kept_owned_, 0);
  for (std::size_t i = 0; i < n_local; ++i) {
    const std::uint32_t k = kept_index_.index_of(p.id[i]);
    if (k < kept_owned_) stays[k] = 1;
  }
  const std::size_t w = static_cast<std::size_t>(layout_.width);
  ContactHistory out(layout_);
  for (std::size_t a = 0; a < kept_owned_; ++a)
    for (std::uint32_t q = old_start_[a]; q < old_start_[a + 1]; ++q) {
      const std::uint32_t b = old_nbr_[q];
      if (stays[a] && (b >= kept_owned_ || stays[b])) continue;
      out.save(kept_id_[a], kept_id_[b], old_history_.data() + w * q, kept_x_[a]);
    }
  std::vector<SavedSpring> leaving = out.take_records();
  if (!dormant) return leaving;
  // A dormant spring is held by every rank that owns one of its particles (build_with_ghosts):
  // it travels when one of them leaves, to the ranks near it, where the new owner keeps it.
  // (A set of ids asked per record: a rank holds ~1 dormant spring per frozen particle.)
  const IdSet left([&](auto mark) {
    for (std::size_t a = 0; a < kept_owned_; ++a)
      if (!stays[a]) mark(kept_id_[a]);
  });
  if (left.empty()) return leaving;
  for (const SavedSpring& r : dormant->records())
    if (left(r.lo) || left(r.hi)) leaving.push_back(r);
  return leaving;
}

void VerletList::fill_rows() {
  resize_discarding(row, nbr.size());
  const std::size_t n = start.empty() ? 0 : start.size() - 1;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) row[k] = static_cast<std::uint32_t>(i);
}

void VerletList::sort(Particles& p, bool frozen_last, const std::vector<std::uint8_t>* border) {
  skip_frozen_ = frozen_last;
  per_class_ = frozen_last ? 2 : 1;
  layers_ = CellGrid::layer_count(border != nullptr, frozen_last);
  grid_.sort(p.x, perm_, cell_start_, frozen_last ? p.bulk_state.data() : nullptr,
             border ? border->data() : nullptr);
  p.permute(perm_);
  // The first border particle's index (without flags no row is known to be free of ghosts).
  interior_rows_ = border ? cell_start_[per_class_ * grid_.cell_count()] : 0;
}

namespace {
// Whether record k of `from` stays dormant: no pair took it, it is the one lookups find for its
// pair, and one of its particles is this rank's.
template <class Mine>
bool stays_dormant(const ContactHistory& from, const std::vector<std::uint8_t>& taken,
                   const Mine& mine, std::size_t k) {
  const SavedSpring& r = from.records()[k];
  return !taken[k] && (mine(r.lo) || mine(r.hi)) && from.indexed(k);
}

// `more` after `records`, with an eighth of room to spare where they must grow, and memory given
// back where they hold over a quarter more than they keep (the records taken were every spring of
// a restart, or the bed thawed): a rank holds about one dormant spring per frozen particle, 88
// bytes each, not to be copied once more per rebuild.
void append_with_room(std::vector<SavedSpring>& records, const std::vector<SavedSpring>& more) {
  const std::size_t size = records.size() + more.size();
  if (records.capacity() < size || records.capacity() > size + size / 4 + 16) {
    std::vector<SavedSpring> fit;
    fit.reserve(size + size / 8);
    fit.assign(records.begin(), records.end());
    records.swap(fit);
  }
  records.insert(records.end(), more.begin(), more.end());
}

// The dormant springs after a rebuild: every record of `from` that no pair of the new list took
// (`taken`), is the one lookups find for its pair, and has a particle `mine` says is this rank's,
// then `more` (pairs that left the list at it). The records are taken from `from` and kept where
// they lie.
template <class Mine>
std::vector<SavedSpring> keep_untaken(ContactHistory& from, const std::vector<std::uint8_t>& taken,
                                      const Mine& mine, const std::vector<SavedSpring>& more) {
  std::vector<std::uint8_t> keep(from.records().size(), 0);
  for (std::size_t k = 0; k < keep.size(); ++k) keep[k] = stays_dormant(from, taken, mine, k);
  std::vector<SavedSpring> kept = from.take_records();
  std::size_t count = 0;
  for (std::size_t k = 0; k < kept.size(); ++k)
    if (keep[k]) kept[count++] = kept[k];
  kept.resize(count);
  append_with_room(kept, more);
  return kept;
}

// The dormant springs of `records` that a pair of the new list may take: those with a particle
// that moves here (a row of `p` with bulk_state >= 0, ghosts included) or with one of the ids of
// `also` (springs that arrived, which may be copies of them). A list holds no pair of two frozen
// particles, so every other record stays dormant whatever the list: only these are indexed and
// looked up, a few percent of a rank's records on a flowing bed (indexing them all at every
// rebuild was ~3% of a rigid step; docs/performance.md). They are moved out of `records` in their
// order; the others stay, in theirs, where `mine` says one of their particles is this rank's (the
// others left with it: springs_leaving sent them on; a list has no row for them).
template <class Mine>
std::vector<SavedSpring> take_waking(std::vector<SavedSpring>& records, const Particles& p,
                                     const std::vector<SavedSpring>& also, const Mine& mine) {
  const IdSet wanted([&](auto mark) {
    for (std::size_t i = 0; i < p.size(); ++i)
      if (p.bulk_state[i] >= 0) mark(p.id[i]);
    for (const SavedSpring& r : also) mark(r.lo), mark(r.hi);
  });
  // Which leave (to wake, or dropped), found first: the waking ones are then copied once into
  // room for them and the springs that arrived (at a segment change every record wakes: grown by
  // doubling, they would hold the store up to four times over), and the records after the first
  // to leave are moved down.
  std::vector<std::uint32_t> leave;
  std::vector<std::uint8_t> wakes;
  std::size_t waking_count = 0;
  for (std::size_t k = 0; k < records.size(); ++k) {
    const SavedSpring& r = records[k];
    const bool wake = wanted(r.lo) || wanted(r.hi);
    if (!wake && (mine(r.lo) || mine(r.hi))) continue;  // it sleeps on
    leave.push_back(static_cast<std::uint32_t>(k));
    wakes.push_back(wake);
    waking_count += wake;
  }
  std::vector<SavedSpring> waking;
  waking.reserve(waking_count + also.size());
  for (std::size_t m = 0; m < leave.size(); ++m)
    if (wakes[m]) waking.push_back(records[leave[m]]);
  std::size_t to = leave.empty() ? records.size() : leave.front();
  for (std::size_t k = to, m = 0; k < records.size(); ++k) {
    if (m < leave.size() && leave[m] == k) {
      ++m;
      continue;
    }
    records[to++] = records[k];
  }
  records.resize(to);
  return waking;
}

// keep_untaken from records that stay the caller's (a restart's): only those kept are copied.
template <class Mine>
std::vector<SavedSpring> copy_untaken(const ContactHistory& from,
                                      const std::vector<std::uint8_t>& taken, const Mine& mine,
                                      const std::vector<SavedSpring>& more) {
  std::vector<SavedSpring> kept;
  for (std::size_t k = 0; k < from.records().size(); ++k)
    if (stays_dormant(from, taken, mine, k)) kept.push_back(from.records()[k]);
  kept.insert(kept.end(), more.begin(), more.end());
  return kept;
}
}  // namespace

void VerletList::ghost_order(const Particles& p, std::size_t n_local,
                             std::vector<std::uint32_t>& order) const {
  const std::size_t cells = grid_.cell_count(), n = p.size() - n_local;
  std::vector<std::uint32_t> cell(n), first(cells + 1, 0);
  for (std::size_t g = 0; g < n; ++g) {
    cell[g] = grid_.cell_of(p.x[n_local + g]);
    ++first[cell[g] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) first[c + 1] += first[c];
  order.resize(n);
  for (std::size_t g = 0; g < n; ++g) order[first[cell[g]]++] = static_cast<std::uint32_t>(g);
}

void VerletList::build_with_ghosts(const Particles& p, std::size_t n_local, ContactHistory& saved,
                                   ContactHistory* dormant) {
  // Bin the ghosts by cell without moving them (the refresh writes each where it lies; placed in
  // cell order by ghost_order() they are one range per cell).
  const std::size_t cells = grid_.cell_count();
  ghost_start_.assign(cells + 1, 0);
  ghost_of_cell_.resize(p.size() - n_local);
  std::vector<std::uint32_t> cell(p.size() - n_local);
  for (std::size_t g = n_local; g < p.size(); ++g) {
    cell[g - n_local] = grid_.cell_of(p.x[g]);
    ++ghost_start_[cell[g - n_local] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) ghost_start_[c + 1] += ghost_start_[c];
  std::vector<std::uint32_t> fill(ghost_start_.begin(), ghost_start_.end() - 1);
  for (std::size_t g = n_local; g < p.size(); ++g)
    ghost_of_cell_[fill[cell[g - n_local]]++] = static_cast<std::uint32_t>(g);
  ghosts_in_cell_order_ = true;
  for (std::size_t k = 0; k < ghost_of_cell_.size(); ++k)
    ghosts_in_cell_order_ = ghosts_in_cell_order_ && ghost_of_cell_[k] == n_local + k;

  start.assign(n_local + 1, 0);
  std::size_t count = 0;
  for (std::size_t i = 0; i < n_local; ++i) {
    start[i] = static_cast<std::uint32_t>(count);
    // An interior row's particle is farther than r_i + r_max + skin from every other rank's
    // domain (Domain::mark_border), so no ghost is within its cutoff r_i + r_j + skin.
    count = add_row(p, i, i >= interior_rows_, count);
    if (newton_ && i >= interior_rows_) {  // the ghosts whose pair the other rank computes go
      std::size_t kept = start[i];
      for (std::size_t k = start[i]; k < count; ++k) {
        const std::uint32_t j = nbr[k];
        if (j < n_local || computes_border_pair(p.id[i], p.id[j])) nbr[kept++] = j;
      }
      count = kept;
    }
  }
  nbr.resize(count);
  start[n_local] = static_cast<std::uint32_t>(count);
  fill_rows();
  const std::size_t w = static_cast<std::size_t>(layout_.width);
  resize_discarding(history, w * nbr.size());
  std::fill(history.begin(), history.end(), 0.0);
  // The rigid bulk: the rank's own particles (a dormant spring stays with the ranks that own one
  // of its two), and its dormant springs that a pair of this list may take, which go ahead of the
  // springs that arrived (a pair's first record is the one found: the rank's own); the others
  // sleep on, where they lie.
  const IdSet mine([&](auto mark) {
    if (dormant)
      for (std::size_t i = 0; i < n_local; ++i) mark(p.id[i]);
  });
  std::vector<SavedSpring> sleeping;
  if (dormant) {
    sleeping = dormant->take_records();
    std::vector<SavedSpring> looked_up = take_waking(sleeping, p, saved.records(), mine);
    if (!looked_up.empty()) {
      const std::vector<SavedSpring>& arrived = saved.records();
      looked_up.insert(looked_up.end(), arrived.begin(), arrived.end());
      saved.set_records(std::move(looked_up));
    }
  }
  std::vector<std::uint8_t> taken(dormant ? saved.records().size() : 0, 0);
  const bool carry = carry_kept_;
  carry_kept_ = false;
  // The rigid bulk: the ids with a record in `saved` (none otherwise).
  const IdSet has_records = dormant ? ids_with_records(saved.records()) : IdSet([](auto) {});
  // Which kept springs a pair of the new list took (the rigid bulk: the others may go dormant).
  std::vector<std::uint8_t> carried;
  if (carry) {
    // Each particle's row before the migration (IdIndex::kAbsent: it was not on this rank). The
    // old list held every pair with an owned particle, so a pair with a particle owned before
    // has its spring there (in the row of either) or had none; a pair of two particles new to
    // this rank (one of them arrived) finds it among the records that came with them. With
    // Newton across borders the old list held a border pair only where its rank computed it
    // (the owner of the pair's deciding particle, computes_border_pair): a pair whose deciding
    // particle arrived looks among the records too (its old rank sent the spring, as that
    // particle left it), whichever rank held its other particle.
    // The rigid bulk (Newton off) left out the pairs of two frozen particles: their springs are
    // in `saved` with this rank's other dormant ones, and a pair found in the old list is looked
    // up there too where it can be, so that a copy that arrived with a particle is not kept as
    // dormant beside the spring the pair took.
    const std::uint32_t owned_before = static_cast<std::uint32_t>(kept_owned_);
    const std::uint32_t absent = IdIndex::kAbsent;
    std::vector<std::uint32_t> before(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) before[i] = kept_index_.index_of(p.id[i]);
    if (dormant) carried.assign(old_nbr_.size(), 0);
    const bool arrived = !saved.records().empty();
    for (std::size_t i = 0; i < n_local; ++i) {
      const std::uint32_t a = before[i];
      for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
        const std::uint32_t b = before[nbr[k]];
        double* to = history.data() + w * k;
        const bool deciding_arrived =
            newton_ && (computes_border_pair(p.id[i], p.id[nbr[k]]) ? a : b) >= owned_before;
        const bool held = (a < owned_before || b < owned_before) && !deciding_arrived;
        std::int64_t q = -1;
        if (held && a < owned_before && b != absent) q = carry_spring(a, b, false, to);
        if (held && q < 0 && b < owned_before && a != absent) q = carry_spring(b, a, true, to);
        if (!dormant) {
          if (!held && arrived) saved.find(p.id[i], p.id[nbr[k]], to);
          continue;
        }
        if (q >= 0) carried[static_cast<std::size_t>(q)] = 1;
        if (!has_records(p.id[i]) || !has_records(p.id[nbr[k]])) continue;
        HistoryValues found{};
        const std::int64_t at = saved.find(p.id[i], p.id[nbr[k]], q >= 0 ? found.data() : to);
        if (at >= 0) taken[static_cast<std::size_t>(at)] = 1;
      }
    }
  } else {
    for (std::size_t i = 0; i < n_local; ++i)
      for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
        const std::int64_t at = saved.find(p.id[i], p.id[nbr[k]], history.data() + w * k);
        if (dormant && at >= 0) taken[static_cast<std::size_t>(at)] = 1;
      }
  }
  if (dormant) {
    // A record no pair took is a dormant pair's (a live spring is a touching pair's, within every
    // rank's reach of its particles) or another rank's pair routed here: this rank keeps those
    // with one of its own particles. So does a kept spring that no pair took: its pair's
    // particles are both frozen now (or it left with one of them, and is not this rank's).
    ContactHistory now_dormant(layout_);
    if (carry) {
      HistoryValues scratch{};
      for (std::size_t a = 0; a < kept_owned_; ++a)
        for (std::uint32_t q = old_start_[a]; q < old_start_[a + 1]; ++q) {
          const std::int64_t id_a = kept_id_[a], id_b = kept_id_[old_nbr_[q]];
          if (carried[q] || !(mine(id_a) || mine(id_b))) continue;
          // A copy of it that arrived (its pair froze as a particle of it left another rank) is
          // dropped: the rank's own spring first, as when every spring was saved by id.
          if (has_records(id_a) && has_records(id_b)) {
            const std::int64_t at = saved.find(id_a, id_b, scratch.data());
            if (at >= 0) taken[static_cast<std::size_t>(at)] = 1;
          }
          now_dormant.save(id_a, id_b, old_history_.data() + w * q, kept_x_[a]);
        }
    }
    // (Indexed at the next rebuild, as far as looked up.)
    append_with_room(sleeping, keep_untaken(saved, taken, mine, now_dormant.records()));
    dormant->set_records_unindexed(std::move(sleeping));
  }
  x_ref_.assign(p.x.begin(), p.x.begin() + static_cast<std::ptrdiff_t>(n_local));
  ++builds;
}

void VerletList::rebuild(Particles& p, const ContactHistory* saved, ContactHistory* dormant) {
  const std::size_t n = p.size();
  // Keep the old list: within one process the histories are carried over by old index (a short
  // scan of one old row), which is far cheaper than matching global ids. The id-keyed
  // ContactHistory is used where indices mean nothing: restarts (and, later, rank migration).
  const bool carry_local = saved == nullptr && old_start_capacity_ok(n);
  const std::size_t w = static_cast<std::size_t>(layout_.width);
  const std::size_t previous = nbr.size();
  // The rigid bulk: the old list's pairs whose particles are both frozen now leave the list; their
  // springs join the dormant ones (old indices: before the sort).
  std::vector<SavedSpring> kept;
  if (dormant && !saved && old_start_capacity_ok(n)) {
    ContactHistory leaving(layout_);
    for (std::size_t i = 0; i < n; ++i) {
      if (p.bulk_state[i] >= 0) continue;
      for (std::uint32_t k = start[i]; k < start[i + 1]; ++k)
        if (p.bulk_state[nbr[k]] < 0)
          leaving.save(p.id[i], p.id[nbr[k]], history.data() + w * k, p.x[i]);
    }
    kept = leaving.take_records();
  }
  // The particles are sorted first: the permutation's scratch column then never coincides with
  // the copy of the old springs below (the rebuild's peak is the lower for it).
  skip_frozen_ = dormant != nullptr;
  per_class_ = skip_frozen_ ? 2 : 1;
  layers_ = CellGrid::layer_count(false, skip_frozen_);
  interior_rows_ = n;  // one rank: no ghosts
  grid_.sort(p.x, perm_, cell_start_, dormant ? p.bulk_state.data() : nullptr);
  p.permute(perm_);
  if (carry_local) {
    // Only the live springs of the old list are kept (a pair whose spring is zero carries
    // nothing, as in ContactHistory::save): about the touching pairs, 60% of the list on a
    // flowing bed, where a copy of the whole list held its memory twice.
    keep_live_springs(n);
  }

  start.assign(n + 1, 0);
  resize_discarding(nbr, previous + previous / 8 + 16);
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    start[i] = static_cast<std::uint32_t>(count);
    count = add_row(p, i, false, count);
  }
  nbr.resize(count);
  start[n] = static_cast<std::uint32_t>(count);
  fill_rows();

  resize_discarding(history, w * nbr.size());
  std::fill(history.begin(), history.end(), 0.0);
  if (carry_local) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
        // Old indices of the pair; the old list holds its live spring in the row of the smaller
        // one.
        const std::uint32_t a = perm_[i], b = perm_[nbr[k]];
        if (a < b)
          carry_spring(a, b, false, history.data() + w * k);
        else
          carry_spring(b, a, true, history.data() + w * k);
      }
  } else if (saved) {  // restart (or, later, migration): match by global id
    for (std::size_t i = 0; i < n; ++i)
      for (std::uint32_t k = start[i]; k < start[i + 1]; ++k)
        saved->lookup(p.id[i], p.id[nbr[k]], history.data() + w * k);
  }  // else: the first build, nothing to carry
  if (dormant) {
    // A pair back in the list (one of its particles thawed) takes its dormant spring; on a restart
    // `saved` holds the dormant springs too. What no pair took stays dormant (one process: every
    // particle is its own).
    // (Kept unindexed between rebuilds: only those a pair may take are indexed, the others sleep
    // on where they lie.)
    std::vector<SavedSpring> sleeping;
    if (!saved) {
      sleeping = dormant->take_records();
      dormant->set_records(take_waking(sleeping, p, {}, [](std::int64_t) { return true; }));
    }
    const ContactHistory& from = saved ? *saved : *dormant;
    std::vector<std::uint8_t> taken(from.records().size(), 0);
    const IdSet listed = ids_with_records(from.records());
    for (std::size_t i = 0; i < n; ++i) {
      if (!listed(p.id[i])) continue;
      for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
        double* h = history.data() + w * k;
        if (!listed(p.id[nbr[k]])) continue;
        if (!saved && is_live(h, layout_.width)) continue;  // carried from the old list
        const std::int64_t at = from.find(p.id[i], p.id[nbr[k]], h);
        if (at >= 0) taken[static_cast<std::size_t>(at)] = 1;
      }
    }
    auto all = [](std::int64_t) { return true; };
    if (saved) {
      dormant->set_records_unindexed(copy_untaken(*saved, taken, all, kept));
    } else {
      append_with_room(sleeping, keep_untaken(*dormant, taken, all, kept));
      dormant->set_records_unindexed(std::move(sleeping));
    }
  }
  x_ref_ = p.x;
  ++builds;
}

}  // namespace tumble::neighbor
