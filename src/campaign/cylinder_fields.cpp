#include "campaign/cylinder_fields.hpp"

#include "h5/hdf5_file.hpp"

namespace tumble::campaign {

void write_cylinder_fields(const std::string& path, const FieldsMeta& m, const CollectSpec& spec,
                           const analysis::CylinderSeries& s) {
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  write_case_attributes(f, m, spec);
  f.write("series/time", s.time);
  f.write("series/iteration", s.revolutions);
  f.write("series/Sa", s.sa);
  f.write("series/Sr", s.sr);
  f.write("series/bands", s.bands);
  f.set_attr("series/iteration", "content", std::string("cylinder revolutions"));
  out.commit();
}

}  // namespace tumble::campaign
