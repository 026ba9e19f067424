#include "io/checkpoint.hpp"

#include "core/error.hpp"
#include "io/cylinder_series_io.hpp"
#include "io/hdf5_file.hpp"
#include "io/snapshot.hpp"

namespace tumble::io {
namespace {
std::vector<double> flat(const std::vector<Vec3>& a) {
  std::vector<double> out(3 * a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int d = 0; d < 3; ++d) out[3 * i + d] = a[i][d];
  return out;
}
std::vector<Vec3> unflat(const std::vector<double>& a) {
  std::vector<Vec3> out(a.size() / 3);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = {a[3 * i], a[3 * i + 1], a[3 * i + 2]};
  return out;
}
}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim, const Scene& scene,
                      const analysis::Series& series, std::int64_t snapshots_written) {
  const Particles& p = sim.particles();
  const hsize_t n = p.size();
  AtomicH5Writer out(path);
  H5File& f = out.file();
  f.write("particles/x", flat(p.x), {n, 3});
  f.write("particles/v", flat(p.v), {n, 3});
  f.write("particles/w", flat(p.w), {n, 3});
  f.write("particles/f", flat(p.f), {n, 3});
  f.write("particles/t", flat(p.t), {n, 3});
  f.write("particles/wall_spring", flat(p.wall_spring), {n, 3});
  f.write("particles/radius", p.radius);
  f.write("particles/inv_mass", p.inv_mass);
  f.write("particles/inv_inertia", p.inv_inertia);
  f.write("particles/species", p.species);
  f.write("particles/id", p.id);
  neighbor::ContactHistory h;
  sim.neighbors().save_history(p, h);
  std::vector<std::int64_t> pairs;
  std::vector<double> springs;
  for (const auto& r : h.records()) {
    pairs.push_back(r.lo);
    pairs.push_back(r.hi);
    for (int d = 0; d < 3; ++d) springs.push_back(r.spring[d]);
  }
  const hsize_t nc = h.records().size();
  f.write("contacts/pair_ids", pairs, {nc, 2});
  f.write("contacts/spring", springs, {nc, 3});
  f.write("series/time", series.time);
  f.write("series/iteration", series.iteration);
  f.write("series/shell_large_fraction", series.shell_large_fraction);
  f.write("series/bed_large_fraction", series.bed_large_fraction);
  f.write("series/kinetic_energy", series.kinetic_energy);
  write_cylinder_series(f, series.cylinder);
  f.set_attr("/", "time", sim.time());
  f.set_attr("/", "step", static_cast<std::int64_t>(sim.step_count()));
  f.set_attr("/", "snapshots_written", snapshots_written);
  f.set_attr("/", "kind", std::string("tumble checkpoint"));
  write_provenance(f, scene);
  out.commit();
}

CheckpointData read_checkpoint(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  if (!f.has_attr("/", "kind") || f.attr_string("/", "kind") != "tumble checkpoint")
    throw InputError("'" + path + "' is not a Tumble checkpoint");
  CheckpointData c;
  Particles& p = c.particles;
  p.x = unflat(f.read_double("particles/x"));
  p.resize(p.x.size());
  p.v = unflat(f.read_double("particles/v"));
  p.w = unflat(f.read_double("particles/w"));
  p.f = unflat(f.read_double("particles/f"));
  p.t = unflat(f.read_double("particles/t"));
  p.wall_spring = unflat(f.read_double("particles/wall_spring"));
  p.radius = f.read_double("particles/radius");
  p.inv_mass = f.read_double("particles/inv_mass");
  p.inv_inertia = f.read_double("particles/inv_inertia");
  p.species = f.read_int32("particles/species");
  p.id = f.read_int64("particles/id");
  const auto pairs = f.read_int64("contacts/pair_ids");
  const auto springs = f.read_double("contacts/spring");
  std::vector<neighbor::SavedSpring> recs(pairs.size() / 2);
  for (std::size_t k = 0; k < recs.size(); ++k)
    recs[k] = {
        pairs[2 * k], pairs[2 * k + 1], {springs[3 * k], springs[3 * k + 1], springs[3 * k + 2]}};
  c.history.set_records(std::move(recs));
  c.series.time = f.read_double("series/time");
  c.series.iteration = f.read_double("series/iteration");
  c.series.shell_large_fraction = f.read_double("series/shell_large_fraction");
  c.series.bed_large_fraction = f.read_double("series/bed_large_fraction");
  c.series.kinetic_energy = f.read_double("series/kinetic_energy");
  read_cylinder_series(f, c.series.cylinder);
  c.time = f.attr_double("/", "time");
  c.step = f.attr_int64("/", "step");
  c.snapshots_written = f.attr_int64("/", "snapshots_written");
  c.scene_text = f.attr_string("/", "scene");
  return c;
}

}  // namespace tumble::io
