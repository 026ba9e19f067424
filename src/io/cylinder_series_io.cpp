#include "io/cylinder_series_io.hpp"

namespace tumble::io {

void write_cylinder_series(H5File& f, const analysis::CylinderSeries& s) {
  if (s.empty()) return;
  const hsize_t rows = s.time.size();
  f.write("cylinder/time", s.time);
  f.write("cylinder/revolutions", s.revolutions);
  f.write("cylinder/Sa", s.sa);
  f.write("cylinder/Sr", s.sr);
  f.write("cylinder/bands", s.bands);
  f.write("cylinder/surface_slope", s.surface_slope);
  f.write("cylinder/kinetic_energy", s.kinetic_energy);
  f.write("cylinder/axial_profile", s.axial, {rows, static_cast<hsize_t>(s.axial_cols)});
  f.write("cylinder/radial_profile", s.radial, {rows, static_cast<hsize_t>(s.radial_cols)});
  f.write("cylinder/surface_x", s.surface_x);
  f.write("cylinder/surface_large", s.surface_large, {rows, static_cast<hsize_t>(s.surface_cols)});
  f.write("cylinder/surface_small", s.surface_small, {rows, static_cast<hsize_t>(s.surface_cols)});
  f.set_attr(
      "cylinder/Sa", "definition",
      std::string("Rapaport 2007 Eq. 6: <|b^3 n_b(q) - n_s(q)|>_q / <b^3 n_b(q) + n_s(q)>_q"));
  f.set_attr("cylinder/Sr", "definition",
             std::string("Rapaport 2007 Eq. 7 with r the position in the cross-section"));
  f.set_attr("cylinder/axial_profile", "content",
             std::string("big-particle volume fraction per axial slice (-1: empty)"));
  f.set_attr("cylinder/radial_profile", "content",
             std::string("big-particle volume fraction per slab parallel to the fitted free "
                         "surface, by depth (-1: empty)"));
}

void read_cylinder_series(const H5File& f, analysis::CylinderSeries& s) {
  s = analysis::CylinderSeries{};
  if (!f.exists("cylinder/time")) return;
  s.time = f.read_double("cylinder/time");
  s.revolutions = f.read_double("cylinder/revolutions");
  s.sa = f.read_double("cylinder/Sa");
  s.sr = f.read_double("cylinder/Sr");
  s.bands = f.read_double("cylinder/bands");
  s.surface_slope = f.read_double("cylinder/surface_slope");
  s.kinetic_energy = f.read_double("cylinder/kinetic_energy");
  s.axial = f.read_double("cylinder/axial_profile");
  s.radial = f.read_double("cylinder/radial_profile");
  s.surface_x = f.read_double("cylinder/surface_x");
  s.surface_large = f.read_double("cylinder/surface_large");
  s.surface_small = f.read_double("cylinder/surface_small");
  s.axial_cols = static_cast<int>(f.shape("cylinder/axial_profile").back());
  s.radial_cols = static_cast<int>(f.shape("cylinder/radial_profile").back());
  s.surface_cols = static_cast<int>(f.shape("cylinder/surface_large").back());
}

}  // namespace tumble::io
