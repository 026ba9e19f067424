#include "scene/fill_cylinder.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_map>

#include "base/error.hpp"
#include "scene/fill.hpp"

namespace tumble {
namespace {

// Overlap checks during placement: a hash of cells of side >= the largest diameter.
class PlacementGrid {
 public:
  explicit PlacementGrid(double cell) : inv_(1.0 / cell) {}
  bool free(const Vec3& x, double r, const std::vector<Vec3>& pos,
            const std::vector<double>& rad) const {
    const long ci = cell(x.x), cj = cell(x.y), ck = cell(x.z);
    for (long a = ci - 1; a <= ci + 1; ++a)
      for (long b = cj - 1; b <= cj + 1; ++b)
        for (long c = ck - 1; c <= ck + 1; ++c) {
          auto it = cells_.find(key(a, b, c));
          if (it == cells_.end()) continue;
          for (std::uint32_t j : it->second) {
            const double cut = r + rad[j];
            if (norm2(x - pos[j]) < cut * cut) return false;
          }
        }
    return true;
  }
  void add(const Vec3& x, std::uint32_t j) {
    cells_[key(cell(x.x), cell(x.y), cell(x.z))].push_back(j);
  }

 private:
  long cell(double v) const { return static_cast<long>(std::floor(v * inv_)); }
  static long long key(long a, long b, long c) {
    return ((static_cast<long long>(a) + 100000) * 200003 + (b + 100000)) * 200003 + (c + 100000);
  }
  double inv_;
  std::unordered_map<long long, std::vector<std::uint32_t>> cells_;
};

// Sites of a cubic lattice of side a whose cells lie inside the cylinder, bottom first.
std::vector<Vec3> lattice_sites(const Scene& s, double a) {
  const double R = s.radius - 0.5 * a, hl = 0.5 * s.length - 0.5 * a;
  std::vector<Vec3> sites;
  const int nr = static_cast<int>(std::ceil(s.radius / a));
  const int nz = static_cast<int>(std::ceil(0.5 * s.length / a));
  for (int i = -nr; i < nr; ++i)
    for (int j = -nr; j < nr; ++j)
      for (int k = -nz; k < nz; ++k) {
        const Vec3 c{(i + 0.5) * a, (j + 0.5) * a, (k + 0.5) * a};
        if (R > 0 && c.x * c.x + c.y * c.y <= R * R && std::fabs(c.z) <= hl) sites.push_back(c);
      }
  std::sort(sites.begin(), sites.end(), [](const Vec3& p, const Vec3& q) {
    if (p.y != q.y) return p.y < q.y;
    if (p.x != q.x) return p.x < q.x;
    return p.z < q.z;
  });
  return sites;
}

// Presegregated start: places the particles (radii `rad`, already multiplied by the shrink
// factor) bottom first on a cubic lattice of side `a`, each particle on the lowest free site where
// it fits, the large particles confined to z < z_split and the small to z >= z_split. Returns
// false if some particle found no site.
bool place(const Scene& s, const std::vector<double>& rad, const std::vector<std::int32_t>& sp,
           double a, double z_split, std::vector<Vec3>& pos) {
  const double R = s.radius, hl = 0.5 * s.length;
  const std::vector<Vec3> sites = lattice_sites(s, a);
  const double rmax = *std::max_element(rad.begin(), rad.end());
  PlacementGrid grid(2 * rmax);
  std::vector<char> used(sites.size(), 0);
  std::size_t first_free[2] = {0, 0};  // per species: sites below are used or rejected for it
  pos.assign(rad.size(), Vec3{});
  const bool split = s.start == Start::large_zneg;
  for (std::size_t p = 0; p < rad.size(); ++p) {
    const double r = rad[p];
    const int q = sp[p];
    std::size_t k = first_free[q];
    bool advancing = true;  // sites skipped while this stays true are unusable for this species
    for (; k < sites.size(); ++k) {
      if (used[k]) {
        if (advancing) first_free[q] = k + 1;
        continue;
      }
      const Vec3& c = sites[k];
      const bool in_half = !split || (q == 1 ? c.z < z_split : c.z >= z_split);
      const bool inside = c.x * c.x + c.y * c.y < (R - r) * (R - r) && std::fabs(c.z) < hl - r;
      if (!in_half || !inside) {
        if (advancing) first_free[q] = k + 1;
        continue;
      }
      if (grid.free(c, r, pos, rad)) break;
      advancing = false;  // blocked for now by a neighbour: a smaller particle may fit later
    }
    if (k == sites.size()) return false;
    used[k] = 1;
    pos[p] = sites[k];
    grid.add(sites[k], static_cast<std::uint32_t>(p));
  }
  return true;
}

// Mixed start, as the paper: one particle per site of a lattice spread over the cylinder, species
// drawn at random. The side is the largest that holds every particle (at most a big particle's
// diameter: beyond that particles would start shrunk); the lowest N sites are used.
bool place_mixed(const Scene& s, std::int64_t n, std::vector<Vec3>& pos, double& shrink) {
  const double a_full = 1.01 * s.d_large;
  double lo = 0.3 * s.d_small, hi = a_full;
  if (static_cast<std::int64_t>(lattice_sites(s, hi).size()) < n) {
    if (static_cast<std::int64_t>(lattice_sites(s, lo).size()) < n) return false;
    for (int it = 0; it < 40; ++it) {  // the count falls as the side grows
      const double mid = 0.5 * (lo + hi);
      (static_cast<std::int64_t>(lattice_sites(s, mid).size()) >= n ? lo : hi) = mid;
    }
    hi = lo;
  }
  std::vector<Vec3> sites = lattice_sites(s, hi);
  pos.assign(sites.begin(), sites.begin() + n);
  shrink = hi / a_full;
  return true;
}

}  // namespace

CylinderBed make_cylinder_bed(const Scene& s) {
  const std::int64_t n = s.count;
  // large_fraction is the large particles' share of the solid volume, as for the sphere, counted
  // with the nominal diameters as the paper's weights b^3 (equal volumes, b = 1.8: 14.6% of the
  // particles big, the paper's "big particle fraction of 0.15").
  const double fl = s.large_fraction / (s.d_large * s.d_large * s.d_large);
  const double fs = (1 - s.large_fraction) / (s.d_small * s.d_small * s.d_small);
  const std::int64_t n_large = std::llround(n * fl / (fl + fs));

  Rng rng(static_cast<std::uint64_t>(s.seed));
  std::vector<std::int32_t> sp(n, 0);
  for (std::int64_t i = 0; i < n_large; ++i) sp[i] = 1;
  if (s.start == Start::mixed) rng.shuffle(sp);
  std::vector<double> rad(n);
  for (std::int64_t i = 0; i < n; ++i) {
    const double d = sp[i] == 1 ? s.d_large : s.d_small;
    rad[i] = 0.5 * (d - s.size_spread * rng.uniform());
  }
  // Presegregated: the large particles' half is sized by their share of the volume.
  double v_large = 0, v_all = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    const double v = rad[i] * rad[i] * rad[i];
    v_all += v;
    if (sp[i] == 1) v_large += v;
  }
  const double z_split = -0.5 * s.length + s.length * (v_all > 0 ? v_large / v_all : 0);

  CylinderBed bed;
  std::vector<Vec3> pos;
  bool ok = false;
  if (s.start == Start::mixed) {
    ok = place_mixed(s, n, pos, bed.shrink) && bed.shrink >= 0.6;
  } else {
    // Presegregated: each species packed bottom first into its own axial part of the cylinder.
    for (double shrink = 1.0; shrink > 0.59; shrink -= 0.05) {
      std::vector<double> r2(rad);
      for (double& r : r2) r *= shrink;
      // Lattice side: 1.01 of the largest small diameter, shrunk alike.
      if (place(s, r2, sp, 1.01 * s.d_small * shrink, z_split, pos)) {
        bed.shrink = shrink;
        ok = true;
        break;
      }
    }
  }
  if (!ok) {
    std::ostringstream os;
    os << "scene error: key 'particles.count' = " << n
       << ": the particles cannot be placed in the cylinder even at 0.6 of their size; lower "
          "particles.count or enlarge tumbler.radius / tumbler.length";
    throw InputError(os.str());
  }
  Particles& p = bed.particles;
  p.resize(n);
  for (std::int64_t i = 0; i < n; ++i) {
    p.x[i] = pos[i];
    p.radius[i] = rad[i];
    p.species[i] = sp[i];
    p.id[i] = i;
  }
  set_species_properties(s, p);
  return bed;
}

}  // namespace tumble
