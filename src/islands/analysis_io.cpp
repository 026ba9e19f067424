#include "islands/analysis_io.hpp"

#include "base/version.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::analysis {

namespace {
void provenance(io::H5File& f, const std::string& kind, const std::vector<std::string>& inputs) {
  std::string joined;
  for (const auto& s : inputs) joined += (joined.empty() ? "" : "\n") + s;
  f.set_attr("/", "kind", kind);
  f.set_attr("/", "inputs", joined);
  f.set_attr("/", "tumble_version", std::string(kVersion));
  f.set_attr("/", "git_hash", std::string(kGitHash));
}
std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out;
  for (const auto& a : v) out.insert(out.end(), {a.x, a.y, a.z});
  return out;
}
}  // namespace

void write_fates(const std::string& path, const SnapshotData& start, const SnapshotData& end,
                 const FateResult& r) {
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  provenance(f, "tumble fates (Yu 2022 Fig. 8)", {start.path, end.path});
  f.set_attr("/", "from_iteration", start.iteration);
  f.set_attr("/", "to_iteration", end.iteration);
  f.set_attr("/", "fate_codes",
             std::string("0 persistent (same island), 1 captured, 2 dispersed, 3 other, "
                         "4 switched (another island)"));
  const auto& c = r.counts;
  f.set_attr("/", "persistent", c.persistent);
  f.set_attr("/", "captured", c.captured);
  f.set_attr("/", "dispersed", c.dispersed);
  f.set_attr("/", "other", c.other);
  f.set_attr("/", "switched", c.switched);
  const FateExpectation e = chance_fates(r);
  f.set_attr("/", "chance_persistent", e.persistent);
  f.set_attr("/", "chance_switched", e.switched);
  f.set_attr("/", "chance_captured", e.captured);
  f.set_attr("/", "chance_dispersed", e.dispersed);
  f.set_attr("/", "chance_other", e.other);
  f.set_attr("/", "total", c.total());
  const hsize_t n = r.id.size();
  f.write("id", r.id);
  f.write("fate", r.fate);
  f.write("island_start", r.island_start);
  f.write("island_end", r.island_end);
  f.write("x_start", flat(r.x_start), {n, 3});
  f.write("x_end", flat(r.x_end), {n, 3});
  out.commit();
}

void write_section(const std::string& path, const std::vector<std::string>& inputs,
                   const SectionMap& map, const SectionPlane& plane, double half_width,
                   const std::vector<TubeCrossing>& tubes, int island_a, int island_b) {
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  provenance(f, "tumble cross-section (Yu 2022 Fig. 5)", inputs);
  const hsize_t n = map.n();
  f.write("c_L", map.c_large(), {n, n});
  f.write("volume_large", map.large, {n, n});
  f.write("volume_small", map.small, {n, n});
  f.write("e1", std::vector<double>{plane.e1.x, plane.e1.y, plane.e1.z});
  f.write("e2", std::vector<double>{plane.e2.x, plane.e2.y, plane.e2.z});
  f.set_attr("/", "half_width", half_width);
  f.set_attr("/", "samples", static_cast<std::int64_t>(map.samples));
  f.set_attr("/", "island_a", static_cast<std::int64_t>(island_a));
  f.set_attr("/", "island_b", static_cast<std::int64_t>(island_b));
  f.set_attr("/", "grid",
             std::string("cell (i, j): s1 in [-1 + 2i/n, -1 + 2(i+1)/n] along e1, "
                         "s2 likewise along e2, units of R"));
  std::vector<double> t;
  std::vector<std::int32_t> which;
  for (const auto& c : tubes) {
    t.insert(t.end(), {c.r, c.s1, c.s2});
    which.push_back(c.island);
  }
  f.write("tube_crossings", t, {tubes.size(), 3});
  f.write("tube_island", which);
  out.commit();
}

void write_light(const std::string& path, const std::vector<std::string>& inputs,
                 const std::vector<double>& light, int n, int light_species, double inner) {
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  provenance(f, "tumble lighter-particle concentration (Yu 2022 Fig. 13)", inputs);
  const hsize_t hn = n;
  f.write("c_light", light, {hn, hn});
  f.set_attr("/", "light_species", static_cast<std::int64_t>(light_species));
  f.set_attr("/", "shell_inner", inner);
  out.commit();
}

void write_enrichment(const std::string& path, const std::vector<std::string>& inputs,
                      const std::vector<Enrichment>& values, const MeanCI& stat, double inner) {
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  provenance(f, "tumble island enrichment", inputs);
  std::vector<double> v, in, area;
  for (const auto& e : values) {
    v.push_back(e.value);
    in.push_back(e.inside_share);
    area.push_back(e.area_share);
  }
  f.write("enrichment", v);
  f.write("inside_share", in);
  f.write("area_share", area);
  f.set_attr("/", "mean", stat.mean);
  f.set_attr("/", "ci95", stat.ci95);
  f.set_attr("/", "n", static_cast<std::int64_t>(stat.n));
  f.set_attr("/", "shell_inner", inner);
  out.commit();
}

}  // namespace tumble::analysis
