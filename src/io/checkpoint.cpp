#include "io/checkpoint.hpp"

#include "base/error.hpp"
#include "h5/hdf5_file.hpp"
#include "io/series_io.hpp"
#include "io/snapshot.hpp"

namespace tumble::io {
namespace {
// The first n vectors as a flat row-major (n, 3) array.
std::vector<double> flat(const std::vector<Vec3>& a, std::size_t n) {
  std::vector<double> out(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) out[3 * i + d] = a[i][d];
  return out;
}
std::vector<Vec3> unflat(const std::vector<double>& a) {
  std::vector<Vec3> out(a.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
  return out;
}
}  // namespace

template <class T>
std::vector<T> head(const std::vector<T>& a, std::size_t n) {
  return std::vector<T>(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(n));
}

void write_checkpoint(const std::string& path, const Simulation& sim, const Scene& scene,
                      const analysis::Series& series, std::int64_t snapshots_written) {
  // Owned particles only (ghosts are rebuilt on restart), in memory order.
  const Particles& p = sim.particles();
  const std::size_t n = sim.local_count();
  AtomicH5Writer out(path, sim.domain() ? sim.domain()->comm() : MPI_COMM_NULL);
  H5File& f = out.file();
  f.write_rows("particles/x", flat(p.x, n), 3);
  f.write_rows("particles/v", flat(p.v, n), 3);
  f.write_rows("particles/w", flat(p.w, n), 3);
  f.write_rows("particles/f", flat(p.f, n), 3);
  f.write_rows("particles/t", flat(p.t, n), 3);
  f.write_rows("particles/wall_spring", flat(p.wall_spring, n), 3);
  f.write_rows("particles/radius", head(p.radius, n));
  f.write_rows("particles/inv_mass", head(p.inv_mass, n));
  f.write_rows("particles/inv_inertia", head(p.inv_inertia, n));
  f.write_rows("particles/species", head(p.species, n));
  f.write_rows("particles/id", head(p.id, n));
  neighbor::ContactHistory h;
  sim.neighbors().save_history(p, h);
  std::vector<std::int64_t> pairs;
  std::vector<double> springs, anchors;
  for (const auto& r : h.records()) {
    pairs.push_back(r.lo);
    pairs.push_back(r.hi);
    for (int d = 0; d < 3; ++d) springs.push_back(r.spring[d]);
    for (int d = 0; d < 3; ++d) anchors.push_back(r.anchor[d]);
  }
  f.write_rows("contacts/pair_ids", pairs, 2);
  f.write_rows("contacts/spring", springs, 3);
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
  auto rows = [&](const std::string& name) { return f.read_rows_double(name, b0, b1 - b0); };
  Particles& p = c.particles;
  p.x = unflat(rows("particles/x"));
  p.resize(p.x.size());
  p.v = unflat(rows("particles/v"));
  p.w = unflat(rows("particles/w"));
  p.f = unflat(rows("particles/f"));
  p.t = unflat(rows("particles/t"));
  p.wall_spring = unflat(rows("particles/wall_spring"));
  p.radius = rows("particles/radius");
  p.inv_mass = rows("particles/inv_mass");
  p.inv_inertia = rows("particles/inv_inertia");
  p.species = f.read_rows_int32("particles/species", b0, b1 - b0);
  p.id = f.read_rows_int64("particles/id", b0, b1 - b0);
  // Contact records: a block each (routed to the pairs' ranks by their anchors). Checkpoints
  // written before anchors existed give every rank every record instead.
  const auto nc = static_cast<std::int64_t>(f.shape("contacts/spring")[0]);
  const bool anchored = f.exists("contacts/anchor");
  const auto c0 = anchored ? static_cast<hsize_t>(nc * rank / size) : 0;
  const auto c1 = anchored ? static_cast<hsize_t>(nc * (rank + 1) / size) : nc;
  const auto pairs = f.read_rows_int64("contacts/pair_ids", c0, c1 - c0);
  const auto springs = f.read_rows_double("contacts/spring", c0, c1 - c0);
  const auto anchors = anchored ? f.read_rows_double("contacts/anchor", c0, c1 - c0)
                                : std::vector<double>(springs.size(), 0.0);
  std::vector<neighbor::SavedSpring> recs(pairs.size() / 2);
  for (std::size_t k = 0; k < recs.size(); ++k)
    recs[k] = {pairs[2 * k],
               pairs[2 * k + 1],
               {springs[3 * k], springs[3 * k + 1], springs[3 * k + 2]},
               {anchors[3 * k], anchors[3 * k + 1], anchors[3 * k + 2]}};
  c.history.set_records(std::move(recs));
  read_series(f, c.series);
  c.time = f.attr_double("/", "time");
  c.step = f.attr_int64("/", "step");
  c.snapshots_written = f.attr_int64("/", "snapshots_written");
  c.scene_text = f.attr_string("/", "scene");
  return c;
}

}  // namespace tumble::io
