#include "campaign/cylinder_fields.hpp"

#include "io/hdf5_file.hpp"
#include "tumble/version.hpp"

namespace tumble::campaign {

void write_cylinder_fields(const std::string& path, const FieldsMeta& m, const CollectSpec& spec,
                           const analysis::CylinderSeries& s) {
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  f.set_attr("/", "kind", std::string("tumble case fields"));
  f.set_attr("/", "case_id", m.case_id);
  f.set_attr("/", "point_id", m.point_id);
  f.set_attr("/", "params", m.params);
  f.set_attr("/", "tier", m.tier);
  f.set_attr("/", "replica", static_cast<std::int64_t>(m.replica));
  f.set_attr("/", "seed", static_cast<std::int64_t>(m.seed));
  f.set_attr("/", "collect", spec.canonical());
  f.set_attr("/", "tumble_version", std::string(kVersion));
  f.set_attr("/", "git_hash", std::string(kGitHash));
  f.set_attr("/", "scene", m.scene_text);
  f.write("series/time", s.time);
  f.write("series/iteration", s.revolutions);
  f.write("series/Sa", s.sa);
  f.write("series/Sr", s.sr);
  f.write("series/bands", s.bands);
  f.set_attr("series/iteration", "content", std::string("cylinder revolutions"));
  out.commit();
}

}  // namespace tumble::campaign
