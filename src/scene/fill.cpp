#include "scene/fill.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "base/error.hpp"
#include "base/memory.hpp"

namespace tumble {

namespace {

// The sphere's particle numbers: the solid volume of the bed shared by species (also the
// estimate's count, so it needs nothing but arithmetic).
void bed_counts(const Scene& s, std::int64_t& n_large, std::int64_t& n_small) {
  const double R = s.radius;
  const double v_small = kPi / 6.0 * std::pow(s.d_small, 3);
  const double v_large = kPi / 6.0 * std::pow(s.d_large, 3);
  const double v_solid = s.packing_fraction * s.fill_level * 4.0 / 3.0 * kPi * R * R * R;
  n_large = std::llround(s.large_fraction * v_solid / v_large);
  n_small = std::llround((1.0 - s.large_fraction) * v_solid / v_small);
}

}  // namespace

// Placement: a cubic lattice of sites of side 1.02 d_large covers the tumbler; a site holds one
// large particle or a k x k x k block of small ones (slots). Sites are visited bottom first and
// filled until every particle is placed, so the bed starts near its final shape and settles in a
// fraction of a second. Slots and large particles must lie inside the sphere individually, so the
// curved wall is filled down to the size of the small particles.
BedPlan plan_bed(const Scene& s, bool positions) {
  BedPlan plan;
  const double R = s.radius;
  bed_counts(s, plan.n_large, plan.n_small);

  const double a = 1.02 * s.d_large;
  const int k = std::max(1, static_cast<int>(std::floor(a / (1.01 * s.d_small))));
  const double sub = a / k;
  plan.site = a;
  plan.small_per_side = k;
  const double reach_large = R - 0.51 * s.d_large;
  const double reach_small = R - 0.51 * s.d_small;
  const int m = static_cast<int>(std::ceil(R / a));

  Rng rng(static_cast<std::uint64_t>(s.seed));
  std::int64_t large_left = plan.n_large, small_left = plan.n_small;
  // For the "large_top" start the small particles go first, so the large ones end up on top.
  const bool small_first = s.start == Start::large_top;
  const double k3 = static_cast<double>(k) * k * k;
  std::vector<Vec3> smalls;
  // One site: a large particle, or up to k^3 small ones in the slots inside the sphere.
  auto fill_site = [&](const Vec3& c) {
    const bool fits_large = norm(c) < reach_large;
    bool put_large = false;
    if (fits_large && large_left > 0) {
      if (s.start == Start::mixed)  // chance proportional to the sites each species still needs
        put_large = rng.uniform() * (large_left + small_left / k3) < large_left;
      else if (s.start == Start::large_xneg)
        put_large = c.x < 0 || small_left == 0;
      else
        put_large = small_left == 0;
    }
    if (small_first && small_left > 0) put_large = false;
    if (put_large) {
      if (positions) {
        plan.position.push_back(c);
        plan.species.push_back(1);
      }
      --large_left;
      return;
    }
    for (int x = 0; x < k && small_left > 0; ++x)
      for (int y = 0; y < k && small_left > 0; ++y)
        for (int z = 0; z < k && small_left > 0; ++z) {
          const Vec3 q = c + Vec3{(x + 0.5) * sub - 0.5 * a, (y + 0.5) * sub - 0.5 * a,
                                  (z + 0.5) * sub - 0.5 * a};
          if (norm(q) < reach_small) {
            if (positions) smalls.push_back(q);
            --small_left;
          }
        }
  };
  // Sites are visited bottom first (gravity is -y), ties broken by x then z, so the order is fully
  // determined: the loops run over y, then x, then z (the order a sort of the sites gives) and no
  // list of sites is held, so a plan costs memory only for its particles.
  for (int j = -m; j < m && (large_left > 0 || small_left > 0); ++j)
    for (int i = -m; i < m && (large_left > 0 || small_left > 0); ++i)
      for (int l = -m; l < m && (large_left > 0 || small_left > 0); ++l) {
        const Vec3 c{(i + 0.5) * a, (j + 0.5) * a, (l + 0.5) * a};
        if (norm(c) < reach_small + 0.87 * a) fill_site(c);
      }
  if (large_left > 0 || small_left > 0) {
    std::ostringstream os;
    os << "scene error: the bed does not fit in the tumbler: " << plan.n_large << " large and "
       << plan.n_small << " small particles (particles.fill_level = " << s.fill_level
       << ", particles.packing_fraction = " << s.packing_fraction << "), " << large_left
       << " large and " << small_left
       << " small left over once the loose start lattice fills the tumbler; lower "
          "particles.fill_level or particles.packing_fraction, or enlarge tumbler.radius";
    throw InputError(os.str());
  }
  for (const Vec3& q : smalls) {
    plan.position.push_back(q);
    plan.species.push_back(0);
  }
  return plan;
}

std::int64_t planned_particle_count(const Scene& s) {
  if (s.cylinder()) return s.count;
  std::int64_t n_large = 0, n_small = 0;
  bed_counts(s, n_large, n_small);
  return n_large + n_small;
}

namespace {
double g_memory_limit = 0;
std::string g_memory_origin;
}  // namespace

ResourceEstimate estimate_resources(const Scene& s) {
  ResourceEstimate e;
  if (!s.bed_file.empty()) {
    // A given bed's size is known only once it is read (its loader checks it); the grid is not.
  } else if (s.cylinder()) {
    e.particles = static_cast<double>(s.count);
  } else {  // as bed_counts, in doubles: a huge scene must not overflow before it is refused
    const double R = s.radius;
    const double v_solid = s.packing_fraction * s.fill_level * 4.0 / 3.0 * kPi * R * R * R;
    e.particles = s.large_fraction * v_solid / (kPi / 6.0 * std::pow(s.d_large, 3)) +
                  (1.0 - s.large_fraction) * v_solid / (kPi / 6.0 * std::pow(s.d_small, 3));
  }
  // The engine's grid (engine/simulation.cpp): cells of 2 r_max + skin over the box of the wall
  // plus one skin.
  const double skin = s.skin * s.d_small, cell = s.d_large + skin;
  const double side = std::max(1.0, std::floor(2 * (s.radius + skin) / cell));
  const double axial =
      s.cylinder() ? std::max(1.0, std::floor((s.length + 2 * skin) / cell)) : side;
  e.cells = side * side * axial;
  e.bytes = e.particles * kBytesPerParticle + e.cells * kBytesPerCell;
  if (!s.cylinder() &&
      s.bed_file
          .empty()) {  // the plan: a position and a species per particle while the bed is made
    e.bytes += e.particles * (sizeof(Vec3) + sizeof(std::int32_t));
  }
  return e;
}

void set_memory_limit(double bytes, const std::string& origin) {
  g_memory_limit = bytes;
  g_memory_origin = origin;
}

void check_resources(const Scene& s) {
  const ResourceEstimate e = estimate_resources(s);
  const double per_particle =
      e.particles > 0 ? (e.bytes - e.cells * kBytesPerCell) / e.particles : kBytesPerParticle;
  std::ostringstream est;
  est.precision(3);
  est << "about " << format_bytes(e.bytes) << " (" << e.particles << " particles, " << e.cells
      << " neighbour cells; " << per_particle << " B per particle, " << kBytesPerCell
      << " B per cell)";
  const char* fix =
      "; enlarge particles.d_small / particles.d_large, or reduce tumbler.radius, "
      "particles.fill_level or particles.count";
  // Particles and cells are indexed by uint32 in the neighbour grid and list.
  const double index_limit = 4294967295.0;
  if (!(e.particles < index_limit) || !(e.cells < index_limit))
    throw InputError("scene error: the scene is too large: it would need " + est.str() +
                     ", and the particle and cell indices hold at most 4294967295" + fix);
  if (g_memory_limit > 0 && !(e.bytes <= g_memory_limit))
    throw InputError("scene error: the scene would need " + est.str() + ", more memory than " +
                     g_memory_origin + " (" + format_bytes(g_memory_limit) + ")" + fix);
}

void set_species_properties(const Scene& s, Particles& p) {
  const double ms = s.mass_small(), ml = s.mass_large();
  const double rho[2] = {s.density, s.density * s.density_ratio};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool large = p.species[i] == 1;
    double m = large ? ml : ms;
    if (s.size_spread > 0) {  // polydisperse: the radius is the particle's own
      const double d = 2.0 * p.radius[i];
      m = rho[large ? 1 : 0] * kPi / 6.0 * d * d * d;
    } else {
      p.radius[i] = 0.5 * (large ? s.d_large : s.d_small);
    }
    p.inv_mass[i] = 1.0 / m;
    p.inv_inertia[i] = 1.0 / (0.4 * m * p.radius[i] * p.radius[i]);
  }
}

Particles make_bed(const Scene& s) {
  const BedPlan plan = plan_bed(s);
  // The jitter draws continue the plan's stream from a second, independent generator.
  Rng rng(static_cast<std::uint64_t>(s.seed) ^ 0xA5A5A5A5DEADBEEFull);
  const double sub = plan.site / plan.small_per_side;
  const double slack[2] = {0.45 * (sub - s.d_small), 0.45 * (plan.site - s.d_large)};
  const double reach[2] = {s.radius - 0.5 * s.d_small, s.radius - 0.5 * s.d_large};
  Particles p;
  p.resize(plan.position.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const int sp = plan.species[i];
    const double amp = slack[sp];
    Vec3 x = plan.position[i] + Vec3{amp * (2 * rng.uniform() - 1), amp * (2 * rng.uniform() - 1),
                                     amp * (2 * rng.uniform() - 1)};
    if (norm(x) >= reach[sp]) x = plan.position[i];  // jitter never pushes into the wall
    p.x[i] = x;
    p.species[i] = sp;
    p.id[i] = static_cast<std::int64_t>(i);
  }
  set_species_properties(s, p);
  return p;
}

}  // namespace tumble
