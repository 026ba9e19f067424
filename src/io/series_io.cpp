#include "io/series_io.hpp"

#include "io/cylinder_series_io.hpp"

namespace tumble::io {

void write_series(H5File& f, const analysis::Series& s) {
  f.write("series/time", s.time);
  f.write("series/iteration", s.iteration);
  f.write("series/shell_large_fraction", s.shell_large_fraction);
  f.write("series/bed_large_fraction", s.bed_large_fraction);
  f.write("series/kinetic_energy", s.kinetic_energy);
  if (!s.repose_angle.empty()) {  // sphere scenes that turn
    f.write("series/repose_angle", s.repose_angle);
    f.write("series/surface_speed", s.surface_speed);
    // The profile per sample (docs/accuracy.md: the surface velocity profile per tier).
    const hsize_t bins = s.profile_h.size();
    if (bins > 0 && s.surface_profile.size() == bins * s.surface_speed.size()) {
      f.write("series/surface_profile_h", s.profile_h);
      f.write("series/surface_profile", s.surface_profile, {s.surface_speed.size(), bins});
    }
  }
  if (!s.segment.empty()) {  // biaxial scenes
    f.write("series/segment", s.segment);
    f.write("series/segment_turn", s.segment_turn);
  }
  if (!s.frozen_fraction.empty()) f.write("series/frozen_fraction", s.frozen_fraction);
  write_cylinder_series(f, s.cylinder);
}

void read_series(const H5File& f, analysis::Series& s) {
  s.time = f.read_double("series/time");
  s.iteration = f.read_double("series/iteration");
  s.shell_large_fraction = f.read_double("series/shell_large_fraction");
  s.bed_large_fraction = f.read_double("series/bed_large_fraction");
  s.kinetic_energy = f.read_double("series/kinetic_energy");
  if (f.exists("series/repose_angle")) {
    s.repose_angle = f.read_double("series/repose_angle");
    s.surface_speed = f.read_double("series/surface_speed");
  }
  if (f.exists("series/surface_profile")) {  // absent in files written before it was added
    s.profile_h = f.read_double("series/surface_profile_h");
    s.surface_profile = f.read_double("series/surface_profile");
  }
  if (f.exists("series/segment")) {  // absent in files written before it was added
    s.segment = f.read_double("series/segment");
    s.segment_turn = f.read_double("series/segment_turn");
  }
  if (f.exists("series/frozen_fraction"))
    s.frozen_fraction = f.read_double("series/frozen_fraction");
  read_cylinder_series(f, s.cylinder);
}

}  // namespace tumble::io
