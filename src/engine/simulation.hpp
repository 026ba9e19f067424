#pragma once
// The DEM engine for one realization: particle state, neighbour list with contact history, the
// contact law, the tumbler wall (sphere, or cylinder with end caps) and its rotation protocol, and
// the integrator (velocity Verlet, or leapfrog). Physics options are resolved once at construction
// into member-function pointers to kernels instantiated for exactly those options (law, wall,
// friction, axial periodicity): the per-contact loops have no option branches.
#include <mpi.h>

#include <cstdint>
#include <memory>
#include <string>
#include <variant>

#include "base/particles.hpp"
#include "contact/laws.hpp"
#include "engine/contact_lanes.hpp"
#include "engine/integrator_lanes.hpp"
#include "geometry/cylinder_wall.hpp"
#include "geometry/protocol.hpp"
#include "geometry/sphere_wall.hpp"
#include "neighbor/verlet_list.hpp"
#include "parallel/domain.hpp"
#include "scene/scene.hpp"

namespace tumble {

struct EnergyBreakdown {
  double kinetic = 0;    // translational + rotational
  double potential = 0;  // gravity, relative to y = 0
  double elastic = 0;    // normal springs (pairs + wall); tangential springs
  double total() const { return kinetic + potential + elastic; }
};

// The engine's memory on one rank, from its arrays' capacities (bytes; each array's high-water
// mark). docs/performance.md measures the whole heap with valgrind's massif against it.
struct EngineMemory {
  std::size_t particles = 0;  // per-particle state, owned particles and ghosts
  std::size_t neighbors = 0;  // the Verlet list with its springs, and the previous one
  std::size_t scratch = 0;    // the pair loop's contacts, wall candidates, rigid bulk, halo
  std::size_t total() const { return particles + neighbors + scratch; }
};

class Simulation {
 public:
  // `time` and `step` let a restart continue the clock. `comm`: the ranks that share this
  // realization (MPI_COMM_NULL or a one-rank communicator: serial). With more than one rank,
  // `particles` is this rank's share of the bed (any split in which every particle is on exactly
  // one rank); the engine bisects the tumbler among the ranks and moves each particle to its
  // owner. Every public call is then collective over `comm`.
  Simulation(const Scene& scene, Particles particles, geometry::Protocol protocol, double time = 0,
             std::int64_t step = 0, MPI_Comm comm = MPI_COMM_NULL);

  // Advances one time step.
  void step();
  // Forces a neighbour rebuild during the next step (checkpoints: see io/checkpoint.cpp).
  void request_rebuild() { force_rebuild_ = true; }
  // Restores contact history and forces from a checkpoint; rebuilds the list from the current
  // (already sorted) particle order without recomputing forces. `anchored`: the records carry
  // where their pair is (checkpoints from 2026-11-23 on); without it, the rigid bulk's dormant
  // springs are placed at their own particle here, or a migration would send them astray.
  void restore(const neighbor::ContactHistory& history, bool anchored = true);
  // The ranks' boxes (parallel::RcbTree::to_doubles; empty when serial), and a restart on as
  // many ranks going on in the boxes of its checkpoint: called before restore(), it makes the
  // first distribution keep every particle where the checkpoint's rows put it, so the continued
  // run is bitwise the uninterrupted one on a decomposed run too. Throws std::invalid_argument
  // for numbers that are not a tree of this run's ranks; does nothing when serial.
  std::vector<double> decomposition() const;
  void adopt_decomposition(const std::vector<double>& tree);
  // Computes forces for the current state (initial call of a fresh run).
  void compute_forces();

  // Throws RunError if a particle has a non-finite state or left the tumbler.
  void check_health() const;

  EnergyBreakdown energy() const;
  double rms_speed() const;
  // This rank's engine memory (engine/engine_memory.cpp; not collective).
  EngineMemory memory() const;

  // This rank's particles: the owned ones first (local_count()), then the ghosts (parallel runs
  // only; copies of neighbours' particles, refreshed every step).
  // With the rigid bulk, the frozen particles no moving one touches are brought to the present
  // (turned with the wall) here, not every step.
  const Particles& particles() const {
    sync_frozen();
    return p_;
  }
  Particles& particles() {
    sync_frozen();
    return p_;
  }
  std::size_t local_count() const { return n_local_; }
  // Collective: every particle of the realization, sorted by id (a copy of particles() when
  // serial).
  Particles gather_all() const;
  std::int64_t global_count() const;
  // The parallel layer, or nullptr for a serial run.
  const parallel::Domain* domain() const { return dom_.get(); }
  // The neighbour list (with the rigid bulk, without the pairs of two frozen particles: their
  // springs are dormant, see save_contacts()).
  const neighbor::VerletList& neighbors() const { return list_; }
  // Every live contact spring, by ids and sorted: the list's and, with the rigid bulk, the
  // dormant ones (checkpoints).
  void save_contacts(neighbor::ContactHistory& out) const;
  const geometry::Protocol& protocol() const { return protocol_; }
  const geometry::SphereWall& wall() const { return wall_; }
  const geometry::CylinderWall& cylinder() const { return cylinder_; }
  bool is_cylinder() const { return is_cylinder_; }
  bool leapfrog() const { return leapfrog_; }
  bool rotation() const { return rotation_; }
  bool one_species() const { return one_species_; }
  // fidelity.bulk = "rigid" (engine/rigid_bulk.cpp): whether it runs, and the share of the
  // realization's particles frozen at the last neighbour rebuild (0 for a dynamic bulk; not
  // collective: every rank holds it).
  bool rigid_bulk() const { return rigid_; }
  double frozen_fraction() const { return frozen_fraction_; }
  // Rebuilds forced by a frozen particle pushed past fidelity.bulk_thaw_force (this rank's count;
  // a diagnostic of the rigid bulk's cost).
  std::uint64_t thaw_rebuilds() const { return thaw_rebuilds_; }
  // Frozen particles thawed because gravity had turned past fidelity.bulk_thaw_gravity since
  // they froze (this rank's count).
  std::uint64_t gravity_thaws() const { return gravity_thaws_; }
  // Which pair loop runs: "plain" (one contact at a time, the reference) or the lane kernel
  // chosen for this CPU (engine/contact_lanes.hpp).
  const char* pair_kernel_name() const { return pair_kernel_name_; }
  double time() const { return time_; }
  std::int64_t step_count() const { return step_; }
  double dt() const { return dt_; }
  std::uint64_t rebuilds() const { return list_.builds; }
  // Number of rebuilds that came fewer than 10 steps after the previous one (skin too thin).
  std::uint64_t fast_rebuilds() const { return fast_rebuilds_; }
  // The coefficient tables of the scene's law (throws std::bad_variant_access for another law).
  template <class Law>
  const contact::Tables<Law>& tables() const {
    return std::get<contact::Tables<Law>>(tables_);
  }
  // The Yu law's coefficients (yu2022 scenes).
  const contact::Yu2022Pair& pair(int a, int b) const {
    return tables<contact::Yu2022Law>().pair[a][b];
  }
  const contact::Yu2022Pair& wall_pair(int a) const { return tables<contact::Yu2022Law>().wall[a]; }

 private:
  using Kernel = void (Simulation::*)();
  // A pair loop over the list's rows [row_begin, row_end) (owned particles): run over two
  // consecutive ranges it does what one run over both does, in the same order.
  using PairKernel = void (Simulation::*)(std::uint32_t row_begin, std::uint32_t row_end);
  template <class Law, bool kFriction, bool kPeriodic, bool kOneSpecies>
  void pair_forces(std::uint32_t row_begin, std::uint32_t row_end);
  template <class Law, bool kFriction, bool kPeriodic>
  static PairKernel pair_kernel_for(bool one_species);
  // The optimised pair loop of a law with a lane kernel (engine/law_lanes.hpp): scan for touching
  // pairs, lane kernel, accumulation (engine/contact_lanes.hpp); bitwise equal to pair_forces.
  // The scene's options (friction, periodic, one species) are in lane_kernel_, chosen once.
  void pair_forces_lanes(std::uint32_t row_begin, std::uint32_t row_end);
  // The integrator: its scalar loops over a range of rows, the same passes over a range on AVX2
  // lanes where the CPU has them (engine/integrator_lanes.hpp: bitwise those of the loops, which
  // take the last (last - first) mod 4 rows), and the dynamic bulk's steps, over every owned
  // particle.
  struct Rows {  // first, first + 1, ..., last - 1 as a range of indices
    std::uint32_t first, last;
    struct Iterator {
      std::uint32_t i;
      std::uint32_t operator*() const { return i; }
      Iterator& operator++() {
        ++i;
        return *this;
      }
      bool operator!=(const Iterator& o) const { return i != o.i; }
    };
    Iterator begin() const { return {first}; }
    Iterator end() const { return {last}; }
  };
  template <bool kRotation>
  double kick_drift_rows(Rows rows, double kick);
  template <bool kRotation>
  void half_kick_rows(Rows rows);
  template <bool kRotation>
  double kick_drift_range(Rows rows, double kick);
  template <bool kRotation>
  void half_kick_range(Rows rows);
  template <bool kRotation>
  double kick_drift(double kick);
  template <bool kRotation>
  void half_kick();
  engine::IntegratorInput integrator_input(double kick, std::size_t first, std::size_t n);
  // ... with the rigid bulk (rigid_bulk.cpp): the moving particles as above (their runs of rows),
  // the frozen ones that
  // a moving particle touches turned with the wall, the other frozen ones left where they are
  // until sync_frozen().
  template <bool kRotation>
  double kick_drift_rigid(double kick);
  template <bool kRotation>
  void half_kick_rigid();
  // Rigid bulk: every frozen particle (owned and ghost) at its present place, velocity and spin
  // (a no-op when they are current).
  void sync_frozen() const;
  // Rigid bulk, at a neighbour rebuild: freezes and thaws (before the particles move to their
  // cells and ranks), then the pairs the force loops run.
  void update_bulk_states();
  // The tangent of the free surface's inclination, from the bulk's column tops.
  double surface_slope_tan() const;
  void set_pair_view();
  template <class Law, bool kFriction, class Wall>
  void rough_wall_forces(const Wall& wall);
  template <class Law, bool kFriction>
  void sphere_wall_forces();
  template <class Law, bool kFriction>
  void cylinder_wall_forces();
  template <class Law>
  void select_kernels(bool friction, bool wall_friction, bool periodic);
  template <class Law>
  double elastic_energy() const;
  // Overlap with the tumbler's wall (curved wall of a cylinder) for diagnostics.
  double wall_overlap(const Vec3& x, double r, Vec3& n, Vec3& point) const;
  // Collective: whether this step rebuilds (a particle has moved more than half the skin on any
  // rank, or a rebuild was asked for); then the rebuild itself (with the rigid bulk's pass).
  bool rebuild_due(double max_displacement2);
  void rebuild_now();
  // The pair forces of the step: on more than one rank the interior rows run while the ghosts'
  // refresh (begun by step()) is on its way, the border rows after it arrives.
  void pair_forces_with_refresh();
  // `history_everywhere`: every rank holds all of `history` (a checkpoint without anchors), which
  // then needs no routing.
  void rebuild_lists(const neighbor::ContactHistory* history, bool history_everywhere = false);
  // Parallel rebuild: migrate (with contact records), sort, exchange ghosts, list.
  void rebuild_distributed(const neighbor::ContactHistory* history, bool history_everywhere);
  double sum(double local) const;  // over the ranks (identity when serial)

  // mutable: with the rigid bulk the frozen particles that no moving one touches are turned with
  // the wall lazily, by readers too (particles(), gather_all(), energy(); sync_frozen()).
  mutable Particles p_;
  std::size_t n_local_ = 0;  // owned particles: p_[0, n_local_); ghosts after them
  std::unique_ptr<parallel::Domain> dom_;
  // Contact records go to every rank within halo_reach_ (2 r_max + skin) of the pair; a particle
  // is a ghost where its surface is within ghost_reach_ (r_max + skin) of a rank's domain (a thin
  // particle of a size mixture only where it may pair with one: Domain::thin_halo).
  double halo_reach_ = 0, ghost_reach_ = 0;
  std::vector<std::uint8_t> border_;  // rebuild scratch: owned particles that may pair with ghosts
  // Newton across borders (parallel.newton; never with the rigid bulk): a border pair is computed
  // on one of its ranks, the ghosts' force and torque sent to their owners after the pairs.
  bool newton_ = false;
  // After every evaluation of the pair forces: the ghosts' halves to their owners (newton_).
  void send_ghost_forces();
  geometry::Protocol protocol_;
  geometry::SphereWall wall_;
  geometry::CylinderWall cylinder_;
  bool is_cylinder_ = false;
  bool leapfrog_ = false;
  bool rotation_ = true;      // false: no friction anywhere, the spins never change
  bool one_species_ = false;  // every particle of species species0_: no pair-table lookups
  std::int32_t species0_ = 0;
  neighbor::VerletList list_;
  std::vector<std::uint32_t>
      wall_candidates_;  // particles that may touch the (curved) wall before the next rebuild
  std::vector<std::uint32_t> cap_candidates_;  // cylinder: particles that may touch an end cap
  contact::AnyTables tables_;  // the coefficients of the scene's law, per species pair and wall
  Vec3 gravity_;
  double dt_;
  double time_;
  std::int64_t step_;
  std::int64_t last_build_step_ = -1000;
  std::uint64_t fast_rebuilds_ = 0;
  bool force_rebuild_ = false;
  PairKernel pair_kernel_ = nullptr;
  const char* pair_kernel_name_ = "plain";
  engine::LaneKernel lane_kernel_ = nullptr;  // pair_forces_lanes: the CPU's lane kernel
  engine::TouchingContacts touching_;         // pair_forces_lanes: this step's contacts
  double lane_coefficients_[8][4] = {};       // the law's coefficients per type 2 a + b
  Kernel wall_kernel_ = nullptr;
  double (Simulation::*kick_drift_)(double) = nullptr;  // first kick and drift (rotation, bulk)
  Kernel half_kick_ = nullptr;                          // second kick
  bool integrator_lanes_ = false;  // kick_drift, half_kick: the AVX2 passes (lanes_available())
  // The pairs the force loops run: the whole list (with the rigid bulk every pair of it has a
  // moving particle). Set after every rebuild.
  struct PairView {
    const std::uint32_t* start = nullptr;
    const std::uint32_t* nbr = nullptr;
    const std::uint32_t* row = nullptr;
    double* history = nullptr;
    std::size_t pairs = 0;
  };
  PairView pairs_;
  // fidelity.bulk = "rigid": the scene's thresholds in SI units, the free surface's height per
  // column of the lab's x-z plane, the dormant springs, scratch.
  struct RigidBulk {
    double calm_distance = 0;       // [m] in the tumbler's frame, from the particle's anchor
    std::int64_t dwell_steps = 0;   // steps calm before freezing
    std::int64_t update_every = 0;  // the longest run of steps without a freeze/thaw pass
    double margin = 0;              // [m] below the free surface
    double thaw_acceleration = 0;   // [m/s^2]: thaw_force g
    double thaw_gravity = 2;        // |change of gravity's direction| since freezing (2: never)
    // which new protocol segments thaw everything
    SegmentThaw segment_thaw = SegmentThaw::on;
    double still_slope_tan = 0;  // the surface layer may freeze below this slope (0: never)
    double slope_reach2 = 0;     // [m^2] the columns the slope is fitted to: x^2 (+ z^2) below
    bool slope_z = true;         // z counts in the columns' reach (not along a cylinder's axis)
    bool still = false;          // the last pass found the surface still (below the slope)
    double bin = 0, x0 = 0, z0 = 0;
    int nx = 0, nz = 0;
    std::vector<double> top;  // highest particle top per column (-1e300: empty)
    std::vector<std::uint8_t> calm, unsettled, touched;
    // The springs of the pairs of two frozen particles (left out of the list), by ids, as seen
    // from the lower id, in the lab frame (turned with the wall at every pass), anchored at
    // their row particle's present place (for migration). On more than one rank: the pairs with
    // one of the rank's own particles.
    neighbor::ContactHistory dormant;
    // Set with the pairs at every rebuild: whether anything is frozen; the owned moving particles
    // as runs of consecutive rows (one per border class: the sort puts the frozen after the
    // moving ones, neighbor/cell_grid.hpp); the frozen particles in a pair with a moving one
    // (owned, then ghosts): the only frozen ones the step needs; every particle's position at the
    // rebuild and its time (a frozen particle is at turn(build_time -> t) x_build at time t,
    // whoever computes it, owner or ghost holder); the largest |x_build|^2 of an owned frozen
    // particle (it bounds their displacement); the time up to which the frozen particles' state is
    // current.
    bool any_frozen = false;
    std::vector<Rows> moving;
    std::vector<std::uint32_t> exposed, exposed_ghosts;
    std::vector<Vec3> x_build;
    double build_time = 0;
    double frozen_reach2 = 0;
    mutable double synced_time = 0;
    std::int64_t segment = 0;      // the protocol's segment at the last pass
    std::int64_t last_update = 0;  // step of the last freeze/thaw pass
    double last_update_time = 0;   // ... and its time
  };
  bool rigid_ = false;
  RigidBulk bulk_;
  double frozen_fraction_ = 0;
  bool thaw_pending_ = false;  // kick_drift found a thaw: this step's rebuild is forced by it
  std::uint64_t thaw_rebuilds_ = 0;
  std::uint64_t gravity_thaws_ = 0;
  double (Simulation::*elastic_energy_)() const = nullptr;  // of the scene's law
};

}  // namespace tumble
