#pragma once
// The parallel layer of one realization: which rank owns which region (RCB tree), migration of
// owned particles and of their contact history when they cross a border, and the ghost (halo)
// particles every rank needs from its neighbours: sent in full at each neighbour rebuild, their
// positions and velocities refreshed every step. Pairs across a rank border are computed on both
// sides (Newton off, docs/architecture.md, "Parallel"); each side keeps its own copy of the pair's
// spring, and the two copies stay equal because the pair force is evaluated with the same
// operations on both sides.
//
// Works on any communicator it is handed (a campaign's rank group as well as MPI_COMM_WORLD); it
// duplicates it so that its messages never meet anyone else's.
#include <mpi.h>

#include <cstdint>
#include <vector>

#include "base/particles.hpp"
#include "neighbor/contact_history.hpp"
#include "parallel/rcb.hpp"

namespace tumble::parallel {

class WideBins;

class Domain {
 public:
  // `root`: the tumbler's bounding box; `period_z` > 0: periodic in z with that period;
  // `rebalance_threshold`: re-bisect when max/mean owned particles exceeds it.
  Domain(MPI_Comm comm, const Box& root, double period_z, double rebalance_threshold);
  ~Domain();
  // fidelity.bulk = "rigid": a frozen particle (bulk_state -1) counts as `w` of a moving one when
  // the regions are cut and the imbalance is measured (parallel.frozen_weight), so that the ranks
  // share the work, not the particles. 1 (the default): every particle counts alike. (Measured on
  // 16 ranks, docs/performance.md: 0.12 halves rank 0's waiting but not the wall time.)
  void weigh_frozen(double w) { frozen_weight_ = w; }
  Domain(const Domain&) = delete;
  Domain& operator=(const Domain&) = delete;

  // Collective. `p` holds only owned particles (no ghosts). Sends every particle to the owner of
  // its position (bisecting afresh on the first call and whenever the imbalance exceeds the
  // threshold), and every contact record to each rank whose domain lies within `reach` of its
  // anchor, so both owners of a pair find it after the move. `history_width`: the doubles of
  // history in each record (the law's).
  void distribute(Particles& p, std::vector<neighbor::SavedSpring>& records, double reach,
                  int history_width);
  // distribute() in its two halves. migrate_owned(): the particles only (bisecting as above).
  // route_records(): each record to every other rank whose domain lies within `reach` of its
  // anchor; `records` becomes what arrived, after the rank's own records if `keep_own`.
  void migrate_owned(Particles& p);
  // A restart on as many ranks as its checkpoint's: the first migrate_owned() uses the boxes the
  // run had (RcbTree::to_doubles) instead of bisecting afresh. Throws std::invalid_argument for
  // numbers that are not a tree of this many ranks. Not collective (every rank passes the same).
  void adopt_tree(const std::vector<double>& tree);
  void route_records(std::vector<neighbor::SavedSpring>& records, double reach, int history_width,
                     bool keep_own);
  // Collective. Appends to `p` (after its `n_local` owned particles) a ghost copy of every other
  // rank's particle whose surface lies within `reach` of this rank's domain (its centre within
  // its radius + `reach`); remembers what went where. With reach = r_max + skin a rank receives
  // exactly the particles that may pair with one of its own (the list's cutoff is r_i + r_j +
  // skin): a small particle's halo is thinner than a large one's.
  // `first`: the owned particles before it are known to lie near no other rank (mark_border's
  // unflagged ones, sorted first) and are not queried again.
  void exchange_ghosts(Particles& p, std::size_t n_local, double reach, std::size_t first = 0);
  // A thinner halo for the thin particles of a size mixture (after LAMMPS' comm_modify
  // reduce/multi, without its Newton across borders): a particle of radius <= `thin_radius` goes
  // to another rank only if its centre is within r_i + thin_radius + `skin` of that rank's domain
  // (where that rank's thin particles may pair with it) or within r_i + r_w + skin of one of that
  // rank's wider particles w, whose centres and radii exchange_ghosts() then sends first. Every
  // pair of the list still finds its ghost, and the ghosts that do arrive keep their order (those
  // left out had no pair), so the list and the forces are those of the full halo. Collective
  // setting, once per scene; thin_radius <= 0 (the default): one halo of r_i + reach for all.
  void thin_halo(double thin_radius, double skin) {
    thin_radius_ = thin_radius;
    skin_ = skin;
  }
  // Collective, after every exchange_ghosts(), once the list is built from its ghosts (and
  // place_ghosts): fixes which ghosts the refresh carries until the next exchange, and lays out
  // the node's shared rows for them. Only those with `used[g]` set (g: the row's index from
  // n_local; the ghosts in a pair of this rank's list) are refreshed and, with Newton across
  // borders, send sums back; their owners learn which and send only those rows; the others keep
  // the state of the exchange (nothing reads them: they are in no pair). `used` null: all of
  // them (the rigid bulk, whose pass reads ghosts beyond the list's pairs).
  void keep_used_ghosts(const std::vector<std::uint8_t>* used);
  // The ghosts refreshed every step (this rank's; keep_used_ghosts()), and all it holds.
  std::int64_t refreshed_ghosts() const { return refreshed_count_; }
  // Puts the ghosts of the last exchange_ghosts() in another order: ghost slot k (row n_local + k)
  // takes the ghost that arrived k-th in `order` (VerletList::ghost_order). The refreshes until
  // the next exchange write each ghost where it now is. Not collective.
  void place_ghosts(Particles& p, std::size_t n_local, const std::vector<std::uint32_t>& order);
  // border[i] = 1 for each owned particle that another rank's exchange_ghosts(reach) would receive
  // as a ghost (centre within its radius + `reach` of that rank's domain): with reach = r_max +
  // skin, every owned particle that may pair with a ghost is flagged (a pair's cutoff r_i + r_j +
  // skin is symmetric), so the others' pairs need no ghost. Not collective.
  void mark_border(const Particles& p, std::size_t n_local, double reach,
                   std::vector<std::uint8_t>& border) const;
  // Collective, every step: refreshes the ghosts' positions and velocities from their owners.
  // `skip_frozen` (the rigid bulk): particles with bulk_state < 0 are left out on both sides;
  // every rank turns its frozen ghosts with the wall itself, as their owners turn them (the
  // states of both sides are those of the last exchange_ghosts, so both agree on what is sent).
  void refresh_ghosts(Particles& p, std::size_t n_local, bool skip_frozen = false) {
    begin_refresh(p, n_local, skip_frozen);
    end_refresh(p, n_local);
  }
  // The same in two halves, so that work which reads no ghost runs while the rows travel:
  // begin_refresh() writes the owned rows where their neighbours read them and posts the
  // receives; end_refresh() waits for them and writes the ghosts. Nothing may read the ghosts'
  // motion, or change the owned rows' or the states, in between.
  // Between ranks of one node (MPI_COMM_TYPE_SHARED) the rows go through a shared window, not
  // messages: each rank writes its rows for a neighbour into its own segment (two buffers, used
  // in turns, so a neighbour still reading the last refresh never sees the next one being
  // written) and the neighbour reads them from there, one copy instead of MPI's two plus its
  // polling. A collective between the halves (max_over_ranks: the step's rebuild test) is the
  // point after which the rows are there; without one end_refresh() waits at a barrier of the
  // node. TUMBLE_REFRESH_MESSAGES=1 in the environment sends messages to every rank instead;
  // TUMBLE_HALO_NODE_RANKS=k takes each k ranks of a node for a node (tests of many nodes on one).
  void begin_refresh(Particles& p, std::size_t n_local, bool skip_frozen = false);
  void end_refresh(Particles& p, std::size_t n_local);
  // Collective, every step with Newton across borders (VerletList::set_newton): the force and
  // torque each ghost collected from this rank's pairs go to its owner, which adds them to its
  // particle's (in the order of the ranks, so a run repeats itself). In two halves like the
  // refresh, and the same ways (the node's shared window, messages): begin_reverse() sends the
  // ghosts' sums (every pair with a ghost computed) and posts the receives; end_reverse() waits
  // and adds. Work that neither writes a ghost's
  // accumulators nor reads or writes a border particle's force (the interior rows' pairs) may
  // run in between. Not with the rigid bulk.
  void reverse_forces(Particles& p, std::size_t n_local) {
    begin_reverse(p, n_local);
    end_reverse(p);
  }
  // Collective setting, once per scene before the first exchange: the sums go between ranks of
  // one node through the shared window (a barrier of the node per step instead of messages).
  // Messages only where the refresh's rows go by messages (TUMBLE_REFRESH_MESSAGES=1, other
  // nodes).
  void reverse_through_window(bool on) { reverse_window_ = on; }
  void begin_reverse(const Particles& p, std::size_t n_local);
  void end_reverse(Particles& p);
  // Let MPI move the messages of the refresh (of the reverse) in flight along (a test of their
  // requests; returns at once).
  void progress_refresh() { progress(requests_); }
  void progress_reverse() { progress(reverse_requests_); }
  // The ranks whose ghosts this rank reads from the shared window (0: all by messages).
  int shared_sources() const { return shared_sources_; }

  // Collective. All particles of every rank, sorted by id (analyses, bed files).
  Particles gather_all(const Particles& p, std::size_t n_local) const;
  // Collective. The particles whose ids fall in this rank's block of [0, n_total) (ids must be
  // 0..n_total-1), sorted by id: contiguous rows for a collective file write.
  Particles id_block(const Particles& p, std::size_t n_local, std::int64_t n_total) const;

  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  const RcbTree& tree() const { return tree_; }
  // max / mean of owned particles (weighted as weigh_frozen says) after the last distribute().
  double imbalance() const { return imbalance_; }
  std::int64_t bisections() const { return bisections_; }
  std::int64_t ghosts() const { return ghost_count_; }
  // Wall seconds this rank spent in the halo: refreshing ghosts every step and, with Newton
  // across borders, sending their forces back (including waiting for its neighbours), and in
  // distribute() + exchange_ghosts() at rebuilds.
  double refresh_seconds() const { return refresh_seconds_; }
  // Collective: the largest `value` of the ranks (the per-step rebuild test), timed: with the
  // refresh travelling behind the interior pairs, a rank waiting for a slower one waits here.
  double max_over_ranks(double value);
  double test_seconds() const { return test_seconds_; }
  double rebuild_seconds() const { return rebuild_seconds_; }
  // Bytes held by the halo's buffers and the work weights (capacities).
  std::size_t memory_bytes() const;

 private:
  void migrate(Particles& p);
  // exchange_ghosts() with thin_halo(): the ranks of `near` (those within the full reach of
  // thin particle i) that it goes to, in `to`. `wide`: the other ranks' wide particles near this
  // rank's domain; `scratch`: room for a tree query.
  void thin_halo_targets(const Particles& p, std::size_t i, const std::vector<int>& near,
                         const WideBins& wide, std::vector<int>& scratch,
                         std::vector<int>& to) const;
  // Each owned particle's share of the work (weight_), and max / mean of their sums over the ranks.
  void weigh(const Particles& p);
  double measure_imbalance() const;

  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  Box root_;
  double period_z_ = 0, threshold_ = 1.1, frozen_weight_ = 1;
  double thin_radius_ = 0, skin_ = 0;  // thin_halo()
  std::vector<double> weight_;
  RcbTree tree_;
  bool have_tree_ = false;
  double imbalance_ = 1;
  std::int64_t bisections_ = 0, ghost_count_ = 0, refreshed_count_ = 0;
  double refresh_seconds_ = 0, rebuild_seconds_ = 0, test_seconds_ = 0;
  // Ghost traffic: local indices sent to each rank; rows received from each rank.
  std::vector<std::vector<std::uint32_t>> send_;
  std::vector<int> recv_rows_;
  // Where the ghost that arrived k-th lies (slot from n_local; empty: where it arrived).
  std::vector<std::uint32_t> ghost_slot_;
  std::vector<double> buf_out_, buf_in_;
  std::vector<double> reverse_out_, reverse_in_;  // reverse_forces(): ghosts' halves, owners' sums
  std::vector<MPI_Request> reverse_requests_;
  // The sums between ranks of one node go through the shared window as the refresh's rows do
  // (reverse_through_window): where this rank writes the sums for each rank (doubles into its
  // segment; kNoOffset: a message), where it reads those of its own particles from each, and
  // which of two buffers the step uses (reverses_ & 1).
  static constexpr std::size_t kNoOffset = ~std::size_t{0};
  static constexpr std::size_t kReverseDoubles = 6;  // force, torque
  bool reverse_window_ = false;
  std::vector<std::size_t> reverse_write_at_;
  std::vector<const double*> reverse_read_at_;
  std::uint64_t reverses_ = 0;
  // The refresh in flight (begin_refresh to end_refresh): its requests, and whether the frozen
  // were left out.
  std::vector<MPI_Request> requests_;
  bool refresh_skips_frozen_ = false;
  // The refresh between ranks of one node (begin_refresh): the node's communicator, each rank's
  // rank in it (-1: another node, or messages), this rank's segment of the shared window (grown
  // at rebuilds, never shrunk), where it writes for each rank (doubles into its segment), where
  // it reads from each (in their segments), and which of the two buffers this refresh uses.
  MPI_Comm node_comm_ = MPI_COMM_NULL;
  std::vector<int> node_rank_;
  MPI_Win window_ = MPI_WIN_NULL;
  double* segment_ = nullptr;
  std::size_t segment_doubles_ = 0;
  std::vector<std::size_t> write_at_;
  std::vector<const double*> read_at_;
  std::uint64_t refreshes_ = 0;
  int shared_sources_ = 0;
  bool shared_out_ = false;       // this rank writes rows into its segment
  bool refresh_pending_ = false;  // between begin_refresh and end_refresh
  bool refresh_synced_ = false;   // ... and a collective of all ranks has passed since begin
  // At keep_used_ghosts: lays out the segment for the new send lists (and the sums going back),
  // grows the window if any rank of the node needs more, and learns where each neighbour of the
  // node writes this rank's rows.
  void place_shared_rows();
  // A test of `requests` (the refresh's or the reverse's), timed as the halo's.
  void progress(std::vector<MPI_Request>& requests);
  // Whether this rank's rows for rank r go into the window (r on this node), not a message.
  bool writes_shared(int r) const { return shared_out_ && node_rank_[r] >= 0; }
  void free_window();
};

// Alltoallv of doubles: `out[r]` goes to rank r; returns what arrived, rank by rank, and the
// number of doubles from each rank in `from`.
std::vector<double> exchange(MPI_Comm comm, const std::vector<std::vector<double>>& out,
                             std::vector<int>& from);

// The block of [0, n) that rank r of p ranks owns in id-blocked layouts.
inline std::int64_t block_begin(std::int64_t n, int r, int p) { return n * r / p; }

}  // namespace tumble::parallel
