#include "io/checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "base/comm.hpp"
#include "base/error.hpp"
#include "h5/hdf5_file.hpp"
#include "io/series_io.hpp"
#include "io/snapshot.hpp"

namespace tumble::io {
namespace {
// One column of Particles as the dataset `name`: its first n rows (Vec3: an (n, 3) array of
// doubles; the scalar types as themselves, one row each). Each rank writes its own rows.
void write_column(H5File& f, const std::string& name, const std::vector<Vec3>& a, std::size_t n) {
  std::vector<double> out(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) out[3 * i + d] = a[i][d];
  f.write_rows(name, out, 3);
}
template <class T>
void write_column(H5File& f, const std::string& name, const std::vector<T>& a, std::size_t n) {
  f.write_rows(name, std::vector<T>(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(n)));
}

// Rows [begin, begin + count) of the dataset `name` into a column (the inverse of write_column).
void read_column(const H5File& f, const std::string& name, hsize_t begin, hsize_t count,
                 std::vector<Vec3>& out) {
  const std::vector<double> a = f.read_rows_double(name, begin, count);
  out.resize(a.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
}
void read_column(const H5File& f, const std::string& name, hsize_t begin, hsize_t count,
                 std::vector<double>& out) {
  out = f.read_rows_double(name, begin, count);
}
void read_column(const H5File& f, const std::string& name, hsize_t begin, hsize_t count,
                 std::vector<std::int32_t>& out) {
  out = f.read_rows_int32(name, begin, count);
}
void read_column(const H5File& f, const std::string& name, hsize_t begin, hsize_t count,
                 std::vector<std::int64_t>& out) {
  out = f.read_rows_int64(name, begin, count);
}

std::string dataset_of(const char* field) { return std::string("particles/") + field; }

[[noreturn]] void corrupt(const std::string& path, const std::string& what) {
  throw CorruptInputError("checkpoint '" + path + "': " + what);
}

// The shape a column's dataset must have: (n, 3) for a Vec3, (n) otherwise. Checked before any
// read, so that a damaged length can never make a reader index past its arrays.
template <class Column>
void check_shape(const H5File& f, const std::string& name, hsize_t n) {
  const std::vector<hsize_t> s = f.shape(name);
  const bool vec3 = std::is_same<typename Column::value_type, Vec3>::value;
  const bool ok = vec3 ? s.size() == 2 && s[0] == n && s[1] == 3 : s.size() == 1 && s[0] == n;
  if (!ok)
    corrupt(f.path(), "dataset '" + name + "' does not have " + std::to_string(n) +
                          (vec3 ? " rows of 3" : " rows") + " (particles/id has " +
                          std::to_string(n) + ")");
}

bool finite(double v) { return std::isfinite(v); }
bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
template <class T>
bool finite(const T&) {
  return true;  // integers
}

// What a checkpoint holds that does not depend on the scene: ids in [0, N) and unique (over all
// ranks' blocks), species 0 or 1, every double finite, radii, masses and inertias positive,
// contact pairs of existing particles (lo < hi), the step, time and snapshot count consistent.
// The checksums catch damaged bytes; these catch what a checksum cannot (a file edited by hand,
// written by a broken build), and they are what keeps a bad index from ever reaching an array.
// Returns how often each id occurs in this rank's block (uniqueness over all blocks is checked
// after the ranks have agreed that every block read: a collective must not wait on a rank that
// threw).
std::vector<int> check_contents(const CheckpointData& c, std::int64_t n, std::int64_t row0,
                                const std::string& path) {
  const Particles& p = c.particles;
  std::vector<int> seen(static_cast<std::size_t>(n), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::string row = " (row " + std::to_string(row0 + static_cast<std::int64_t>(i)) + ")";
    if (p.id[i] < 0 || p.id[i] >= n)
      corrupt(path, "particle id " + std::to_string(p.id[i]) + row + " is outside [0, " +
                        std::to_string(n) + ")");
    ++seen[static_cast<std::size_t>(p.id[i])];
    if (p.species[i] != 0 && p.species[i] != 1)
      corrupt(path, "particle " + std::to_string(p.id[i]) + row + " has species " +
                        std::to_string(p.species[i]) + " (Tumble's are 0 and 1)");
    // The rigid bulk's state: -2 thawing, -1 frozen, else the steps of its calm stay so far (an
    // unknown value would leave the particle in no state the engine handles). Files without
    // the column read 0.
    if (i < p.bulk_state.size() && p.bulk_state[i] < -2)
      corrupt(path, "particle " + std::to_string(p.id[i]) + row + " has bulk_state " +
                        std::to_string(p.bulk_state[i]) + " (Tumble's are -2, -1 and >= 0)");
    if (!(p.radius[i] > 0) || !(p.inv_mass[i] > 0) || !(p.inv_inertia[i] > 0) ||
        !finite(p.radius[i]) || !finite(p.inv_mass[i]) || !finite(p.inv_inertia[i]))
      corrupt(path, "particle " + std::to_string(p.id[i]) + row +
                        " has a radius, mass or inertia that is not positive and finite");
  }
  for_each_field<field::kCheckpoint>(p, [&](const char* name, const auto& column) {
    for (std::size_t i = 0; i < column.size(); ++i)
      if (!finite(column[i]))
        corrupt(path, "dataset '" + dataset_of(name) + "' row " +
                          std::to_string(row0 + static_cast<std::int64_t>(i)) + " is not finite");
  });
  for (const auto& r : c.history.records()) {
    if (r.lo < 0 || r.hi >= n || r.lo >= r.hi)
      corrupt(path, "contacts/pair_ids holds the pair (" + std::to_string(r.lo) + ", " +
                        std::to_string(r.hi) + "), not two particles 0 <= lo < hi < " +
                        std::to_string(n));
    for (int d = 0; d < c.history.width(); ++d)
      if (!finite(r.history[d])) corrupt(path, "contacts/spring holds a value that is not finite");
    if (!finite(r.anchor)) corrupt(path, "contacts/anchor holds a value that is not finite");
  }
  if (c.step < 0 || !finite(c.time) || c.time < 0)
    corrupt(path, "step " + std::to_string(c.step) + " and time " + std::to_string(c.time) +
                      " are not a step count and a time");
  // Snapshots are written at most once per step (and at step 0): a larger count cannot be right
  // (and a huge one would make the restart list billions of snapshot names).
  if (c.snapshots_written < 0 || c.snapshots_written > c.step + 1)
    corrupt(path, "snapshots_written = " + std::to_string(c.snapshots_written) + " at step " +
                      std::to_string(c.step));
  if (!c.snapshot_times.empty() &&
      static_cast<std::int64_t>(c.snapshot_times.size()) != c.snapshots_written)
    corrupt(path, "snapshots/time holds " + std::to_string(c.snapshot_times.size()) +
                      " times for snapshots_written = " + std::to_string(c.snapshots_written));
  for (std::size_t k = 0; k < c.snapshot_times.size(); ++k)
    if (!finite(c.snapshot_times[k]) || (k > 0 && c.snapshot_times[k] < c.snapshot_times[k - 1]))
      corrupt(path, "snapshots/time is not a list of increasing times");
  if (static_cast<std::int64_t>(c.measure_samples.size()) > c.step + 1 ||
      std::any_of(c.measure_samples.begin(), c.measure_samples.end(),
                  [](double x) { return !finite(x); }))
    corrupt(path, "measure/samples holds more samples than steps, or one that is not finite");
  const auto len = c.series.time.size();
  for (const auto* v : {&c.series.iteration, &c.series.shell_large_fraction,
                        &c.series.bed_large_fraction, &c.series.kinetic_energy})
    if (v->size() != len)
      corrupt(path, "the series datasets have different lengths (series/time has " +
                        std::to_string(len) + ")");
  return seen;
}

// What a rank's read failed with: a damaged file, a file Tumble cannot use, or anything else (a
// file that went away between the ranks' opens, an I/O error).
enum ReadFailure : int { kBadFile = 0, kCorruptFile = 1, kOtherFailure = 2 };

[[noreturn]] void throw_read_failure(const std::string& msg, int kind) {
  if (kind == kCorruptFile) throw CorruptInputError(msg);
  if (kind == kBadFile) throw InputError(msg);
  throw std::runtime_error(msg);
}

// A rank that finds the file damaged must not leave the others waiting in a collective: every
// rank learns the lowest failing rank's message and throws it.
void agree(MPI_Comm comm, const std::string& local_error, int failure) {
  if (size_of(comm) <= 1) {
    if (local_error.empty()) return;
    throw_read_failure(local_error, failure);
  }
  const int size = size_of(comm), mine = local_error.empty() ? size : rank_in(comm);
  int first = size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  std::string msg = local_error;
  int len = static_cast<int>(msg.size()), kind = failure;
  MPI_Bcast(&len, 1, MPI_INT, first, comm);
  MPI_Bcast(&kind, 1, MPI_INT, first, comm);
  msg.resize(static_cast<std::size_t>(len));
  MPI_Bcast(msg.data(), len, MPI_CHAR, first, comm);
  throw_read_failure(msg, kind);
}
}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim, const Scene& scene,
                      const analysis::Series& series, const std::vector<double>& snapshot_times,
                      const cm::DriftStatistics& drift,
                      const std::vector<double>& measure_samples) {
  // Owned particles only (ghosts are rebuilt on restart), in memory order.
  const Particles& p = sim.particles();
  const std::size_t n = sim.local_count();
  AtomicH5Writer out(path, sim.domain() ? sim.domain()->comm() : MPI_COMM_NULL);
  H5File& f = out.file();
  // Every field the list marks for checkpoints (base/particle_fields.hpp), in list order.
  // The rigid bulk's columns are empty in a dynamic run (field::kRigidOnly): zeros, as every
  // dynamic run's particles had before they were left empty.
  for_each_field<field::kCheckpoint>(p, [&](const char* name, const auto& column) {
    if (column.empty() && n > 0)
      write_column(f, dataset_of(name), std::decay_t<decltype(column)>(n), n);
    else
      write_column(f, dataset_of(name), column, n);
  });
  neighbor::ContactHistory h;
  sim.save_contacts(h);  // the list's springs and the rigid bulk's dormant ones
  std::vector<std::int64_t> pairs;
  std::vector<double> springs, anchors;
  const int width = h.width();  // the law's doubles of history per contact: the columns
  pairs.reserve(2 * h.records().size());
  springs.reserve(static_cast<std::size_t>(width) * h.records().size());
  anchors.reserve(3 * h.records().size());
  for (const auto& r : h.records()) {
    pairs.push_back(r.lo);
    pairs.push_back(r.hi);
    for (int d = 0; d < width; ++d) springs.push_back(r.history[d]);
    for (int d = 0; d < 3; ++d) anchors.push_back(r.anchor[d]);
  }
  f.write_rows("contacts/pair_ids", pairs, 2);
  f.write_rows("contacts/spring", springs, static_cast<hsize_t>(width));
  f.write_rows("contacts/anchor", anchors, 3);
  if (sim.domain()) {  // which rows each rank wrote, and its box (engine_from_checkpoint)
    f.write_rows("domain/rows", std::vector<std::int64_t>{static_cast<std::int64_t>(n)});
    f.write("domain/tree", sim.decomposition());
  }
  write_series(f, series);
  if (!drift.empty()) {  // rank 0's sums (the others hold none: the meter samples the gathered bed)
    f.write("drift/count", drift.count);
    f.write("drift/sum", drift.sum);
    f.write("drift/sum2", drift.sum2);
  }
  f.set_attr("/", "time", sim.time());
  f.set_attr("/", "step", static_cast<std::int64_t>(sim.step_count()));
  f.set_attr("/", "snapshots_written", static_cast<std::int64_t>(snapshot_times.size()));
  if (!snapshot_times.empty()) f.write("snapshots/time", snapshot_times);
  if (!measure_samples.empty()) f.write("measure/samples", measure_samples);
  f.set_attr("/", "kind", std::string("tumble checkpoint"));
  write_provenance(f, scene);
  out.commit();
}

void check_is_checkpoint(const std::string& path) {
  const H5File f(path, H5File::Mode::Read);
  if (!f.has_attr("/", "kind") || f.attr_string("/", "kind") != "tumble checkpoint")
    throw InputError("'" + path + "' is not a Tumble checkpoint");
}

CheckpointData read_checkpoint(const std::string& path, MPI_Comm comm) {
  int rank = 0, size = 1;
  if (comm != MPI_COMM_NULL) {
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
  }
  CheckpointData c;
  std::string error;
  int failure = kCorruptFile;
  std::vector<int> seen;  // occurrences of each id in this rank's block
  try {
    H5File f(path, H5File::Mode::Read);  // every rank reads its own rows independently
    if (!f.has_attr("/", "kind") || f.attr_string("/", "kind") != "tumble checkpoint")
      throw InputError("'" + path + "' is not a Tumble checkpoint");
    const std::vector<hsize_t> id_shape = f.shape("particles/id");
    if (id_shape.size() != 1) corrupt(path, "particles/id is not a list");
    const auto n = static_cast<std::int64_t>(id_shape[0]);
    // A count beyond 2^31 (a 100 GB checkpoint) is a damaged shape, not a bed.
    if (n <= 0 || n >= (std::int64_t{1} << 31))
      corrupt(path, "particles/id has " + std::to_string(n) + " rows");
    auto b0 = static_cast<hsize_t>(n * rank / size),
         b1 = static_cast<hsize_t>(n * (rank + 1) / size);
    // Written on as many ranks: each takes the rows it wrote, and the boxes it had.
    const std::vector<std::int64_t> rows = size > 1 && f.exists("domain/rows")
                                               ? f.read_int64("domain/rows")
                                               : std::vector<std::int64_t>{};
    if (rows.size() == static_cast<std::size_t>(size)) {
      std::int64_t before = 0, total = 0;
      for (int r = 0; r < size; ++r) {
        if (rows[r] < 0 || rows[r] > n) corrupt(path, "domain/rows does not split the particles");
        if (r < rank) before += rows[r];
        total += rows[r];
      }
      if (total != n) corrupt(path, "domain/rows does not add up to the particles' rows");
      b0 = static_cast<hsize_t>(before);
      b1 = b0 + static_cast<hsize_t>(rows[rank]);
      c.domain_tree = f.read_double("domain/tree");
    }
    Particles& p = c.particles;
    p.resize(b1 - b0);  // fields not in checkpoints start value-initialised
    // Fields added after a checkpoint was written start value-initialised when marked optional.
    std::vector<std::string> optional;
    for_each_field<field::kCheckpoint | field::kOptionalOnRead>(
        p, [&](const char* name, auto&) { optional.push_back(name); });
    for_each_field<field::kCheckpoint>(p, [&](const char* name, auto& column) {
      if (!f.exists(dataset_of(name)) &&
          std::find(optional.begin(), optional.end(), name) != optional.end())
        return;
      check_shape<std::decay_t<decltype(column)>>(f, dataset_of(name), static_cast<hsize_t>(n));
      read_column(f, dataset_of(name), b0, b1 - b0, column);
    });
    // Contact records: a block each (routed to the pairs' ranks by their anchors). Checkpoints
    // written before anchors existed give every rank every record instead.
    const std::vector<hsize_t> shape = f.shape("contacts/spring");
    if (shape.empty()) corrupt(path, "contacts/spring is not a table");
    const auto nc = static_cast<std::int64_t>(shape[0]);
    // Its columns: the doubles of history per contact of the law that wrote it (Simulation::restore
    // checks them against the scene's law and applies that law's sign pattern).
    const int h = shape.size() > 1 ? static_cast<int>(shape[1]) : 1;
    if (h < 1 || h > neighbor::kMaxHistoryDoubles)
      corrupt(path, "contacts/spring has " + std::to_string(h) + " columns (at most " +
                        std::to_string(neighbor::kMaxHistoryDoubles) + ")");
    const bool anchored = f.exists("contacts/anchor");
    const std::vector<hsize_t> pair_shape = f.shape("contacts/pair_ids");
    if (pair_shape != std::vector<hsize_t>{shape[0], 2} ||
        (anchored && f.shape("contacts/anchor") != std::vector<hsize_t>{shape[0], 3}))
      corrupt(path,
              "contacts/pair_ids, contacts/spring and contacts/anchor have different lengths");
    const auto c0 = anchored ? static_cast<hsize_t>(nc * rank / size) : 0;
    const auto c1 = anchored ? static_cast<hsize_t>(nc * (rank + 1) / size) : nc;
    const auto pairs = f.read_rows_int64("contacts/pair_ids", c0, c1 - c0);
    const auto springs = f.read_rows_double("contacts/spring", c0, c1 - c0);
    const auto anchors = anchored ? f.read_rows_double("contacts/anchor", c0, c1 - c0)
                                  : std::vector<double>(3 * (pairs.size() / 2), 0.0);
    std::vector<neighbor::SavedSpring> recs(pairs.size() / 2);
    for (std::size_t k = 0; k < recs.size(); ++k) {
      neighbor::SavedSpring& r = recs[k];
      r.lo = pairs[2 * k];
      r.hi = pairs[2 * k + 1];
      for (int d = 0; d < h; ++d) r.history[d] = springs[static_cast<std::size_t>(h) * k + d];
      r.anchor = {anchors[3 * k], anchors[3 * k + 1], anchors[3 * k + 2]};
    }
    c.anchored = anchored;
    c.history = neighbor::ContactHistory({h, (1u << h) - 1});
    c.history.set_records(std::move(recs));
    read_series(f, c.series);
    if (f.exists("drift/count")) {
      c.drift.count = f.read_double("drift/count");
      c.drift.sum = f.read_double("drift/sum");
      c.drift.sum2 = f.read_double("drift/sum2");
      if (c.drift.sum.size() != c.drift.count.size() || c.drift.sum2.size() != c.drift.count.size())
        corrupt(path, "the drift/ datasets have different lengths");
    }
    c.time = f.attr_double("/", "time");
    c.step = f.attr_int64("/", "step");
    c.snapshots_written = f.attr_int64("/", "snapshots_written");
    if (f.exists("snapshots/time")) c.snapshot_times = f.read_double("snapshots/time");
    if (f.exists("measure/samples")) c.measure_samples = f.read_double("measure/samples");
    c.scene_text = f.attr_string("/", "scene");
    seen = check_contents(c, n, static_cast<std::int64_t>(b0), path);
  } catch (const CorruptInputError& e) {
    error = e.what();
  } catch (const InputError& e) {
    error = e.what();
    failure = kBadFile;
  } catch (const std::exception& e) {
    error = e.what();
    failure = kOtherFailure;
  }
  agree(comm, error, failure);
  if (size_of(comm) > 1)
    MPI_Allreduce(MPI_IN_PLACE, seen.data(), static_cast<int>(seen.size()), MPI_INT, MPI_SUM, comm);
  for (std::size_t k = 0; k < seen.size(); ++k)
    if (seen[k] > 1) corrupt(path, "particle id " + std::to_string(k) + " appears twice");
  return c;
}

std::unique_ptr<Simulation> engine_from_checkpoint(CheckpointData& c, const Scene& scene,
                                                   const geometry::Protocol& protocol,
                                                   const std::string& path, MPI_Comm comm) {
  auto sim =
      std::make_unique<Simulation>(scene, std::move(c.particles), protocol, c.time, c.step, comm);
  if (!c.domain_tree.empty()) {
    try {  // (every rank holds the same numbers: all throw alike)
      sim->adopt_decomposition(c.domain_tree);
    } catch (const std::invalid_argument& e) {
      corrupt(path, e.what());
    }
  }
  sim->restore(c.history, c.anchored);
  return sim;
}

void check_checkpoint_fits(const CheckpointData& c, const Scene& s, const std::string& path,
                           MPI_Comm comm) {
  std::string error;
  try {
    const Particles& p = c.particles;
    const double tol = s.d_large;  // settled beds press into the wall by far less than this
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::string who = "particle " + std::to_string(p.id[i]);
      const double want = 0.5 * (p.species[i] == 1 ? s.d_large : s.d_small);
      const bool size_ok = p.radius[i] <= want * (1 + 1e-9) &&
                           p.radius[i] >= want - 0.5 * s.size_spread - 1e-9 * want;
      if (!size_ok)
        corrupt(path, who + " has radius " + std::to_string(p.radius[i]) +
                          " but its species' diameter gives " + std::to_string(want));
      const Vec3& x = p.x[i];
      const bool inside = s.cylinder() ? std::hypot(x.x, x.y) <= s.radius + tol &&
                                             std::fabs(x.z) <= 0.5 * s.length + tol
                                       : norm(x) <= s.radius + tol;
      if (!inside)
        corrupt(path, who + " at (" + std::to_string(x.x) + ", " + std::to_string(x.y) + ", " +
                          std::to_string(x.z) + ") lies outside the tumbler (tumbler.radius = " +
                          std::to_string(s.radius) + " plus one d_large)");
    }
    // time += dt once per step from 0: the two attributes must tell the same story.
    const double expect = static_cast<double>(c.step) * s.time_step();
    if (std::fabs(c.time - expect) > 1e-6 * expect + s.time_step())
      corrupt(path, "time " + std::to_string(c.time) + " s is not step " + std::to_string(c.step) +
                        " x dt = " + std::to_string(expect) + " s");
  } catch (const CorruptInputError& e) {
    error = e.what();
  }
  agree(comm, error, kCorruptFile);
}

}  // namespace tumble::io
