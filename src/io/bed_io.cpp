#include "io/bed_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <unordered_map>

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

void write_bed(const std::string& path, const Particles& p, const Scene& scene,
               int settled_on_ranks) {
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
  f.set_attr("/", "settled_on_ranks", static_cast<std::int64_t>(settled_on_ranks));
  write_provenance(f, scene);
  out.commit();
}

int bed_settled_on_ranks(const std::string& path) {
  H5File f(path, H5File::Mode::Read);
  return f.has_attr("/", "settled_on_ranks")
             ? static_cast<int>(f.attr_int64("/", "settled_on_ranks"))
             : 0;
}

namespace {
// Two settled particles overlap by a few per cent of a diameter at most (the validator refuses
// scenes whose weight would press them by more than kMaxWeightOverlap = 0.25 d_small); half the
// smaller diameter is beyond any bed a scene can settle to, and catches two particles placed at
// one point or a bed for other particle sizes.
constexpr double kMaxBedOverlap = 0.5;

// Pairs closer than the overlap limit, through a hash of cells of the largest diameter: each
// particle is compared with those of its own and the 26 neighbouring cells, O(N).
void check_overlaps(const Particles& p, const std::string& where,
                    const std::function<std::string(std::size_t)>& row_of,
                    const std::function<void(const std::string&)>& refuse) {
  double rmax = 0;
  for (double r : p.radius) rmax = std::max(rmax, r);
  const double cell = 2 * rmax;
  auto key = [](long long i, long long j, long long k) {
    return (static_cast<std::uint64_t>(i & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(j & 0x1fffff) << 21) |
           static_cast<std::uint64_t>(k & 0x1fffff);
  };
  auto index = [&](double v) { return static_cast<long long>(std::floor(v / cell)); };
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> cells;
  cells.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    cells[key(index(p.x[i].x), index(p.x[i].y), index(p.x[i].z))].push_back(i);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const long long ci = index(p.x[i].x), cj = index(p.x[i].y), ck = index(p.x[i].z);
    for (long long a = ci - 1; a <= ci + 1; ++a)
      for (long long b = cj - 1; b <= cj + 1; ++b)
        for (long long c = ck - 1; c <= ck + 1; ++c) {
          const auto it = cells.find(key(a, b, c));
          if (it == cells.end()) continue;
          for (std::size_t j : it->second) {
            if (j <= i) continue;
            const double overlap = p.radius[i] + p.radius[j] - norm(p.x[i] - p.x[j]);
            const double limit = kMaxBedOverlap * 2 * std::min(p.radius[i], p.radius[j]);
            if (overlap > limit)
              refuse("bed '" + where + "': the particles of " + row_of(i) + " and " + row_of(j) +
                     " overlap by " + std::to_string(overlap) + " m, more than " +
                     std::to_string(kMaxBedOverlap) + " of the smaller diameter");
          }
        }
  }
}

// Everything a bed must satisfy before any work starts: not empty, finite coordinates and radii,
// species 0 or 1, unique ids in [0, N), each radius its species' diameter, every particle inside
// the tumbler, no two particles overlapping by more than kMaxBedOverlap of the smaller diameter.
// `row_of(i)` names particle i as the user sees it (the file's line, or the HDF5 row); `refuse`
// throws (InputError for a bed the user gave, CorruptInputError for one Tumble cached itself).
void check_bed(const Particles& p, const Scene& s, const std::string& path,
               const std::function<std::string(std::size_t)>& row_of,
               const std::function<void(const std::string&)>& refuse) {
  if (p.size() == 0) refuse("bed '" + path + "' holds no particles");
  const auto n = static_cast<std::int64_t>(p.size());
  std::vector<char> seen(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::string at = "bed '" + path + "', " + row_of(i) + ": ";
    if (p.id[i] < 0 || p.id[i] >= n)
      refuse(at + "id " + std::to_string(p.id[i]) + " is outside [0, " + std::to_string(n) +
             ") (the ids of a bed of N particles are 0..N-1)");
    if (seen[static_cast<std::size_t>(p.id[i])]++)
      refuse(at + "id " + std::to_string(p.id[i]) + " appears twice");
    if (p.species[i] != 0 && p.species[i] != 1)
      refuse(at + "species " + std::to_string(p.species[i]) + " (a bed's species are 0 and 1)");
    if (!std::isfinite(p.x[i].x) || !std::isfinite(p.x[i].y) || !std::isfinite(p.x[i].z))
      refuse(at + "the position is not finite");
    if (!std::isfinite(p.radius[i]) || !(p.radius[i] > 0))
      refuse(at + "the radius " + std::to_string(p.radius[i]) + " is not positive and finite");
  }
  double (*wall_tolerance)(const Scene&, double) = nullptr;
  contact::with_law(s,
                    [&](auto tag) { wall_tolerance = &decltype(tag)::type::bed_wall_tolerance; });
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::string at = "bed '" + path + "', " + row_of(i) + ": ";
    const double want = 0.5 * (p.species[i] == 1 ? s.d_large : s.d_small);
    const bool size_ok = s.size_spread > 0
                             ? p.radius[i] <= want * (1 + 1e-9) &&
                                   p.radius[i] >= want - 0.5 * s.size_spread - 1e-9 * want
                             : std::fabs(p.radius[i] - want) <= 1e-9 * want;
    if (!size_ok)
      refuse(at + "particle " + std::to_string(p.id[i]) + " has radius " +
             std::to_string(p.radius[i]) + " but the scene's particles.d_" +
             (p.species[i] == 1 ? "large" : "small") + " gives " + std::to_string(want));
    // Settled beds press into the wall as far as the scene's contacts let the weight push them
    // (Law::bed_wall_tolerance: up to the overlap the validator accepts, kMaxWeightOverlap d_small,
    // and at least 10% of a radius; the soft Rapaport particles up to the centre). More than that
    // means a different tumbler.
    const double from_axis = s.cylinder() ? std::hypot(p.x[i].x, p.x[i].y) : norm(p.x[i]);
    const double tolerance = wall_tolerance(s, p.radius[i]);
    const bool beyond_caps = s.cylinder() && s.periodic != OnOff::on &&
                             std::fabs(p.x[i].z) + p.radius[i] > 0.5 * s.length + tolerance;
    if (from_axis + p.radius[i] > s.radius + tolerance || beyond_caps)
      refuse(at + "particle " + std::to_string(p.id[i]) + " lies outside the tumbler (radius " +
             std::to_string(s.radius) +
             (s.cylinder() ? ", length " + std::to_string(s.length) : "") + ")");
  }
  check_overlaps(p, path, row_of, refuse);
}
}  // namespace

Particles read_bed(const std::string& path, const Scene& scene, BedSource source) {
  Particles p;
  std::vector<std::size_t> line_of;  // text: the file's line of each particle
  const bool text = path.size() > 4 && path.substr(path.size() - 4) == ".txt";
  // A bed the user gave is bad input (exit 2); a cached bed Tumble wrote itself that does not
  // pass is damaged (exit 3: delete it, it will be settled again).
  const auto refuse = [&](const std::string& msg) {
    if (source == BedSource::Cache) throw CorruptInputError(msg);
    throw InputError(msg);
  };
  if (text) {
    std::ifstream in(path);
    if (!in) throw InputError("cannot read bed file '" + path + "'");
    std::string line;
    std::vector<long long> file_ids;
    for (std::size_t lineno = 1; std::getline(in, line); ++lineno) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream ls(line);
      long long id;
      int type;
      double d, x, y, z;
      if (!(ls >> id >> type >> d >> x >> y >> z))
        throw InputError("bed '" + path + "', line " + std::to_string(lineno) + ": cannot parse '" +
                         line + "' (id type diameter x y z)");
      if (type != 1 && type != 2)
        throw InputError("bed '" + path + "', line " + std::to_string(lineno) + ": particle type " +
                         std::to_string(type) + " (1 = small, 2 = large)");
      const std::size_t i = p.size();
      p.resize(i + 1);
      // Tumble's ids are 0..N-1 (snapshots are indexed by them); the file's own ids (LIGGGHTS
      // counts from 1) are replaced by the line order, after the check below that they are ids.
      file_ids.push_back(id);
      line_of.push_back(lineno);
      p.id[i] = static_cast<std::int64_t>(i);
      p.species[i] = type == 2 ? 1 : 0;
      p.radius[i] = 0.5 * d;
      // The text beds have gravity along -z; Tumble's lab frame has gravity along -y.
      p.x[i] = {x, z, -y};
    }
    // The file's ids: unique, and numbering the particles from 0 or from 1 (a LIGGGHTS dump).
    std::vector<char> seen(file_ids.size() + 2, 0);
    for (std::size_t i = 0; i < file_ids.size(); ++i) {
      const long long id = file_ids[i];
      const std::string at = "bed '" + path + "', line " + std::to_string(line_of[i]) + ": ";
      if (id < 0 || id > static_cast<long long>(file_ids.size()))
        throw InputError(at + "id " + std::to_string(id) + " is outside [0, " +
                         std::to_string(file_ids.size()) + "] (ids number the " +
                         std::to_string(file_ids.size()) + " particles from 0 or 1)");
      if (seen[static_cast<std::size_t>(id)]++)
        throw InputError(at + "id " + std::to_string(id) + " appears twice");
    }
  } else {
    try {
      H5File f(path, H5File::Mode::Read);
      // Another kind of Tumble file that says its kind (a checkpoint) is named as what it is: it
      // was said to be damaged or not written by Tumble.
      if (f.has_attr("/", "kind")) {
        const std::string kind = f.attr_string("/", "kind");
        if (kind != "tumble bed" && kind.rfind("tumble ", 0) == 0)
          refuse(std::string(source == BedSource::User ? "fill.bed_file: " : "") + "bed '" + path +
                 "' is a " + kind + " file, not a bed (a bed is a file of " +
                 "fill.bed_cache's, or a text file of id, type, diameter, x, y, z lines)" +
                 (kind == "tumble checkpoint" ? "; to go on from a checkpoint, --restart it" : ""));
      }
      // Lengths first: a reader must never index one array by another's length.
      const auto xs = f.shape("x"), is = f.shape("id"), ss = f.shape("species"),
                 rs = f.shape("radius");
      if (xs.size() != 2 || xs[1] != 3 || is.size() != 1 || ss.size() != 1 || rs.size() != 1 ||
          is[0] != xs[0] || ss[0] != xs[0] || rs[0] != xs[0])
        refuse("bed '" + path + "': x must be (N, 3) and id, species, radius (N); they have " +
               std::to_string(xs.empty() ? 0 : xs[0]) + ", " +
               std::to_string(is.empty() ? 0 : is[0]) + ", " +
               std::to_string(ss.empty() ? 0 : ss[0]) + ", " +
               std::to_string(rs.empty() ? 0 : rs[0]) + " rows");
      const auto x = f.read_double("x");
      p.resize(x.size() / 3);
      for (std::size_t i = 0; i < p.size(); ++i) p.x[i] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
      p.id = f.read_int64("id");
      p.species = f.read_int32("species");
      p.radius = f.read_double("radius");
    } catch (const CorruptInputError& e) {
      // A file the user named that HDF5 cannot read as a bed is bad input (exit 2), named by its
      // key; only a cached bed, which Tumble wrote itself, is damaged (exit 3).
      if (source == BedSource::User) throw InputError(std::string("fill.bed_file: ") + e.what());
      throw;
    }
  }
  const auto row_of = [&](std::size_t i) {
    return text ? "line " + std::to_string(line_of[i]) : "row " + std::to_string(i);
  };
  check_bed(p, scene, path, row_of, refuse);
  set_species_properties(scene, p);
  return p;
}

}  // namespace tumble::io
