#include "parallel/domain.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <stdexcept>
#include <string>

#include "base/environment.hpp"
#include "base/error.hpp"
#include "parallel/particle_pack.hpp"
#include "parallel/wide_bins.hpp"

namespace tumble::parallel {

std::vector<double> exchange(MPI_Comm comm, const std::vector<std::vector<double>>& out,
                             std::vector<int>& from) {
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<int> to(size), sd(size), rd(size);
  from.assign(size, 0);
  for (int r = 0; r < size; ++r) to[r] = static_cast<int>(out[r].size());
  MPI_Alltoall(to.data(), 1, MPI_INT, from.data(), 1, MPI_INT, comm);
  std::vector<double> flat;
  for (int r = 0; r < size; ++r) {
    sd[r] = static_cast<int>(flat.size());
    flat.insert(flat.end(), out[r].begin(), out[r].end());
  }
  std::exclusive_scan(from.begin(), from.end(), rd.begin(), 0);
  std::vector<double> in(static_cast<std::size_t>(rd.back()) + from.back());
  MPI_Alltoallv(flat.data(), to.data(), sd.data(), MPI_DOUBLE, in.data(), from.data(), rd.data(),
                MPI_DOUBLE, comm);
  return in;
}

Domain::Domain(MPI_Comm comm, const Box& root, double period_z, double rebalance_threshold)
    : root_(root), period_z_(period_z), threshold_(rebalance_threshold) {
  MPI_Comm_dup(comm, &comm_);
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
  // The environment's halo settings, agreed by all ranks in one reduction: the window if every
  // rank may use it; the node split only if every rank asks for the same (the split is
  // collective), else refused on all of them (freeing what the destructor will not).
  const int node_ranks = halo_node_ranks_from_environment();  // (-1: a bad value)
  int agreed[3] = {env_switch_on("TUMBLE_REFRESH_MESSAGES") ? 0 : 1, node_ranks, -node_ranks};
  MPI_Allreduce(MPI_IN_PLACE, agreed, 3, MPI_INT, MPI_MIN, comm_);
  const int shared = agreed[0];
  if (agreed[1] < 0 || agreed[1] != -agreed[2]) {
    MPI_Comm_free(&comm_);
    // (a campaign fails the case once, as bad input: no retry helps; the commands refuse a bad
    // value at start, so this is a value that differs between ranks)
    throw InputError(halo_node_ranks_error());
  }
  send_.resize(size_);
  recv_rows_.assign(size_, 0);
  write_at_.assign(size_, 0);
  read_at_.assign(size_, nullptr);
  reverse_write_at_.assign(size_, kNoOffset);
  reverse_read_at_.assign(size_, nullptr);
  node_rank_.assign(size_, -1);
  if (size_ > 1 && shared) {
    // (Every rank takes part: the split is collective over comm_.)
    MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node_comm_);
    if (node_ranks > 0) {  // nodes of node_ranks ranks each, cut from the real ones
      int node_rank = 0;
      MPI_Comm_rank(node_comm_, &node_rank);
      MPI_Comm part;
      MPI_Comm_split(node_comm_, node_rank / node_ranks, node_rank, &part);
      MPI_Comm_free(&node_comm_);
      node_comm_ = part;
    }
    MPI_Group all, node;
    MPI_Comm_group(comm_, &all);
    MPI_Comm_group(node_comm_, &node);
    std::vector<int> ranks(size_);
    std::iota(ranks.begin(), ranks.end(), 0);
    MPI_Group_translate_ranks(all, size_, ranks.data(), node, node_rank_.data());
    for (int& r : node_rank_)
      if (r == MPI_UNDEFINED) r = -1;
    MPI_Group_free(&all);
    MPI_Group_free(&node);
  }
}

Domain::~Domain() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  // (Collective over the node, like the communicators' frees: a case's ranks end it together,
  // failures included: the health check throws on every rank at once.)
  free_window();
  if (node_comm_ != MPI_COMM_NULL) MPI_Comm_free(&node_comm_);
  if (comm_ != MPI_COMM_NULL) MPI_Comm_free(&comm_);
}

void Domain::free_window() {
  if (window_ == MPI_WIN_NULL) return;
  MPI_Win_unlock_all(window_);
  MPI_Win_free(&window_);
  segment_ = nullptr;
  segment_doubles_ = 0;
}

void Domain::place_shared_rows() {
  shared_out_ = false;
  shared_sources_ = 0;
  if (node_comm_ == MPI_COMM_NULL) return;
  // Two buffers of its rows for each neighbour of the node, one after the other; with the
  // ghosts' sums going back (reverse_through_window), two of those for each neighbour of the node
  // it holds ghosts of. offset_to[2 r], [2 r + 1]: where rank r reads them in this segment.
  std::size_t need = 0;
  std::vector<long long> offset_to(2 * size_, -1), offset_from(2 * size_, -1);
  for (int r = 0; r < size_; ++r) {
    if (r == rank_ || node_rank_[r] < 0 || send_[r].empty()) continue;
    write_at_[r] = need;
    offset_to[2 * r] = static_cast<long long>(need);
    need += 2 * send_[r].size() * kMotionDoubles;
    shared_out_ = true;
  }
  for (int r = 0; r < size_ && reverse_window_; ++r) {
    reverse_write_at_[r] = kNoOffset;
    if (r == rank_ || node_rank_[r] < 0 || recv_rows_[r] == 0) continue;
    reverse_write_at_[r] = need;
    offset_to[2 * r + 1] = static_cast<long long>(need);
    need += 2 * static_cast<std::size_t>(recv_rows_[r]) * kReverseDoubles;
  }
  // The window is the node's (allocated collectively): grown, with headroom, when any rank's
  // segment is too small for its rows.
  int grow = need > segment_doubles_ ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &grow, 1, MPI_INT, MPI_MAX, node_comm_);
  if (grow) {
    // (Never smaller than before: a rank whose rows shrank keeps its room.)
    const std::size_t doubles = std::max<std::size_t>({need + need / 8, segment_doubles_, 16});
    free_window();
    MPI_Info info;
    MPI_Info_create(&info);
    MPI_Info_set(info, "alloc_shared_noncontig", "true");  // each segment near its own rank
    MPI_Win_allocate_shared(static_cast<MPI_Aint>(doubles * sizeof(double)), sizeof(double), info,
                            node_comm_, &segment_, &window_);
    MPI_Info_free(&info);
    MPI_Win_lock_all(MPI_MODE_NOCHECK, window_);
    segment_doubles_ = doubles;
  }
  MPI_Alltoall(offset_to.data(), 2, MPI_LONG_LONG, offset_from.data(), 2, MPI_LONG_LONG, comm_);
  for (int r = 0; r < size_; ++r) {
    read_at_[r] = reverse_read_at_[r] = nullptr;
    const bool rows = offset_from[2 * r] >= 0 && recv_rows_[r] > 0;
    const bool sums = offset_from[2 * r + 1] >= 0 && !send_[r].empty();
    if (!rows && !sums) continue;
    MPI_Aint bytes = 0;
    int unit = 0;
    double* base = nullptr;
    MPI_Win_shared_query(window_, node_rank_[r], &bytes, &unit, &base);
    if (sums) reverse_read_at_[r] = base + offset_from[2 * r + 1];
    if (!rows) continue;
    read_at_[r] = base + offset_from[2 * r];
    ++shared_sources_;
  }
}

void Domain::weigh(const Particles& p) {
  weight_.resize(p.size());
  const bool states = !p.bulk_state.empty();  // empty: a dynamic run, nothing frozen
  for (std::size_t i = 0; i < p.size(); ++i)
    weight_[i] = states && p.bulk_state[i] == -1 ? frozen_weight_ : 1.0;
}

double Domain::measure_imbalance() const {
  double n = 0;
  for (double w : weight_) n += w;
  double mx = 0, sum = 0;
  MPI_Allreduce(&n, &mx, 1, MPI_DOUBLE, MPI_MAX, comm_);
  MPI_Allreduce(&n, &sum, 1, MPI_DOUBLE, MPI_SUM, comm_);
  return sum > 0 ? mx / (sum / size_) : 1.0;
}

void Domain::migrate(Particles& p) {
  std::vector<std::vector<double>> out(size_);
  std::vector<std::uint32_t> keep;
  keep.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int r = tree_.owner(p.x[i]);
    if (r == rank_)
      keep.push_back(static_cast<std::uint32_t>(i));
    else
      pack_state(p, i, out[r]);
  }
  std::vector<int> from;
  const std::vector<double> in = exchange(comm_, out, from);
  if (keep.size() != p.size()) {
    p.permute(keep);  // the kept ones first, in order
    p.resize(keep.size());
  }
  unpack_state(in.data(), in.size() / kStateDoubles, p);
}

void Domain::distribute(Particles& p, std::vector<neighbor::SavedSpring>& records, double reach,
                        int history_width) {
  migrate_owned(p);
  route_records(records, reach, history_width, true);
}

void Domain::adopt_tree(const std::vector<double>& tree) {
  tree_ = RcbTree::from_doubles(root_, tree, size_);
  have_tree_ = true;
}

void Domain::migrate_owned(Particles& p) {
  const double t0 = MPI_Wtime();
  if (!have_tree_) {
    weigh(p);
    tree_ = RcbTree::build(comm_, root_, p.x, p.size(), weight_.data());
    have_tree_ = true;
    ++bisections_;
  }
  migrate(p);
  weigh(p);
  imbalance_ = measure_imbalance();
  if (imbalance_ > threshold_) {  // the bed has moved (or frozen): bisect again where it is now
    tree_ = RcbTree::build(comm_, root_, p.x, p.size(), weight_.data());
    ++bisections_;
    migrate(p);
    weigh(p);
    imbalance_ = measure_imbalance();
  }
  rebuild_seconds_ += MPI_Wtime() - t0;
}

void Domain::route_records(std::vector<neighbor::SavedSpring>& records, double reach,
                           int history_width, bool keep_own) {
  const double t0 = MPI_Wtime();
  // To every rank near the pair (both owners are within `reach` of the anchor).
  std::vector<std::vector<double>> out(size_);
  std::vector<int> near;
  for (const auto& s : records) {
    near.clear();
    tree_.ranks_near(s.anchor, reach, period_z_, near);
    for (int r : near) {
      if (r == rank_) continue;
      neighbor::append_record(s, history_width, out[r]);
    }
  }
  std::vector<int> from;
  const std::vector<double> in = exchange(comm_, out, from);
  const auto row = static_cast<std::size_t>(neighbor::record_doubles(history_width));
  if (!keep_own) records.clear();
  records.reserve(records.size() + in.size() / row);  // (not std::vector's doubling)
  for (std::size_t k = 0; k + row <= in.size(); k += row)
    records.push_back(neighbor::record_from(in.data() + k, history_width));
  rebuild_seconds_ += MPI_Wtime() - t0;
}

void Domain::exchange_ghosts(Particles& p, std::size_t n_local, double reach, std::size_t first) {
  const double t0 = MPI_Wtime();
  std::vector<std::vector<double>> out(size_);
  for (auto& s : send_) s.clear();
  std::vector<int> near, to, scratch;
  // A thin halo: first every wide particle near another rank goes there as centre and radius,
  // so that each rank knows which of its thin particles beyond the thin reach one of them may
  // pair with. (Two more collectives per rebuild; none when the bed has one size.)
  WideBins wide_bins;
  const bool thin = thin_radius_ > 0;
  if (thin) {
    std::vector<std::vector<double>> wide(size_);
    for (std::size_t i = first; i < n_local; ++i) {
      if (p.radius[i] <= thin_radius_) continue;
      near.clear();
      tree_.ranks_near(p.x[i], p.radius[i] + reach, period_z_, near);
      for (int r : near)
        if (r != rank_)
          wide[r].insert(wide[r].end(), {p.x[i][0], p.x[i][1], p.x[i][2], p.radius[i]});
    }
    std::vector<int> from;
    const std::vector<double> in = exchange(comm_, wide, from);
    auto at = in.begin();
    for (int r = 0; r < size_; ++r) {
      wide[r].assign(at, at + from[r]);  // now what rank r sent
      at += from[r];
    }
    wide_bins.assign(wide, thin_radius_ + skin_, period_z_);  // (r_i + skin <= this)
  }
  // Each particle to the ranks it may pair with, in the order of the rows (the ghosts a thin
  // halo leaves out had no pair, so those that arrive keep the full halo's order).
  for (std::size_t i = first; i < n_local; ++i) {
    near.clear();
    tree_.ranks_near(p.x[i], p.radius[i] + reach, period_z_, near);
    const std::vector<int>* targets = &near;
    if (thin && p.radius[i] <= thin_radius_ && near.size() > 1) {
      thin_halo_targets(p, i, near, wide_bins, scratch, to);
      targets = &to;
    }
    for (int r : *targets) {
      if (r == rank_) continue;
      send_[r].push_back(static_cast<std::uint32_t>(i));
      pack_state(p, i, out[r]);
    }
  }
  std::vector<int> from;
  const std::vector<double> in = exchange(comm_, out, from);
  p.resize(n_local);
  unpack_state(in.data(), in.size() / kStateDoubles, p);
  for (int r = 0; r < size_; ++r) recv_rows_[r] = from[r] / kStateDoubles;
  ghost_count_ = refreshed_count_ = static_cast<std::int64_t>(p.size() - n_local);
  ghost_slot_.clear();
  rebuild_seconds_ += MPI_Wtime() - t0;
}

void Domain::thin_halo_targets(const Particles& p, std::size_t i, const std::vector<int>& near,
                               const WideBins& wide, std::vector<int>& scratch,
                               std::vector<int>& to) const {
  // (Margins of 1e-9 keep both tests on the safe side of the list's own rounding.)
  constexpr double kMargin = 1 + 1e-9;
  const Vec3& xi = p.x[i];
  to.clear();
  scratch.clear();
  // Within reach of the rank's thin particles: r_i + r_j + skin <= r_i + thin_radius + skin.
  tree_.ranks_near(xi, (p.radius[i] + thin_radius_ + skin_) * kMargin, period_z_, scratch);
  for (int r : near) {
    if (r == rank_) continue;
    // Beyond it only a wide particle of that rank may pair with it.
    if (std::find(scratch.begin(), scratch.end(), r) != scratch.end() ||
        wide.any_within(r, xi, p.radius[i] + skin_, kMargin))
      to.push_back(r);
  }
}

void Domain::place_ghosts(Particles& p, std::size_t n_local,
                          const std::vector<std::uint32_t>& order) {
  const double t0 = MPI_Wtime();
  for_each_field<field::kAny>(p, [&](const char*, auto& column) {
    if (column.empty()) return;  // (a column the run does not keep)
    using T = typename std::decay_t<decltype(column)>::value_type;
    const std::vector<T> arrived(column.begin() + static_cast<std::ptrdiff_t>(n_local),
                                 column.end());
    for (std::size_t k = 0; k < order.size(); ++k) column[n_local + k] = arrived[order[k]];
  });
  ghost_slot_.resize(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    ghost_slot_[order[k]] = static_cast<std::uint32_t>(k);
  rebuild_seconds_ += MPI_Wtime() - t0;
}

void Domain::keep_used_ghosts(const std::vector<std::uint8_t>* used) {
  const double t0 = MPI_Wtime();
  if (!used) {  // all of them
    place_shared_rows();
    rebuild_seconds_ += MPI_Wtime() - t0;
    return;
  }
  // To each source rank, the places in its send list of the ghosts this rank keeps (in the
  // order they arrived); the kept ghosts' slots in that order become the arrival order.
  const bool placed = !ghost_slot_.empty();
  std::vector<std::vector<double>> keep(size_);
  std::vector<std::uint32_t> slots;
  slots.reserve(used->size());
  std::size_t a = 0;
  for (int r = 0; r < size_; ++r) {
    for (int k = 0; k < recv_rows_[r]; ++k, ++a) {
      const std::uint32_t slot = placed ? ghost_slot_[a] : static_cast<std::uint32_t>(a);
      if (!(*used)[slot]) continue;
      keep[r].push_back(k);
      slots.push_back(slot);
    }
    recv_rows_[r] = static_cast<int>(keep[r].size());
  }
  ghost_slot_ = std::move(slots);
  refreshed_count_ = static_cast<std::int64_t>(ghost_slot_.size());
  std::vector<int> from;
  const std::vector<double> in = exchange(comm_, keep, from);
  const double* at = in.data();
  for (int r = 0; r < size_; ++r) {
    std::vector<std::uint32_t>& out = send_[r];
    for (int q = 0; q < from[r]; ++q) out[q] = out[static_cast<std::size_t>(at[q])];  // (in order)
    out.resize(static_cast<std::size_t>(from[r]));
    at += from[r];
  }
  place_shared_rows();
  rebuild_seconds_ += MPI_Wtime() - t0;
}

double Domain::max_over_ranks(double value) {
  const double t0 = MPI_Wtime();
  refresh_synced_ = refresh_pending_;  // every rank has written its rows: they may be read
  MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MAX, comm_);
  test_seconds_ += MPI_Wtime() - t0;
  return value;
}

void Domain::mark_border(const Particles& p, std::size_t n_local, double reach,
                         std::vector<std::uint8_t>& border) const {
  border.assign(n_local, 0);
  // Another rank's box lies beyond one of this rank's faces that are not the root box's (z's
  // too where z is periodic): a particle farther inside than its reach from each of those is
  // near no other rank, and the tree is asked only about the others. (A margin of 1e-9 of the
  // reach keeps the shortcut on the safe side of the tree's own rounding.)
  const Box& own = tree_.box(rank_);
  Vec3 lo_open, hi_open;  // 1: a face with a neighbour beyond it
  for (int d = 0; d < 3; ++d) {
    const bool wraps = d == 2 && period_z_ > 0;
    lo_open[d] = wraps || own.lo[d] > root_.lo[d] ? 1.0 : 0.0;
    hi_open[d] = wraps || own.hi[d] < root_.hi[d] ? 1.0 : 0.0;
  }
  std::vector<int> near;
  for (std::size_t i = 0; i < n_local; ++i) {
    const double r = (p.radius[i] + reach) * (1 + 1e-9);
    bool inside = true;
    for (int d = 0; d < 3; ++d)
      inside = inside && (lo_open[d] == 0 || p.x[i][d] - own.lo[d] > r) &&
               (hi_open[d] == 0 || own.hi[d] - p.x[i][d] > r);
    if (inside) continue;
    near.clear();
    tree_.ranks_near(p.x[i], p.radius[i] + reach, period_z_, near);
    for (int r_near : near) border[i] |= r_near != rank_;
  }
}

void Domain::begin_refresh(Particles& p, std::size_t n_local, bool skip_frozen) {
  // With the neighbours only: what each sends and receives is fixed until the next rebuild.
  // Rows for the node's ranks go into this rank's segment of the shared window, the others into
  // messages; either way they come in the order the ghosts arrived at the exchange (by source
  // rank), and end_refresh writes each where it now lies (ghost_slot_).
  const double t0 = MPI_Wtime();
  const std::int32_t* state = p.bulk_state.data();
  auto sent = [&](std::size_t i) { return !skip_frozen || state[i] >= 0; };
  refresh_skips_frozen_ = skip_frozen;
  refresh_pending_ = true;
  refresh_synced_ = false;
  const std::size_t turn = refreshes_++ & 1u;  // which of the two buffers (the same on every rank)
  std::size_t total_out = 0;
  for (int r = 0; r < size_; ++r)
    if (!writes_shared(r)) total_out += send_[r].size();
  std::size_t total_in = 0;  // (the rows from the node's ranks are read where they lie)
  for (int r = 0; r < size_; ++r)
    if (read_at_[r] == nullptr) total_in += static_cast<std::size_t>(recv_rows_[r]);
  buf_out_.resize(total_out * kMotionDoubles);
  buf_in_.resize(total_in * kMotionDoubles);
  requests_.clear();
  requests_.reserve(2 * size_);
  std::size_t at = 0, a = 0;  // a: ghosts counted in the order they arrived
  for (int r = 0; r < size_; ++r) {
    if (recv_rows_[r] == 0) continue;
    int rows = recv_rows_[r];  // all of them, unless the frozen are left out
    if (skip_frozen) {
      rows = 0;
      for (const std::size_t end = a + recv_rows_[r]; a < end; ++a)
        rows += sent(n_local + (ghost_slot_.empty() ? a : ghost_slot_[a]));
    }
    if (rows == 0 || read_at_[r] != nullptr) continue;  // (shared: read in end_refresh)
    requests_.emplace_back();
    MPI_Irecv(buf_in_.data() + at, rows * kMotionDoubles, MPI_DOUBLE, r, 7, comm_,
              &requests_.back());
    at += static_cast<std::size_t>(rows) * kMotionDoubles;
  }
  double* o = buf_out_.data();
  for (int r = 0; r < size_; ++r) {
    if (send_[r].empty()) continue;
    const bool shared = writes_shared(r);
    double* begin = shared ? segment_ + write_at_[r] + turn * send_[r].size() * kMotionDoubles : o;
    double* row = begin;
    if (shared) {  // (the neighbour reads them: put_row_streaming)
      for (std::uint32_t i : send_[r])
        if (sent(i)) put_row_streaming<field::kGhostRefresh>(row, p, i);
      continue;
    }
    for (std::uint32_t i : send_[r])
      if (sent(i)) put_row<field::kGhostRefresh>(row, p, i);
    if (row == begin) continue;
    o = row;
    requests_.emplace_back();
    MPI_Isend(begin, static_cast<int>(row - begin), MPI_DOUBLE, r, 7, comm_, &requests_.back());
  }
  if (window_ != MPI_WIN_NULL) {
    // The rows written before the collective that follows (and, on a rank that only reads,
    // its last reads ordered before it: sync, collective, sync on both sides).
    stream_fence();
    MPI_Win_sync(window_);
  }
  refresh_seconds_ += MPI_Wtime() - t0;
}

void Domain::progress(std::vector<MPI_Request>& requests) {
  if (requests.empty()) return;
  const double t0 = MPI_Wtime();
  int done = 0;
  MPI_Testall(static_cast<int>(requests.size()), requests.data(), &done, MPI_STATUSES_IGNORE);
  refresh_seconds_ += MPI_Wtime() - t0;
}

void Domain::end_refresh(Particles& p, std::size_t n_local) {
  const double t0 = MPI_Wtime();
  MPI_Waitall(static_cast<int>(requests_.size()), requests_.data(), MPI_STATUSES_IGNORE);
  requests_.clear();
  if (node_comm_ != MPI_COMM_NULL) {
    // Every rank of the node has written its rows once all have passed a collective since
    // begin_refresh (or this barrier); Win_sync orders this rank's reads after it.
    if (!refresh_synced_) MPI_Barrier(node_comm_);
    if (window_ != MPI_WIN_NULL) MPI_Win_sync(window_);
  }
  refresh_pending_ = refresh_synced_ = false;
  const std::size_t turn = (refreshes_ - 1) & 1u;
  const std::int32_t* state = p.bulk_state.data();
  const double* in = buf_in_.data();
  // Ghosts in the order they arrived (by source rank), each written where it lies.
  const bool placed = !ghost_slot_.empty();
  std::size_t a = 0;
  for (int r = 0; r < size_; ++r) {
    const std::size_t end = a + static_cast<std::size_t>(recv_rows_[r]);
    const double* from =
        read_at_[r] ? read_at_[r] + turn * static_cast<std::size_t>(recv_rows_[r]) * kMotionDoubles
                    : in;
    for (; a < end; ++a) {
      const std::size_t q = n_local + (placed ? ghost_slot_[a] : a);
      if (!refresh_skips_frozen_ || state[q] >= 0) take_row<field::kGhostRefresh>(from, p, q);
    }
    if (!read_at_[r]) in = from;
  }
  refresh_seconds_ += MPI_Wtime() - t0;
}

void Domain::begin_reverse(const Particles& p, std::size_t n_local) {
  const double t0 = MPI_Wtime();
  std::size_t rows_in = 0;
  for (int r = 0; r < size_; ++r) rows_in += send_[r].size();
  reverse_out_.resize((p.size() - n_local) * kReverseDoubles);
  reverse_in_.resize(rows_in * kReverseDoubles);
  reverse_requests_.clear();
  const std::size_t turn = reverses_++ & 1u;  // which of the two buffers (the same on every rank)
  std::size_t at = 0;
  for (int r = 0; r < size_; ++r) {  // the sums of the particles this rank sent to r
    if (send_[r].empty() || reverse_read_at_[r]) continue;  // (shared: read in end_reverse)
    reverse_requests_.emplace_back();
    MPI_Irecv(reverse_in_.data() + at, static_cast<int>(send_[r].size() * kReverseDoubles),
              MPI_DOUBLE, r, 8, comm_, &reverse_requests_.back());
    at += send_[r].size() * kReverseDoubles;
  }
  // Each ghost's sums back to where it came from, in the order it arrived (that rank's send_
  // order): into this rank's segment where the owner is on the node, else a message.
  const bool placed = !ghost_slot_.empty();
  const Vec3* f = p.f.data();
  const Vec3* t = p.t.data();
  double* o = reverse_out_.data();
  std::size_t a = 0;
  for (int r = 0; r < size_; ++r) {
    if (recv_rows_[r] == 0) continue;
    const auto rows = static_cast<std::size_t>(recv_rows_[r]);
    const bool shared = reverse_write_at_[r] != kNoOffset;
    double* begin = shared ? segment_ + reverse_write_at_[r] + turn * rows * kReverseDoubles : o;
    double* w = begin;
    for (const std::size_t end = a + rows; a < end; ++a) {
      const std::size_t q = n_local + (placed ? ghost_slot_[a] : a);
      w[0] = f[q].x, w[1] = f[q].y, w[2] = f[q].z;
      w[3] = t[q].x, w[4] = t[q].y, w[5] = t[q].z;
      w += kReverseDoubles;
    }
    if (shared) continue;
    o = w;
    reverse_requests_.emplace_back();
    MPI_Isend(begin, static_cast<int>(w - begin), MPI_DOUBLE, r, 8, comm_,
              &reverse_requests_.back());
  }
  if (reverse_window_ && window_ != MPI_WIN_NULL) MPI_Win_sync(window_);  // (the rows written)
  refresh_seconds_ += MPI_Wtime() - t0;
}

void Domain::end_reverse(Particles& p) {
  const double t0 = MPI_Wtime();
  MPI_Waitall(static_cast<int>(reverse_requests_.size()), reverse_requests_.data(),
              MPI_STATUSES_IGNORE);
  reverse_requests_.clear();
  if (reverse_window_ && window_ != MPI_WIN_NULL) {
    // Every rank of the node has written its sums once all have passed this barrier (one per
    // step: no collective of the step follows begin_reverse); Win_sync orders the reads after it.
    // The next begin_reverse writes the other buffer, and the one after it this one again only
    // after the next step's rebuild test, which every reader enters after its reads.
    MPI_Barrier(node_comm_);
    MPI_Win_sync(window_);
  }
  const std::size_t turn = (reverses_ - 1) & 1u;
  Vec3* f = p.f.data();
  Vec3* t = p.t.data();
  const double* in = reverse_in_.data();
  for (int r = 0; r < size_; ++r) {
    const double* from =
        reverse_read_at_[r] ? reverse_read_at_[r] + turn * send_[r].size() * kReverseDoubles : in;
    for (const std::uint32_t i : send_[r]) {
      f[i] += Vec3{from[0], from[1], from[2]};
      t[i] += Vec3{from[3], from[4], from[5]};
      from += kReverseDoubles;
    }
    if (!reverse_read_at_[r]) in = from;
  }
  refresh_seconds_ += MPI_Wtime() - t0;
}

namespace {
Particles sorted_by_id(const std::vector<double>& rows) {
  Particles all;
  unpack_state(rows.data(), rows.size() / kStateDoubles, all);
  std::vector<std::uint32_t> order(all.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](std::uint32_t a, std::uint32_t b) { return all.id[a] < all.id[b]; });
  all.permute(order);
  return all;
}
}  // namespace

Particles Domain::gather_all(const Particles& p, std::size_t n_local) const {
  std::vector<double> mine;
  mine.reserve(n_local * kStateDoubles);
  for (std::size_t i = 0; i < n_local; ++i) pack_state(p, i, mine);
  const int n = static_cast<int>(mine.size());
  std::vector<int> counts(size_), displs(size_);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
  std::exclusive_scan(counts.begin(), counts.end(), displs.begin(), 0);
  std::vector<double> all(static_cast<std::size_t>(displs.back()) + counts.back());
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE,
                 comm_);
  return sorted_by_id(all);
}

Particles Domain::id_block(const Particles& p, std::size_t n_local, std::int64_t n_total) const {
  std::vector<std::vector<double>> out(size_);
  for (std::size_t i = 0; i < n_local; ++i) {
    if (p.id[i] < 0 || p.id[i] >= n_total)
      throw std::runtime_error("particle id " + std::to_string(p.id[i]) + " outside 0.." +
                               std::to_string(n_total - 1) + ": ids must be 0..N-1");
    // Rank r holds ids [n r / P, n (r+1) / P): the first r with block_begin(r+1) > id.
    int r = static_cast<int>(p.id[i] * size_ / std::max<std::int64_t>(n_total, 1));
    while (r + 1 < size_ && block_begin(n_total, r + 1, size_) <= p.id[i]) ++r;
    while (r > 0 && block_begin(n_total, r, size_) > p.id[i]) --r;
    pack_state(p, i, out[r]);
  }
  std::vector<int> from;
  return sorted_by_id(exchange(comm_, out, from));
}

std::size_t Domain::memory_bytes() const {
  std::size_t bytes = weight_.capacity() * sizeof(double) + recv_rows_.capacity() * sizeof(int) +
                      (buf_out_.capacity() + buf_in_.capacity() + reverse_out_.capacity() +
                       reverse_in_.capacity() + segment_doubles_) *
                          sizeof(double) +
                      ghost_slot_.capacity() * sizeof(std::uint32_t);
  for (const auto& s : send_) bytes += s.capacity() * sizeof(std::uint32_t);
  return bytes;
}

}  // namespace tumble::parallel
