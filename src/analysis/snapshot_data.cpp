#include "analysis/snapshot_data.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "base/error.hpp"
#include "h5/hdf5_file.hpp"
#include "scene/scene.hpp"

namespace tumble::analysis {

namespace {
std::vector<Vec3> to_vec3(const std::vector<double>& flat) {
  std::vector<Vec3> out(flat.size() / 3);
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = {flat[3 * k], flat[3 * k + 1], flat[3 * k + 2]};
  return out;
}
}  // namespace

SnapshotData read_snapshot(const std::string& path) {
  io::H5File f(path, io::H5File::Mode::Read);
  SnapshotData s;
  s.path = path;
  s.id = f.read_int64("id");
  s.species = f.read_int32("species");
  s.radius = f.read_double("radius");
  s.x = to_vec3(f.read_double("x"));
  s.x_tumbler = to_vec3(f.read_double("x_tumbler"));
  s.time = f.attr_double("/", "time");
  s.iteration = f.attr_double("/", "iteration");
  s.scene_text = f.attr_string("/", "scene");
  // What a checksum cannot see (a file edited or written by a broken build): columns of unequal
  // length would be read past their end, and a value that is no number gave a result all the
  // same (an enrichment of 0 from NaN positions, exit 0).
  auto corrupt = [&](const std::string& what) {
    throw CorruptInputError("snapshot '" + path + "': " + what);
  };
  const std::size_t n = s.id.size();
  if (s.species.size() != n || s.radius.size() != n || s.x.size() != n || s.x_tumbler.size() != n)
    corrupt("the datasets id, species, radius, x and x_tumbler have different lengths");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string who =
        "particle " + std::to_string(s.id[i]) + " (row " + std::to_string(i) + ")";
    if (s.species[i] != 0 && s.species[i] != 1)
      corrupt(who + " has species " + std::to_string(s.species[i]) + " (Tumble's are 0 and 1)");
    if (!(s.radius[i] > 0) || !std::isfinite(s.radius[i]))
      corrupt(who + " has a radius that is not positive and finite");
    if (!std::isfinite(s.x[i].x + s.x[i].y + s.x[i].z) ||
        !std::isfinite(s.x_tumbler[i].x + s.x_tumbler[i].y + s.x_tumbler[i].z))
      corrupt(who + " has a position that is not finite");
  }
  if (!std::isfinite(s.time) || !std::isfinite(s.iteration))
    corrupt("its time or iteration is not finite");
  // The stored scene is valid TOML that parse_scene reads back to the same scene.
  const Scene sc = parse_scene(s.scene_text);
  s.R = sc.radius;
  s.theta_z = sc.theta_z;
  s.theta_x = sc.theta_x;
  s.density_ratio = sc.density_ratio;
  s.shape = name_of(sc.shape);
  s.mode = name_of(sc.mode);
  s.mixture = mixture_of(sc);
  return s;
}

Particles SnapshotData::as_particles() const {
  Particles p;
  p.resize(size());
  for (std::size_t i = 0; i < size(); ++i) {
    p.x[i] = x[i];
    p.radius[i] = radius[i];
    p.species[i] = species[i];
    p.id[i] = id[i];
  }
  return p;
}

std::vector<std::string> list_snapshots(const std::string& dir) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("snap_", 0) == 0 && e.path().extension() == ".h5") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());  // zero-padded numbers: lexical order is time order
  return out;
}

std::vector<bool> repeated_snapshots(const std::vector<double>& iterations) {
  std::vector<double> gaps;
  for (std::size_t k = 1; k < iterations.size(); ++k)
    gaps.push_back(iterations[k] - iterations[k - 1]);
  std::vector<bool> out(iterations.size(), false);
  if (gaps.empty()) return out;
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const double tiny = 0.01 * gaps[gaps.size() / 2];
  for (std::size_t k = 1; k < iterations.size(); ++k)
    out[k] = iterations[k] - iterations[k - 1] < tiny;
  return out;
}

}  // namespace tumble::analysis
