#include "io/checkpoint.hpp"

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
}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim, const Scene& scene,
                      const analysis::Series& series, std::int64_t snapshots_written) {
  // Owned particles only (ghosts are rebuilt on restart), in memory order.
  const Particles& p = sim.particles();
  const std::size_t n = sim.local_count();
  AtomicH5Writer out(path, sim.domain() ? sim.domain()->comm() : MPI_COMM_NULL);
  H5File& f = out.file();
  // Every field the list marks for checkpoints (base/particle_fields.hpp), in list order.
  for_each_field<field::kCheckpoint>(p, [&](const char* name, const auto& column) {
    write_column(f, dataset_of(name), column, n);
  });
  neighbor::ContactHistory h;
  sim.neighbors().save_history(p, h);
  std::vector<std::int64_t> pairs;
  std::vector<double> springs, anchors;
  const int width = h.width();  // the law's doubles of history per contact: the columns
  for (const auto& r : h.records()) {
    pairs.push_back(r.lo);
    pairs.push_back(r.hi);
    for (int d = 0; d < width; ++d) springs.push_back(r.history[d]);
    for (int d = 0; d < 3; ++d) anchors.push_back(r.anchor[d]);
  }
  f.write_rows("contacts/pair_ids", pairs, 2);
  f.write_rows("contacts/spring", springs, static_cast<hsize_t>(width));
  f.write_rows("contacts/anchor", anchors, 3);
  write_series(f, series);
  f.set_attr("/", "time", sim.time());
  f.set_attr("/", "step", static_cast<std::int64_t>(sim.step_count()));
  f.set_attr("/", "snapshots_written", snapshots_written);
  f.set_attr("/", "kind", std::string("tumble checkpoint"));
  write_provenance(f, scene);
  out.commit();
}

CheckpointData read_checkpoint(const std::string& path, MPI_Comm comm) {
  int rank = 0, size = 1;
  if (comm != MPI_COMM_NULL) {
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &size);
  }
  H5File f(path, H5File::Mode::Read);  // every rank reads its own rows independently
  if (!f.has_attr("/", "kind") || f.attr_string("/", "kind") != "tumble checkpoint")
    throw InputError("'" + path + "' is not a Tumble checkpoint");
  CheckpointData c;
  const auto n = static_cast<std::int64_t>(f.shape("particles/id")[0]);
  const auto b0 = static_cast<hsize_t>(n * rank / size),
             b1 = static_cast<hsize_t>(n * (rank + 1) / size);
  Particles& p = c.particles;
  p.resize(b1 - b0);  // fields not in checkpoints start value-initialised
  for_each_field<field::kCheckpoint>(p, [&](const char* name, auto& column) {
    read_column(f, dataset_of(name), b0, b1 - b0, column);
  });
  // Contact records: a block each (routed to the pairs' ranks by their anchors). Checkpoints
  // written before anchors existed give every rank every record instead.
  const std::vector<hsize_t> shape = f.shape("contacts/spring");
  const auto nc = static_cast<std::int64_t>(shape[0]);
  // Its columns: the doubles of history per contact of the law that wrote it (Simulation::restore
  // checks them against the scene's law and applies that law's sign pattern).
  const int h = shape.size() > 1 ? static_cast<int>(shape[1]) : 1;
  if (h < 1 || h > neighbor::kMaxHistoryDoubles)
    throw InputError("'" + path + "': contacts/spring has " + std::to_string(h) +
                     " columns (at most " + std::to_string(neighbor::kMaxHistoryDoubles) + ")");
  const bool anchored = f.exists("contacts/anchor");
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
  c.history = neighbor::ContactHistory({h, (1u << h) - 1});
  c.history.set_records(std::move(recs));
  read_series(f, c.series);
  c.time = f.attr_double("/", "time");
  c.step = f.attr_int64("/", "step");
  c.snapshots_written = f.attr_int64("/", "snapshots_written");
  c.scene_text = f.attr_string("/", "scene");
  return c;
}

}  // namespace tumble::io
