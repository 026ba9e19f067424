#include "io/bed_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "base/error.hpp"
#include "base/hash.hpp"
#include "contact/laws.hpp"
#include "h5/hdf5_file.hpp"
#include "io/snapshot.hpp"
#include "scene/fill.hpp"

namespace tumble::io {

std::string bed_key(const Scene& s, int code_version) {
  std::ostringstream os;
  os.precision(17);
  os << "R=" << s.radius << ";ds=" << s.d_small << ";dl=" << s.d_large << ";rho=" << s.density
     << ";rr=" << s.density_ratio << ";f=" << s.large_fraction << ";fill=" << s.fill_level
     << ";phi=" << s.packing_fraction << ";e=" << s.restitution << ";tc=" << s.collision_time
     << ";mu=" << s.friction << ";muw=" << s.wall_friction << ";gt=" << s.tangential_damping
     << ";g=" << s.g << ";dt=" << s.time_step() << ";seed=" << s.seed << ";start=" << s.start
     << ";settle=" << s.settle_rms_speed;
  // Keys added with the cylinder and with each law's own keys (Law::bed_key_fields: none for
  // yu2022); absent for sphere/Yu scenes so their cached beds keep their names.
  if (s.cylinder())
    os << ";cyl=" << s.length << "," << s.periodic << "," << s.count << "," << s.size_spread;
  contact::with_law(s, [&](auto tag) { os << decltype(tag)::type::bed_key_fields(s); });
  if (code_version > 1) os << ";code=" << code_version;
  return os.str();
}

std::string bed_cache_path(const Scene& s) {
  return s.bed_cache + "/bed_" + hex16(fnv1a64(bed_key(s))) + ".h5";
}

void write_bed(const std::string& path, const Particles& p, const Scene& scene) {
  const hsize_t n = p.size();
  std::vector<double> x(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) x[3 * i + d] = p.x[i][d];
  AtomicH5Writer out(path);
  H5File& f = out.file();
  f.write("x", x, {n, 3});
  f.write("id", p.id);
  f.write("species", p.species);
  f.write("radius", p.radius);
  f.set_attr("/", "kind", std::string("tumble bed"));
  f.set_attr("/", "bed_key", bed_key(scene));
  write_provenance(f, scene);
  out.commit();
}

namespace {
void check_bed(const Particles& p, const Scene& s, const std::string& path) {
  double (*wall_tolerance)(const Scene&, double) = nullptr;
  contact::with_law(s,
                    [&](auto tag) { wall_tolerance = &decltype(tag)::type::bed_wall_tolerance; });
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double want = 0.5 * (p.species[i] == 1 ? s.d_large : s.d_small);
    const bool size_ok = s.size_spread > 0
                             ? p.radius[i] <= want * (1 + 1e-9) &&
                                   p.radius[i] >= want - 0.5 * s.size_spread - 1e-9 * want
                             : std::fabs(p.radius[i] - want) <= 1e-9 * want;
    if (!size_ok)
      throw InputError("bed '" + path + "': particle " + std::to_string(p.id[i]) + " has radius " +
                       std::to_string(p.radius[i]) + " but the scene's particles.d_" +
                       (p.species[i] == 1 ? "large" : "small") + " gives " + std::to_string(want));
    // Settled beds press into the wall as far as the scene's contacts let the weight push them
    // (Law::bed_wall_tolerance: up to the overlap the validator accepts, kMaxWeightOverlap d_small,
    // and at least 10% of a radius; the soft Rapaport particles up to the centre). More than that
    // means a different tumbler.
    const double from_axis = s.cylinder() ? std::hypot(p.x[i].x, p.x[i].y) : norm(p.x[i]);
    const double tolerance = wall_tolerance(s, p.radius[i]);
    if (from_axis + p.radius[i] > s.radius + tolerance)
      throw InputError("bed '" + path + "': particle " + std::to_string(p.id[i]) +
                       " lies outside tumbler.radius = " + std::to_string(s.radius));
  }
}
}  // namespace

Particles read_bed(const std::string& path, const Scene& scene) {
  Particles p;
  const bool text = path.size() > 4 && path.substr(path.size() - 4) == ".txt";
  if (text) {
    std::ifstream in(path);
    if (!in) throw InputError("cannot read bed file '" + path + "'");
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream ls(line);
      long long id;
      int type;
      double d, x, y, z;
      if (!(ls >> id >> type >> d >> x >> y >> z))
        throw InputError("bed '" + path + "': cannot parse line '" + line + "'");
      const std::size_t i = p.size();
      p.resize(i + 1);
      // Tumble's ids are 0..N-1 (snapshots are indexed by them); the file's own ids (LIGGGHTS
      // counts from 1) are replaced by the line order.
      (void)id;
      p.id[i] = static_cast<std::int64_t>(i);
      p.species[i] = type == 2 ? 1 : 0;
      p.radius[i] = 0.5 * d;
      // The text beds have gravity along -z; Tumble's lab frame has gravity along -y.
      p.x[i] = {x, z, -y};
    }
  } else {
    H5File f(path, H5File::Mode::Read);
    const auto x = f.read_double("x");
    p.resize(x.size() / 3);
    for (std::size_t i = 0; i < p.size(); ++i) p.x[i] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    p.id = f.read_int64("id");
    p.species = f.read_int32("species");
    p.radius = f.read_double("radius");
  }
  check_bed(p, scene, path);
  set_species_properties(scene, p);
  return p;
}

}  // namespace tumble::io
