#include "engine/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "base/cpu_lanes.hpp"
#include "base/environment.hpp"
#include "base/error.hpp"
#include "base/growth.hpp"
#include "engine/law_lanes.hpp"
#include "neighbor/id_index.hpp"

namespace tumble {
namespace {
// The per-contact history of a law, as the neighbour layer stores it (width and sign pattern).
template <class Law>
neighbor::HistoryLayout history_layout_of() {
  using History = typename Law::History;
  static_assert(Law::kHistoryDoubles >= 1 && Law::kHistoryDoubles <= neighbor::kMaxHistoryDoubles);
  static_assert(sizeof(History) == Law::kHistoryDoubles * sizeof(double) &&
                    std::is_trivially_copyable_v<History>,
                "a law's History is kHistoryDoubles doubles, copied to and from the store");
  return {Law::kHistoryDoubles, Law::kHistoryFlip};
}
// The history of contact k in a store of stride sizeof(History) / sizeof(double), into a value
// of the law's own type and back (fixed-size copies: plain loads and stores).
template <class History>
History load_history(const double* store, std::size_t k) {
  History h;
  std::memcpy(static_cast<void*>(&h), store + k * (sizeof(History) / sizeof(double)),
              sizeof(History));
  return h;
}
template <class History>
void store_history(double* store, std::size_t k, const History& h) {
  std::memcpy(store + k * (sizeof(History) / sizeof(double)), static_cast<const void*>(&h),
              sizeof(History));
}
}  // namespace

Simulation::Simulation(const Scene& s, Particles particles, geometry::Protocol protocol,
                       double time, std::int64_t step, MPI_Comm comm)
    : p_(std::move(particles)),
      n_local_(p_.size()),
      protocol_(std::move(protocol)),
      gravity_{0, -s.g, 0},
      dt_(s.time_step()),
      time_(time),
      step_(step) {
  wall_.radius = s.radius;
  is_cylinder_ = s.cylinder();
  leapfrog_ = s.integrator == Integrator::leapfrog;
  cylinder_.radius = s.radius;
  cylinder_.half_length = 0.5 * s.length;
  cylinder_.periodic = s.periodic == OnOff::on;

  // Chosen once per scene: law, wall and, for frictionless scenes, no tangential history and no
  // rotation; one species present: no species lookups. TUMBLE_GENERAL_KERNELS=1 turns the last two
  // specialisations off, for measuring what they gain (jobs/bench/bench_specialisations.sh).
  int ranks = 1;
  if (comm != MPI_COMM_NULL) MPI_Comm_size(comm, &ranks);
  // Species present and the largest radius over the whole bed (every rank must choose the same
  // kernels and cell size).
  int sp_range[2] = {1 << 30, 1 << 30};  // {min species, -max species}
  for (std::int32_t sp : p_.species) {
    sp_range[0] = std::min(sp_range[0], static_cast<int>(sp));
    sp_range[1] = std::min(sp_range[1], -static_cast<int>(sp));
  }
  double rmax = 0;
  for (double r : p_.radius) rmax = std::max(rmax, r);
  if (ranks > 1) {
    MPI_Allreduce(MPI_IN_PLACE, sp_range, 2, MPI_INT, MPI_MIN, comm);
    MPI_Allreduce(MPI_IN_PLACE, &rmax, 1, MPI_DOUBLE, MPI_MAX, comm);
  }
  species0_ = sp_range[0] == (1 << 30) ? 0 : sp_range[0];
  one_species_ = sp_range[0] == (1 << 30) || sp_range[0] == -sp_range[1];
  const bool force_general = env_switch_on("TUMBLE_GENERAL_KERNELS");
  if (force_general) one_species_ = false;
  neighbor::HistoryLayout history;  // the law's, for the list's per-contact store
  contact::with_law(s, [&](auto tag) {
    using Law = typename decltype(tag)::type;
    history = history_layout_of<Law>();
    tables_ = contact::Tables<Law>::make(s);
    select_kernels<Law>(Law::pair_friction(s), Law::wall_friction(s), cylinder_.periodic);
  });
  if (force_general) rotation_ = true;
  kick_drift_ = rotation_ ? &Simulation::kick_drift<true> : &Simulation::kick_drift<false>;
  half_kick_ = rotation_ ? &Simulation::half_kick<true> : &Simulation::half_kick<false>;
  integrator_lanes_ = lanes_available();
  // The rigid bulk (scene validation refuses it without rotation). Its calm distance is a
  // fraction of d_large; the free surface is found per column of d_large in the lab's x-z plane
  // (about half a large particle of the surface's rise per column at the repose angle).
  rigid_ = s.bulk == Bulk::rigid;
  // A dynamic run keeps no rigid-bulk columns (field::kRigidOnly: their memory, 52 B per
  // particle, is saved); from a rigid run's checkpoint every particle then moves.
  p_.set_rigid_columns(rigid_);
  if (rigid_) {
    kick_drift_ =
        rotation_ ? &Simulation::kick_drift_rigid<true> : &Simulation::kick_drift_rigid<false>;
    half_kick_ =
        rotation_ ? &Simulation::half_kick_rigid<true> : &Simulation::half_kick_rigid<false>;
    bulk_.calm_distance = s.bulk_calm_distance * s.d_large;
    bulk_.dwell_steps = static_cast<std::int64_t>(std::ceil(s.bulk_dwell / dt_));
    bulk_.update_every = std::max<std::int64_t>(10, bulk_.dwell_steps / 4);
    bulk_.margin = s.bulk_margin * s.d_large;
    bulk_.thaw_acceleration = s.bulk_thaw_force * s.g;
    bulk_.thaw_gravity = s.bulk_thaw_gravity;
    bulk_.segment_thaw = s.bulk_segment_thaw;
    if (s.still_slope_pending())  // run_realization resolves it first
      throw std::logic_error("fidelity.bulk_still_slope = 'measured' was not measured");
    bulk_.still_slope_tan = std::tan(deg2rad(s.bulk_still_slope.deg));
    // The slope is fitted to the columns within 0.7 R of the axis: nearer the wall a tilted
    // bed's columns end under the wall's overhang, below the plane of its free surface.
    bulk_.slope_reach2 = 0.49 * s.radius * s.radius;
    bulk_.slope_z = !is_cylinder_;
    bulk_.bin = s.d_large;
    const double hz = is_cylinder_ ? 0.5 * s.length : s.radius;
    bulk_.x0 = -s.radius;
    bulk_.z0 = -hz;
    bulk_.nx = std::max(1, static_cast<int>(std::ceil(2 * s.radius / bulk_.bin)));
    bulk_.nz = std::max(1, static_cast<int>(std::ceil(2 * hz / bulk_.bin)));
  }

  // Cells cover the tumbler's bounding box; side >= largest cutoff. A periodic cylinder's box is
  // exactly one period long in z.
  const double skin = s.skin * s.d_small;
  const double R = s.radius + skin;
  if (is_cylinder_) {
    const double hz = cylinder_.periodic ? 0.5 * s.length : 0.5 * s.length + skin;
    list_ = neighbor::VerletList(neighbor::CellGrid({-R, -R, -hz}, {R, R, hz}, 2 * rmax + skin),
                                 skin, history);
    if (cylinder_.periodic) list_.set_period_z(s.length);
  } else {
    list_ = neighbor::VerletList(neighbor::CellGrid({-R, -R, -R}, {R, R, R}, 2 * rmax + skin), skin,
                                 history);
  }
  // More than one rank: the parallel layer bisects the tumbler's box among them. Ghosts are the
  // particles that may pair with one of a rank's own before the next rebuild: centre within
  // r_i + r_max + skin of its domain (the list's cutoff r_i + r_j + skin at its largest), so a
  // small particle's halo is thinner than a large one's (in an f = 0.15, size ratio 2 bed 98% of
  // the particles are small: ~1.6 instead of 2.1 d_small).
  if (ranks > 1) {
    const double hz = is_cylinder_ ? 0.5 * s.length + (cylinder_.periodic ? 0 : skin) : R;
    const parallel::Box root{{-R, -R, -hz}, {R, R, hz}};
    dom_ = std::make_unique<parallel::Domain>(comm, root, cylinder_.periodic ? s.length : 0.0,
                                              s.rebalance_threshold);
    if (s.bulk == Bulk::rigid) dom_->weigh_frozen(s.frozen_weight);
    halo_reach_ = 2 * rmax + skin;
    // (A margin of 1e-9: the halo's test r_j + (r_max + skin) against a box and the list's
    // (r_i + r_j) + skin against a particle round apart by an ulp; with it a pair at the cutoff
    // never lacks its ghost. The extra ghosts are in no pair.)
    ghost_reach_ = (rmax + skin) * (1 + 1e-9);
    // A size mixture: the particles no wider than the geometric mean of the smallest and the
    // largest radius go out with a thinner halo (Domain::thin_halo; in an R = 2 bed the small
    // ones' 1.6 d_small becomes 1.1 d_small, where no large one is near).
    // TUMBLE_FULL_HALO=1 in the environment keeps one halo for all (the same results).
    double rmin = rmax;
    for (double r : p_.radius) rmin = std::min(rmin, r);
    MPI_Allreduce(MPI_IN_PLACE, &rmin, 1, MPI_DOUBLE, MPI_MIN, comm);
    double thin = 0;
    for (double r : p_.radius)
      if (r * r <= rmin * rmax) thin = std::max(thin, r);
    MPI_Allreduce(MPI_IN_PLACE, &thin, 1, MPI_DOUBLE, MPI_MAX, comm);
    int thin_ok = thin < rmax && !env_switch_on("TUMBLE_FULL_HALO") ? 1 : 0;
    MPI_Allreduce(MPI_IN_PLACE, &thin_ok, 1, MPI_INT, MPI_MIN, comm);  // every rank alike
    if (thin_ok) dom_->thin_halo(thin, skin);
    // The rigid bulk keeps Newton off: its frozen ghosts are left out of the refresh and its
    // dormant springs travel by id on both sides of a border.
    newton_ = s.newton == OnOff::on && !rigid_;
    list_.set_newton(newton_);
    dom_->reverse_through_window(newton_);
  }
}

double Simulation::sum(double local) const {
  if (!dom_) return local;
  double total = 0;
  MPI_Allreduce(&local, &total, 1, MPI_DOUBLE, MPI_SUM, dom_->comm());
  return total;
}

std::int64_t Simulation::global_count() const {
  return static_cast<std::int64_t>(std::llround(sum(static_cast<double>(n_local_))));
}

Particles Simulation::gather_all() const {
  sync_frozen();
  if (dom_) return dom_->gather_all(p_, n_local_);
  return p_;
}

void Simulation::rebuild_distributed(const neighbor::ContactHistory* history,
                                     bool history_everywhere) {
  // (rebuild_lists has brought the centres back into the period: owners come from positions.)
  std::vector<neighbor::SavedSpring> records;
  const int width = list_.history_layout().width;
  if (!history && list_.start.size() == n_local_ + 1) {
    // The springs stay where they are, by index (VerletList::keep_springs), and only those of
    // the pairs with a particle that leaves travel, by id with the pair's position, to every
    // rank near it. (Saving every spring by id and looking every listed pair up after the move
    // was ~5% of a 2-rank step, docs/performance.md.) The rigid bulk's dormant springs likewise:
    // each rank keeps those of its own particles, and those with a particle that leaves travel.
    list_.keep_springs(p_, n_local_);
    p_.resize(n_local_);  // drop the ghosts
    dom_->migrate_owned(p_);
    records = list_.springs_leaving(p_, p_.size(), rigid_ ? &bulk_.dormant : nullptr);
    dom_->route_records(records, halo_reach_, width, false);
    // (The rank's own dormant springs stay in bulk_.dormant: the build looks up those that a
    // pair may take, ahead of the springs that arrived.)
  } else {
    // A restart or the first build: the histories (the restart's, dormant ones included) are
    // routed by id with the pair's position to every rank near it and matched by id after the
    // move.
    // (Records that every rank holds already stay: routed from where they would all be anchored,
    // the origin, each would reach every rank near it once more from every other rank.)
    if (history) records = history->records();
    bulk_.dormant.clear();  // (the restart's records hold them, a first build has none)
    p_.resize(n_local_);    // drop the ghosts
    if (history_everywhere)
      dom_->migrate_owned(p_);
    else
      dom_->distribute(p_, records, halo_reach_, width);
  }
  n_local_ = p_.size();
  // The particles that may pair with a ghost go last: the list's rows before them read no ghost
  // (the step runs them while the ghosts' refresh travels).
  dom_->mark_border(p_, n_local_, ghost_reach_, border_);
  list_.sort(p_, rigid_, &border_);
  dom_->exchange_ghosts(p_, n_local_, ghost_reach_, list_.interior_rows());
  std::vector<std::uint32_t> order;
  list_.ghost_order(p_, n_local_, order);
  dom_->place_ghosts(p_, n_local_, order);  // each cell's ghosts one range of rows
  neighbor::ContactHistory h(list_.history_layout());
  h.set_records(std::move(records));
  list_.build_with_ghosts(p_, n_local_, h, rigid_ ? &bulk_.dormant : nullptr);
  // Only the ghosts in a pair of the list are refreshed until the next rebuild: the halo's reach
  // is an upper bound, and with Newton across borders the other rank computes about half of a
  // ghost's pairs. (The rigid bulk's pass reads all of them.)
  std::vector<std::uint8_t> used;
  if (!rigid_) {
    used.assign(p_.size() - n_local_, 0);
    for (const std::uint32_t j : list_.nbr)
      if (j >= n_local_) used[j - n_local_] = 1;
  }
  dom_->keep_used_ghosts(rigid_ ? nullptr : &used);
}

template <class Law, bool kFriction, bool kPeriodic>
Simulation::PairKernel Simulation::pair_kernel_for(bool one_species) {
  return one_species ? &Simulation::pair_forces<Law, kFriction, kPeriodic, true>
                     : &Simulation::pair_forces<Law, kFriction, kPeriodic, false>;
}

template <class Law>
void Simulation::select_kernels(bool friction, bool wall_friction, bool periodic) {
  if (friction)
    pair_kernel_ = periodic ? pair_kernel_for<Law, true, true>(one_species_)
                            : pair_kernel_for<Law, true, false>(one_species_);
  else
    pair_kernel_ = periodic ? pair_kernel_for<Law, false, true>(one_species_)
                            : pair_kernel_for<Law, false, false>(one_species_);
  // A law with a lane kernel uses it where the CPU runs it (TUMBLE_PLAIN_KERNELS=1: not).
  if constexpr (engine::LawLanes<Law>::kHas) {
    if (lanes_available()) {
      using Lanes = engine::LawLanes<Law>;
      lane_kernel_ = Lanes::kernel(friction, periodic, one_species_);
      pair_kernel_name_ = "avx2 lanes";
      const auto& pairs = tables<Law>().pair;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          double values[Lanes::kCoefficients];
          Lanes::coefficients(pairs[a][b], values);
          for (int q = 0; q < Lanes::kCoefficients; ++q)
            lane_coefficients_[q][2 * a + b] = values[q];
        }
      pair_kernel_ = &Simulation::pair_forces_lanes;
    }
  }
  if (is_cylinder_)
    wall_kernel_ = wall_friction ? &Simulation::cylinder_wall_forces<Law, true>
                                 : &Simulation::cylinder_wall_forces<Law, false>;
  else
    wall_kernel_ = wall_friction ? &Simulation::sphere_wall_forces<Law, true>
                                 : &Simulation::sphere_wall_forces<Law, false>;
  elastic_energy_ = &Simulation::elastic_energy<Law>;
  // Without friction nothing exerts a torque: the integrator leaves the spins alone.
  rotation_ = friction || wall_friction;
}

void Simulation::rebuild_lists(const neighbor::ContactHistory* history, bool history_everywhere) {
  if (cylinder_.periodic) {  // bring centres back into the period before sorting into cells
    const double L = 2 * cylinder_.half_length;
    for (Vec3& x : p_.x) x.z -= L * std::floor((x.z + cylinder_.half_length) / L);
  }
  sync_frozen();  // the frozen are binned (and migrated) where they are now
  if (dom_)
    rebuild_distributed(history, history_everywhere);
  else
    list_.rebuild(p_, history, rigid_ ? &bulk_.dormant : nullptr);
  // Only particles within one skin of the wall can touch it before the next rebuild (no particle
  // moves more than skin/2 in between).
  wall_candidates_.clear();
  cap_candidates_.clear();
  const double skin = list_.skin();
  for (std::size_t i = 0; i < n_local_; ++i) {
    const auto k = static_cast<std::uint32_t>(i);
    // A frozen particle feels no wall (it turns with it); its wall spring waits for its thaw.
    if (rigid_ && p_.bulk_state[i] < 0) continue;
    if (is_cylinder_) {
      if (cylinder_.near_curved(p_.x[i], p_.radius[i], skin)) wall_candidates_.push_back(k);
      if (cylinder_.near_cap(p_.x[i], p_.radius[i], skin)) cap_candidates_.push_back(k);
      continue;
    }
    const double reach = wall_.radius - p_.radius[i] - skin;
    if (reach <= 0 || norm2(p_.x[i]) > reach * reach) wall_candidates_.push_back(k);
  }
  set_pair_view();
}

void Simulation::compute_forces() {
  rebuild_lists(nullptr);
  last_build_step_ = step_;
  bulk_.last_update = step_;
  bulk_.last_update_time = time_;
  bulk_.segment = protocol_.segment_count(time_);
  for (std::size_t i = 0; i < p_.size(); ++i) p_.f[i] = p_.t[i] = Vec3{};
  (this->*pair_kernel_)(0, static_cast<std::uint32_t>(n_local_));
  send_ghost_forces();
  (this->*wall_kernel_)();
}

void Simulation::send_ghost_forces() {
  if (newton_) dom_->reverse_forces(p_, n_local_);
}

std::vector<double> Simulation::decomposition() const {
  return dom_ ? dom_->tree().to_doubles() : std::vector<double>{};
}

void Simulation::adopt_decomposition(const std::vector<double>& tree) {
  if (dom_) dom_->adopt_tree(tree);
}

void Simulation::restore(const neighbor::ContactHistory& history, bool anchored) {
  // The records as the law reads them: its width (a checkpoint of another law's width cannot be
  // matched) and its sign pattern.
  const neighbor::HistoryLayout& layout = list_.history_layout();
  // (Agreed: a rank holding no record must not go on into the collective rebuild alone.)
  int mismatch = !history.records().empty() && history.width() != layout.width ? 1 : 0;
  if (dom_) MPI_Allreduce(MPI_IN_PLACE, &mismatch, 1, MPI_INT, MPI_MAX, dom_->comm());
  if (mismatch)
    throw InputError("the contact history has " + std::to_string(history.width()) +
                     " doubles per contact; this scene's contact law keeps " +
                     std::to_string(layout.width));
  neighbor::ContactHistory h(layout);
  h.set_records(history.records());
  rebuild_lists(&h, !anchored);
  last_build_step_ = step_;
  // The uninterrupted run passed its freeze/thaw pass at this step (the checkpoint's rebuild). Its
  // thaw-force check comes at the next step's start (kick_drift), from the force kept in the
  // checkpoint; a checkpoint of a binary before that check moved holds its thawing particles (-2)
  // instead, which rebuild at the next step.
  bulk_.last_update = step_;
  bulk_.last_update_time = time_;
  bulk_.segment = protocol_.segment_count(time_);
  if (rigid_) {
    std::int64_t frozen = 0;
    for (std::size_t i = 0; i < n_local_; ++i) {
      if (p_.bulk_state[i] == -2) force_rebuild_ = true;
      frozen += p_.bulk_state[i] < 0;
    }
    // (What that pass found, for the progress line and a sample before the next pass.)
    frozen_fraction_ = sum(static_cast<double>(frozen)) / sum(static_cast<double>(n_local_));
  }
  // A checkpoint without anchors: its records reached every rank, and each rank kept as dormant
  // those with a particle of its own (VerletList's build), still anchored at the origin. A
  // dormant spring travels, when one of its particles leaves, to the ranks near its anchor
  // (Domain::route_records): from the origin it would miss the new owner and be lost, and the
  // pair would restart from no spring when it thaws. Each one is placed at its particle here.
  if (rigid_ && !anchored) {
    neighbor::IdIndex own;
    own.assign(p_.id.data(), n_local_);
    bulk_.dormant.set_anchors([&](std::int64_t lo, std::int64_t hi, const Vec3& anchor) {
      std::uint32_t at = own.index_of(lo);
      if (at == neighbor::IdIndex::kAbsent) at = own.index_of(hi);
      return at == neighbor::IdIndex::kAbsent ? anchor : p_.x[at];
    });
  }
}

bool Simulation::rebuild_due(double max_displacement2) {
  const double half = 0.5 * list_.skin();
  // The rigid bulk freezes and thaws at rebuilds: a still bed (no displacement to trigger one)
  // still needs its passes, a quarter of the dwell apart.
  if (rigid_ && step_ - bulk_.last_update >= bulk_.update_every) force_rebuild_ = true;
  if (dom_) {  // every rank rebuilds at the same step (migration is collective)
    const double d2 = dom_->max_over_ranks(force_rebuild_ ? 1e300 : max_displacement2);
    if (d2 == 1e300) force_rebuild_ = true;  // a rebuild requested on any rank
    max_displacement2 = d2;
  }
  if (!(force_rebuild_ || max_displacement2 > half * half)) return false;
  if (!force_rebuild_ && step_ - last_build_step_ < 10) ++fast_rebuilds_;
  return true;
}

void Simulation::rebuild_now() {
  if (rigid_) {
    // The pass reads every position; it must come before the states change (a particle frozen
    // now is where it is, not where its last rebuild's position would put it).
    sync_frozen();
    update_bulk_states();
  }
  thaw_rebuilds_ += thaw_pending_;
  thaw_pending_ = false;
  rebuild_lists(nullptr);
  last_build_step_ = step_;
  force_rebuild_ = false;
}

// First kick and drift of the owned particles `rows`; their force and torque accumulators are
// cleared, and so are the ghosts', and the largest displacement since the last neighbour rebuild
// is found in the same pass. kRotation = false (no friction anywhere: no torque ever) leaves the
// spins alone.
template <bool kRotation>
double Simulation::kick_drift_rows(Rows rows, double kick) {
  const std::size_t n = n_local_;
  Vec3* __restrict x = p_.x.data();
  Vec3* __restrict v = p_.v.data();
  Vec3* __restrict w = p_.w.data();
  Vec3* __restrict f = p_.f.data();
  Vec3* __restrict t = p_.t.data();
  const double* __restrict im = p_.inv_mass.data();
  const double* __restrict ii = p_.inv_inertia.data();
  const Vec3* __restrict x_ref = list_.reference_positions().data();
  const bool have_ref = list_.reference_positions().size() == n;
  // Ghost accumulators collect the partner halves of border pairs (sent to their owners with
  // Newton across borders, else thrown away): cleared before the step's pairs.
  for (std::size_t g = n; g < p_.size(); ++g) f[g] = t[g] = Vec3{};
  double max_d2 = have_ref ? 0.0 : 1e300;
  for (const std::uint32_t i : rows) {
    v[i] += kick * (im[i] * f[i] + gravity_);
    if constexpr (kRotation) {
      w[i] += (kick * ii[i]) * t[i];
      t[i] = Vec3{};
    }
    x[i] += dt_ * v[i];
    f[i] = Vec3{};
    if (have_ref) max_d2 = std::max(max_d2, norm2(x[i] - x_ref[i]));
  }
  return max_d2;
}

template <bool kRotation>
void Simulation::half_kick_rows(Rows rows) {
  const double h = 0.5 * dt_;
  Vec3* __restrict v = p_.v.data();
  Vec3* __restrict w = p_.w.data();
  const Vec3* __restrict f = p_.f.data();
  const Vec3* __restrict t = p_.t.data();
  const double* __restrict im = p_.inv_mass.data();
  const double* __restrict ii = p_.inv_inertia.data();
  for (const std::uint32_t i : rows) {
    v[i] += h * (im[i] * f[i] + gravity_);
    if constexpr (kRotation) w[i] += (h * ii[i]) * t[i];
  }
}

template <bool kRotation>
double Simulation::kick_drift_range(Rows rows, double kick) {
  const std::uint32_t count = rows.last - rows.first;
  const std::uint32_t lanes = integrator_lanes_ ? count - count % 4 : 0;
  // The scalar loop takes what the lanes leave (and clears the ghosts' accumulators).
  const double tail = kick_drift_rows<kRotation>(Rows{rows.first + lanes, rows.last}, kick);
  if (lanes == 0) return tail;
  return std::max(engine::kick_drift_avx2(integrator_input(kick, rows.first, lanes), kRotation),
                  tail);
}

template <bool kRotation>
void Simulation::half_kick_range(Rows rows) {
  const std::uint32_t count = rows.last - rows.first;
  const std::uint32_t lanes = integrator_lanes_ ? count - count % 4 : 0;
  if (lanes > 0) engine::half_kick_avx2(integrator_input(0.5 * dt_, rows.first, lanes), kRotation);
  half_kick_rows<kRotation>(Rows{rows.first + lanes, rows.last});
}

// The dynamic bulk's: every owned particle. (The rigid bulk's, kick_drift_rigid and
// half_kick_rigid in rigid_bulk.cpp, run the same passes over the runs of its moving particles.)
template <bool kRotation>
double Simulation::kick_drift(double kick) {
  return kick_drift_range<kRotation>(Rows{0, static_cast<std::uint32_t>(n_local_)}, kick);
}

template <bool kRotation>
void Simulation::half_kick() {
  half_kick_range<kRotation>(Rows{0, static_cast<std::uint32_t>(n_local_)});
}

engine::IntegratorInput Simulation::integrator_input(double kick, std::size_t first,
                                                     std::size_t n) {
  engine::IntegratorInput in;
  in.n = n;
  in.x = &p_.x[first].x;
  in.v = &p_.v[first].x;
  in.w = &p_.w[first].x;
  in.f = &p_.f[first].x;
  in.t = &p_.t[first].x;
  in.inv_mass = p_.inv_mass.data() + first;
  in.inv_inertia = p_.inv_inertia.data() + first;
  const std::vector<Vec3>& ref = list_.reference_positions();
  in.has_ref = ref.size() == n_local_;  // (none before the first build)
  in.x_ref = in.has_ref ? &ref[first].x : nullptr;
  in.kick = kick;
  in.dt = dt_;
  in.gravity[0] = gravity_.x;
  in.gravity[1] = gravity_.y;
  in.gravity[2] = gravity_.z;
  return in;
}

// (rigid_bulk.cpp's passes call these)
template double Simulation::kick_drift_rows<true>(Rows, double);
template double Simulation::kick_drift_rows<false>(Rows, double);
template double Simulation::kick_drift_range<true>(Rows, double);
template double Simulation::kick_drift_range<false>(Rows, double);
template void Simulation::half_kick_range<true>(Rows);
template void Simulation::half_kick_range<false>(Rows);
template double Simulation::kick_drift<true>(double);
template double Simulation::kick_drift<false>(double);
template void Simulation::half_kick<true>();
template void Simulation::half_kick<false>();

void Simulation::step() {
  // Leapfrog: one kick of a whole step per step (half-step velocities), except the very first,
  // which starts the half-step velocities from v(0). Velocity Verlet: two half kicks. Both give
  // the same positions (the forces see the half-step velocity in either form).
  const double kick = leapfrog_ && step_ > 0 ? dt_ : 0.5 * dt_;
  const double max_d2 = (this->*kick_drift_)(kick);
  time_ += dt_;
  ++step_;
  // The ghosts' refresh starts before the rebuild test: on one node the test's collective is
  // the point after which the neighbours' rows may be read (Domain::begin_refresh).
  if (dom_) dom_->begin_refresh(p_, n_local_, rigid_);
  if (rebuild_due(max_d2)) {
    // The rigid bulk's pass reads the ghosts' positions: they are refreshed first.
    if (dom_) dom_->end_refresh(p_, n_local_);
    rebuild_now();  // may permute particles
    // (The new ghosts arrive with their owners' state; their accumulators start empty.)
    for (std::size_t g = n_local_; g < p_.size(); ++g) p_.f[g] = p_.t[g] = Vec3{};
    (this->*pair_kernel_)(0, static_cast<std::uint32_t>(n_local_));
    send_ghost_forces();
  } else {
    pair_forces_with_refresh();
  }
  (this->*wall_kernel_)();
  if (leapfrog_) return;
  (this->*half_kick_)();
}

void Simulation::pair_forces_with_refresh() {
  const auto n = static_cast<std::uint32_t>(n_local_);
  if (!dom_) {
    (this->*pair_kernel_)(0, n);
    return;
  }
  const auto interior = static_cast<std::uint32_t>(list_.interior_rows());
  // (step() has begun the refresh.) The interior rows read and write no ghost and no border
  // particle: they run while the messages travel, in four pieces with a look at the messages
  // between them (ranks on other nodes): MPI moves a message larger than its eager limit (a few
  // kB; a rank's refresh is tens to hundreds of kB) only inside its calls, so without them the
  // transfer would wait for end_refresh (end_reverse). (Consecutive pieces: the same sums in the
  // same order as one range.) With Newton across borders the ghosts' sums travel back after the
  // border rows: the first half of the interior rows hides the refresh, the second half the sums.
  // The border rows then run between the halves, so an interior particle of the second half with
  // a border partner sums its forces in another order than on a rebuild step (all rows in index
  // order): round-off, and the same in every run, a restart included (checkpoints are taken at
  // rebuilds).
  auto interior_rows = [&](std::uint32_t begin, std::uint32_t end,
                           void (parallel::Domain::*look)()) {
    constexpr std::uint32_t kPieces = 4;
    for (std::uint32_t q = 0; q < kPieces; ++q) {
      const auto first =
          static_cast<std::uint32_t>(begin + std::uint64_t{end - begin} * q / kPieces);
      const auto last =
          static_cast<std::uint32_t>(begin + std::uint64_t{end - begin} * (q + 1) / kPieces);
      (this->*pair_kernel_)(first, last);
      if (q + 1 < kPieces) (dom_.get()->*look)();
    }
  };
  const std::uint32_t during_refresh = newton_ ? interior / 2 : interior;
  interior_rows(0, during_refresh, &parallel::Domain::progress_refresh);
  dom_->end_refresh(p_, n_local_);
  (this->*pair_kernel_)(interior, n);
  if (!newton_) return;
  dom_->begin_reverse(p_, n_local_);
  interior_rows(during_refresh, interior, &parallel::Domain::progress_reverse);
  dom_->end_reverse(p_);
}

template <class Law, bool kFriction, bool kPeriodic, bool kOneSpecies>
void Simulation::pair_forces(std::uint32_t row_begin, std::uint32_t row_end) {
  // rows: owned particles (partners may be ghosts)
  const Vec3* __restrict x = p_.x.data();
  const Vec3* __restrict v = p_.v.data();
  const Vec3* __restrict w = p_.w.data();
  const double* __restrict rad = p_.radius.data();
  const std::int32_t* __restrict sp = p_.species.data();
  Vec3* __restrict f = p_.f.data();
  Vec3* __restrict t = p_.t.data();
  const std::uint32_t* __restrict start = pairs_.start;
  const std::uint32_t* __restrict nbr = pairs_.nbr;
  // The list's history: kHistoryDoubles doubles per pair (the width is a constant here), loaded
  // into the law's History for its kernel and stored back.
  using History = typename Law::History;
  constexpr int kWidth = Law::kHistoryDoubles;
  static_assert(sizeof(History) == kWidth * sizeof(double));
  double* __restrict hist = pairs_.history;
  const double period = 2 * cylinder_.half_length;
  const auto& pairs = tables<Law>().pair;
  const typename Law::Pair only = pairs[species0_][species0_];  // kOneSpecies: the pair
  for (std::size_t i = row_begin; i < row_end; ++i) {
    const Vec3 xi = x[i];
    const double ri = rad[i];
    Vec3 fi{}, ti{};
    for (std::uint32_t k = start[i]; k < start[i + 1]; ++k) {
      const std::uint32_t j = nbr[k];
      Vec3 d = xi - x[j];
      if constexpr (kPeriodic) d.z -= period * std::nearbyint(d.z / period);
      const double rsum = ri + rad[j];
      const double d2 = norm2(d);
      if (d2 >= rsum * rsum) {
        if constexpr (kFriction) {  // contact over: the history starts afresh
          double* h = hist + std::size_t{k} * kWidth;
          bool live = false;
          for (int c = 0; c < kWidth; ++c) live = live || h[c] != 0.0;
          if (live)
            for (int c = 0; c < kWidth; ++c) h[c] = 0.0;
        }
        continue;
      }
      const double dist = std::sqrt(d2);
      const Vec3 nrm = (1.0 / dist) * d;
      const double li = Law::lever(ri, dist, rsum), lj = Law::lever(rad[j], dist, rsum);
      const Vec3 vrel = v[i] - v[j] - cross(li * w[i] + lj * w[j], nrm);
      Vec3 ft;
      History h{};  // without friction the kernels neither read nor write it
      if constexpr (kFriction) h = load_history<History>(hist, k);
      const Vec3 fc = Law::template force<kFriction>(kOneSpecies ? only : pairs[sp[i]][sp[j]], nrm,
                                                     rsum - dist, vrel, h, dt_, ft);
      if constexpr (kFriction) store_history(hist, k, h);
      fi += fc;
      f[j] -= fc;
      if constexpr (kFriction) {
        const Vec3 tq = cross(ft, nrm);  // = -n x F_t: torque per unit lever arm on both
        ti += li * tq;
        t[j] += lj * tq;
      }
    }
    f[i] += fi;
    t[i] += ti;
  }
}

void Simulation::pair_forces_lanes(std::uint32_t row_begin, std::uint32_t row_end) {
  // The rows' pairs are the list's [start[row_begin], start[row_end]): the kernel sees them from
  // there (its contact indices count from the range's first pair).
  const std::size_t k0 = pairs_.start[row_begin], k1 = pairs_.start[row_end];
  if (k1 == k0) return;
  engine::LaneInput in;
  in.pairs = k1 - k0;
  in.row = pairs_.row + k0;
  in.nbr = pairs_.nbr + k0;
  in.x = &p_.x.data()->x;
  in.v = &p_.v.data()->x;
  in.w = &p_.w.data()->x;
  in.radius = p_.radius.data();
  in.species = p_.species.data();
  in.f = &p_.f.data()->x;
  in.t = &p_.t.data()->x;
  in.history = pairs_.history + 3 * k0;  // (a lane kernel's law keeps 3 doubles per pair)
  for (int q = 0; q < 8; ++q) in.coefficient[q] = lane_coefficients_[q];
  in.one_type = 3 * species0_;
  in.dt = dt_;
  in.period = 2 * cylinder_.half_length;
  engine::TouchingContacts& c = touching_;
  if (c.i.size() < in.pairs + engine::kLaneBlock)
    for (auto* v : {&c.i, &c.j, &c.k, &c.miss})
      resize_discarding(*v, in.pairs + engine::kLaneBlock);
  in.contact_i = c.i.data();
  in.contact_j = c.j.data();
  in.contact_k = c.k.data();
  in.miss = c.miss.data();
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "the lane kernels read Vec3 arrays as doubles");
  lane_kernel_(in);
}

// The rough wall of either tumbler (the sphere, or the cylinder's curved wall): every force term
// of the law, the wall surface moving with Ω × r.
template <class Law, bool kFriction, class Wall>
void Simulation::rough_wall_forces(const Wall& wall) {
  // The wall's history is the per-particle field wall_spring, one Vec3: a law of another width
  // needs a wall field of its own width first.
  static_assert(std::is_same_v<typename Law::History, Vec3>);
  const Vec3 omega = protocol_.omega(time_);
  const auto& walls = tables<Law>().wall;
  for (const std::uint32_t i : wall_candidates_) {
    Vec3 nrm, point;
    const double ri = p_.radius[i];
    const double overlap = wall.overlap(p_.x[i], ri, nrm, point);
    if (overlap <= 0) {
      if constexpr (kFriction) p_.wall_spring[i] = Vec3{};
      continue;
    }
    const double li = Law::lever(ri, ri - overlap, ri);
    const Vec3 vrel = p_.v[i] - cross(li * p_.w[i], nrm) - cross(omega, point);
    Vec3 ft;
    const Vec3 fc = Law::template force<kFriction>(walls[p_.species[i]], nrm, overlap, vrel,
                                                   p_.wall_spring[i], dt_, ft);
    p_.f[i] += fc;
    if constexpr (kFriction) p_.t[i] += li * cross(ft, nrm);
  }
}

template <class Law, bool kFriction>
void Simulation::sphere_wall_forces() {
  rough_wall_forces<Law, kFriction>(wall_);
}

// The cylinder: the curved wall rough, the end caps smooth (normal force only: Rapaport's f_v +
// f_d). The caps turn in their own plane, so their normal velocity is zero.
template <class Law, bool kFriction>
void Simulation::cylinder_wall_forces() {
  rough_wall_forces<Law, kFriction>(cylinder_);
  const auto& walls = tables<Law>().wall;
  for (const std::uint32_t i : cap_candidates_) {
    double nz;
    const double overlap = cylinder_.cap_overlap(p_.x[i], p_.radius[i], nz);
    if (overlap <= 0) continue;
    p_.f[i].z += nz * Law::normal(walls[p_.species[i]], overlap, nz * p_.v[i].z);
  }
}

void Simulation::check_health() const {
  sync_frozen();
  std::string problem;
  for (std::size_t i = 0; i < n_local_ && problem.empty(); ++i) {
    const Vec3& x = p_.x[i];
    const Vec3& v = p_.v[i];
    std::ostringstream os;
    if (!std::isfinite(x.x + x.y + x.z + v.x + v.y + v.z)) {
      os << "non-finite state of particle " << p_.id[i] << " at t = " << time_ << " s (step "
         << step_ << "): the time step may be too large for the contact stiffness";
    } else if (is_cylinder_ ? cylinder_.escaped(x) : wall_.escaped(x)) {
      os << "particle " << p_.id[i] << " left the tumbler at t = " << time_ << " s (step " << step_
         << "), at (" << x.x << ", " << x.y << ", " << x.z << "), tumbler radius " << wall_.radius;
      if (is_cylinder_) os << ", length " << 2 * cylinder_.half_length;
    }
    problem = os.str();
  }
  // Every rank throws together (a rank left behind would wait forever in the next collective),
  // all with the diagnostic of the lowest rank that saw a problem, so that whichever rank reports
  // the failure (a campaign group's leader) names what happened and where.
  if (dom_) {
    const MPI_Comm comm = dom_->comm();
    int me = 0, size = 1;
    MPI_Comm_rank(comm, &me);
    MPI_Comm_size(comm, &size);
    int mine = problem.empty() ? size : me, first = size;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
    if (first < size) {
      int length = static_cast<int>(problem.size());
      MPI_Bcast(&length, 1, MPI_INT, first, comm);
      problem.resize(static_cast<std::size_t>(length));
      MPI_Bcast(problem.data(), length, MPI_CHAR, first, comm);
      problem = "rank " + std::to_string(first) + " of " + std::to_string(size) + ": " + problem;
    }
  }
  if (!problem.empty()) throw RunError(problem);
}

double Simulation::wall_overlap(const Vec3& x, double r, Vec3& n, Vec3& point) const {
  return is_cylinder_ ? cylinder_.overlap(x, r, n, point) : wall_.overlap(x, r, n, point);
}

template <class Law>
double Simulation::elastic_energy() const {
  double e = 0;
  const auto& tab = tables<Law>();
  for (std::size_t i = 0; i < n_local_; ++i) {
    Vec3 nrm, point;
    const double ov = wall_overlap(p_.x[i], p_.radius[i], nrm, point);
    if (ov > 0) e += Law::elastic_energy(tab.wall[p_.species[i]], ov, p_.wall_spring[i]);
    if (is_cylinder_) {
      double nz;
      const double ovc = cylinder_.cap_overlap(p_.x[i], p_.radius[i], nz);
      if (!cylinder_.periodic && ovc > 0)
        e += Law::elastic_energy(tab.wall[p_.species[i]], ovc, Vec3{});
    }
    for (std::uint32_t k = list_.start[i]; k < list_.start[i + 1]; ++k) {
      const std::uint32_t j = list_.nbr[k];
      const Vec3 d = cylinder_.nearest_image(p_.x[i] - p_.x[j]);
      const double ovp = p_.radius[i] + p_.radius[j] - norm(d);
      // A pair across a rank border is held by both ranks (half from each), or with Newton
      // across borders by one.
      const double share = j >= n_local_ && !newton_ ? 0.5 : 1.0;
      if (ovp > 0)
        e += share *
             Law::elastic_energy(tab.pair[p_.species[i]][p_.species[j]], ovp,
                                 load_history<typename Law::History>(list_.history.data(), k));
    }
  }
  // The rigid bulk's dormant pairs (two frozen particles, not in the list): found by ids among
  // this rank's particles and ghosts, shared as the list's pairs are.
  const auto& dormant = bulk_.dormant.records();
  if (!dormant.empty()) {
    std::int64_t top = -1;
    for (std::size_t i = 0; i < p_.size(); ++i) top = std::max(top, p_.id[i]);
    std::vector<std::int64_t> at(static_cast<std::size_t>(top + 1), -1);
    for (std::size_t i = 0; i < p_.size(); ++i)
      at[static_cast<std::size_t>(p_.id[i])] = static_cast<std::int64_t>(i);
    auto index = [&](std::int64_t id) { return id <= top ? at[static_cast<std::size_t>(id)] : -1; };
    for (const auto& r : dormant) {
      const std::int64_t a = index(r.lo), b = index(r.hi);
      if (a < 0 || b < 0) continue;
      const auto i = static_cast<std::size_t>(a), j = static_cast<std::size_t>(b);
      const Vec3 d = cylinder_.nearest_image(p_.x[i] - p_.x[j]);
      const double ovp = p_.radius[i] + p_.radius[j] - norm(d);
      const double share =
          (i < n_local_ ? 0.5 : 0.0) + (j < n_local_ ? 0.5 : 0.0);  // each rank's own half
      if (ovp > 0)
        e += share * Law::elastic_energy(tab.pair[p_.species[i]][p_.species[j]], ovp,
                                         load_history<typename Law::History>(r.history.data(), 0));
    }
  }
  return e;
}

void Simulation::save_contacts(neighbor::ContactHistory& out) const {
  list_.save_history(particles(), out, false);
  std::vector<neighbor::SavedSpring> all = out.records();
  const auto& dormant = bulk_.dormant.records();
  all.insert(all.end(), dormant.begin(), dormant.end());
  out.set_records(std::move(all));
  out.sort_by_ids();
}

EnergyBreakdown Simulation::energy() const {
  sync_frozen();
  EnergyBreakdown e;
  for (std::size_t i = 0; i < n_local_; ++i) {
    const double m = 1.0 / p_.inv_mass[i];
    e.kinetic += 0.5 * m * norm2(p_.v[i]) + 0.5 / p_.inv_inertia[i] * norm2(p_.w[i]);
    e.potential -= m * dot(gravity_, p_.x[i]);
  }
  e.elastic = (this->*elastic_energy_)();
  if (dom_) {
    double parts[3] = {e.kinetic, e.potential, e.elastic};
    MPI_Allreduce(MPI_IN_PLACE, parts, 3, MPI_DOUBLE, MPI_SUM, dom_->comm());
    e = {parts[0], parts[1], parts[2]};
  }
  return e;
}

double Simulation::rms_speed() const {
  sync_frozen();
  double s = 0;
  for (std::size_t i = 0; i < n_local_; ++i) s += norm2(p_.v[i]);
  const double n = sum(static_cast<double>(n_local_));
  return n > 0 ? std::sqrt(sum(s) / n) : 0.0;
}

}  // namespace tumble
