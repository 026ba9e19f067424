#include "islands/campaign_analysis.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numeric>

#include "analysis/light_concentration.hpp"
#include "analysis/radial_segregation.hpp"
#include "analysis/snapshot_data.hpp"
#include "base/error.hpp"
#include "base/text_util.hpp"
#include "base/version.hpp"
#include "cm/cm_io.hpp"
#include "h5/hdf5_file.hpp"
#include "islands/enrichment.hpp"
#include "scene/scene.hpp"

namespace tumble::analysis {

namespace fs = std::filesystem;

namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kDeg = 180.0 / 3.14159265358979323846;

// A case's Δψ of one lag, or nullptr.
const CaseDpsi* find_lag(const std::vector<CaseDpsi>& v, double lag) {
  for (const auto& d : v)
    if (d.lag == lag) return &d;
  return nullptr;
}

// A Δψ map the run collected (fields.h5 displacement*): per cell of the start grid, the mean Δψ
// [rad] and the particle count, by species (index 1 the large one).
struct FieldsDpsiMap {
  double lag = 0;  // iterations
  int intervals = 0;
  std::vector<double> mean[2], count[2];
};

// What one finished case's fields file says about it.
struct CaseFields {
  std::string dir, case_id, point_id, params, scene_text;
  long long replica = 0;
  int grid_n = 0;
  double shell_inner = 0.9;
  double window_first = -1, window_last = -1;  // the fields' collection window (iterations)
  std::vector<double> volume_large, volume_small, c_L, c_S;
  std::vector<FieldsDpsiMap> dpsi;  // the Δψ maps collected during the run, one per lag
};

std::vector<FieldsDpsiMap> read_dpsi_maps(const io::H5File& f) {
  // One group per collected lag: "displacement", "displacement_k6", ... (field_collector.cpp).
  std::vector<FieldsDpsiMap> out;
  for (const auto& g : f.children("/")) {
    if (g.rfind("displacement", 0) != 0 || !f.exists(g + "/dpsi_large")) continue;
    FieldsDpsiMap m;
    m.lag = f.attr_double(g, "periods");
    m.intervals = static_cast<int>(f.attr_int64(g, "intervals"));
    const char* name[2] = {"small", "large"};
    for (int sp = 0; sp < 2; ++sp) {
      m.mean[sp] = f.read_double(g + "/dpsi_" + name[sp]);
      m.count[sp] = f.read_double(g + "/count_" + name[sp]);
    }
    out.push_back(std::move(m));
  }
  return out;
}

std::vector<CaseFields> read_cases(const std::string& dir) {
  std::vector<CaseFields> out;
  const fs::path cases = fs::path(dir) / "cases";
  if (!fs::is_directory(cases)) return out;
  for (const auto& e : fs::directory_iterator(cases)) {
    const fs::path fp = e.path() / "fields.h5";
    if (!fs::exists(fp)) continue;  // not finished (or failed): not part of the ensemble
    io::H5File f(fp.string(), io::H5File::Mode::Read);
    // Every analysis here sets the maps against the CM islands, which sit still in the lab frame
    // at the end of each iteration; in the tumbler's frame they turn with it.
    if (const std::string frame = f.has_attr("/", "frame") ? f.attr_string("/", "frame") : "lab";
        frame != "lab")
      throw InputError("'" + dir + "': its fields were collected with collect.frame = \"" + frame +
                       "\" (" + fp.string() +
                       "); `tumble analyze campaign` compares them with the continuum model's "
                       "islands, which stand still in the lab frame only: collect with frame = "
                       "\"lab\"");
    CaseFields c;
    c.dir = e.path().string();
    c.case_id = f.attr_string("/", "case_id");
    c.point_id = f.attr_string("/", "point_id");
    c.params = f.attr_string("/", "params");
    c.scene_text = f.attr_string("/", "scene");
    // A cylinder campaign's fields are its S_a, S_r series (no Lambert maps, no islands): refused
    // by name, not as a file without grid_n.
    if (parse_scene(c.scene_text).cylinder())
      throw InputError("'" + dir +
                       "' is a campaign of tumbler.shape = cylinder: `tumble analyze "
                       "campaign` maps the spherical tumbler's cases; the cylinder's S_a and S_r "
                       "are in its ensemble.h5 (series/Sa, series/Sr) and each case's results.h5 "
                       "(postproc/plot_cylinder.py)");
    c.replica = f.attr_int64("/", "replica");
    c.grid_n = static_cast<int>(f.attr_int64("/", "grid_n"));
    if (f.has_attr("/", "window_first_iteration")) {
      c.window_first = f.attr_double("/", "window_first_iteration");
      c.window_last = f.attr_double("/", "window_last_iteration");
    }
    if (f.exists("concentration/volume_large")) {
      c.volume_large = f.read_double("concentration/volume_large");
      c.volume_small = f.read_double("concentration/volume_small");
      c.c_L = f.read_double("concentration/c_L");
      c.c_S = f.read_double("concentration/c_S");
      c.shell_inner = f.attr_double("concentration", "shell_inner");
    }
    c.dpsi = read_dpsi_maps(f);
    out.push_back(std::move(c));
  }
  std::sort(out.begin(), out.end(), [](const CaseFields& a, const CaseFields& b) {
    return a.point_id != b.point_id ? a.point_id < b.point_id : a.replica < b.replica;
  });
  return out;
}

// Index of the snapshot whose iteration is nearest `want` (< 0: the first or last).
std::size_t nearest(const std::vector<double>& iters, double want, bool last) {
  if (want < 0) return last ? iters.size() - 1 : 0;
  std::size_t best = 0;
  for (std::size_t k = 1; k < iters.size(); ++k)
    if (std::abs(iters[k] - want) < std::abs(iters[best] - want)) best = k;
  return best;
}

// The Fig. 5 section of one case: the snapshots of the last half of the run (stroboscopic
// snapshots see the islands where the CM puts them; the first half is still mixing).
void add_section(CaseAnalysis& ca, const std::vector<SnapshotData>& snaps,
                 const std::vector<double>& iters, const PointAnalysis& p, int n) {
  SectionMap map(n);
  for (std::size_t k = 0; k < snaps.size(); ++k)
    if (iters[k] >= 0.5 * iters.back()) {
      map.add(snaps[k], p.section_plane, p.section_half_width);
      ++ca.section_snapshots;
    }
  ca.section = map.c_large();
}

// The Fig. 13 shell of a point: the option, or one diameter of the light species (1 - d/R).
double light_shell(const PointAnalysis& p, double radius, const CampaignAnalysisOptions& opt) {
  if (opt.light_inner >= 0) return opt.light_inner;
  const int light = p.light_species >= 0 ? p.light_species : p.mixture.mapped;
  return std::max(0.0, 1 - p.mixture.diameter[light] / radius);
}

void analyze_snapshots(CaseAnalysis& ca, const std::string& dir, const IslandMask& mask,
                       bool have_islands, const PointAnalysis& p, const LambertGrid& grid,
                       const CampaignAnalysisOptions& opt, double window_first,
                       double window_last) {
  const int light = p.light_species;
  const auto files = list_snapshots(dir);
  if (files.size() < 2) return;
  std::vector<SnapshotData> snaps;
  std::vector<double> iters;
  for (const auto& p : files) {
    snaps.push_back(read_snapshot(p));
    iters.push_back(snaps.back().iteration);
  }
  {
    // A run's end written a few steps after its last periodic snapshot is the same
    // configuration: counted once (snapshot_data.hpp).
    const std::vector<bool> repeat = repeated_snapshots(iters);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < snaps.size(); ++k)
      if (!repeat[k]) {
        if (kept != k) snaps[kept] = std::move(snaps[k]);
        iters[kept++] = iters[k];
      }
    snaps.resize(kept);
    iters.resize(kept);
  }
  // Neither end given: the paper's window (fates.hpp: default_fates_start).
  const bool default_window = opt.fates_from < 0 && opt.fates_to < 0;
  const std::size_t b = nearest(iters, opt.fates_to, true);
  const std::size_t a = default_window ? default_fates_start(iters, p.island_period)
                                       : nearest(iters, opt.fates_from, false);
  if (have_islands && a != b) {
    ca.has_fates = true;
    ca.fate_detail = classify_fates(snaps[a], snaps[b], mask, p.mixture.mapped);
    ca.fates = ca.fate_detail.counts;
    ca.fates_by_chance = chance_fates(ca.fate_detail);
    ca.fates_from = iters[a];
    ca.fates_to = iters[b];
  }
  if (have_islands)
    for (const double lag : opt.dpsi_lags) {
      const SnapshotDisplacement d =
          displacement_from_snapshots(snaps, lag, iters[a], iters[b], grid, opt.dpsi_inner);
      CaseDpsi cd;
      cd.lag = lag;
      cd.starts = d.starts;
      cd.first = d.first;
      cd.last = d.last;
      cd.species[1] = dpsi_contrast(d.map.sum_large, d.map.count_large, p.coverage);
      cd.species[0] = dpsi_contrast(d.map.sum_small, d.map.count_small, p.coverage);
      ca.dpsi.push_back(cd);
    }
  if (have_islands)
    ca.enrichment_snap =
        enrichment_from_particles(snaps.back(), mask, opt.enrichment_inner, p.mixture.mapped).value;
  // The configurations of the fields' collection window (Yu 2022 Fig. 13: 25 <= N <= 35);
  // all of them when the window is unknown or holds none.
  std::vector<SnapshotData> window;
  for (std::size_t k = 0; k < snaps.size(); ++k)
    if (window_first >= 0 && in_iteration_window(iters[k], window_first, window_last))
      window.push_back(snaps[k]);
  const bool windowed = !window.empty();
  if (have_islands) {
    // The mapped particles of every configuration of the window, pooled: the snapshots are
    // stroboscopic (one per iteration end, where the CM puts the islands), unlike a fields map
    // sampled within iterations. Shell: Fig. 13's one diameter for a density bed, else
    // opt.enrichment_inner.
    const double inner = p.mixture.kind == MixtureKind::density
                             ? light_shell(p, snaps.front().R, opt)
                             : opt.enrichment_inner;
    ca.enrichment_window =
        enrichment_pooled(windowed ? window : snaps, mask, inner, p.mixture.mapped).value;
  }
  {
    // Radial segregation by species over the same configurations and shell as enrichment_window.
    const double inner = p.mixture.kind == MixtureKind::density
                             ? light_shell(p, snaps.front().R, opt)
                             : opt.enrichment_inner;
    const int mapped = p.mixture.mapped, other = 1 - p.mixture.mapped;
    double sm = 0, so = 0;
    int n = 0;
    for (const auto& s : windowed ? window : snaps) {
      const double a = shell_share(s.x_tumbler, s.species, mapped, s.R, inner);
      const double b = shell_share(s.x_tumbler, s.species, other, s.R, inner);
      if (!std::isfinite(a) || !std::isfinite(b)) continue;
      sm += a;
      so += b;
      ++n;
    }
    ca.shell_share_mapped = n > 0 ? sm / n : kNaN;
    ca.shell_share_other = n > 0 ? so / n : kNaN;
  }
  if (light >= 0) {
    ca.light =
        light_concentration(windowed ? window : snaps, grid, light_shell(p, snaps.front().R, opt));
    ca.light_snapshots = static_cast<int>(windowed ? window.size() : snaps.size());
    ca.light_from = windowed ? window_first : iters.front();
    ca.light_to = windowed ? window_last : iters.back();
  }
  if (!p.section_plane_of.empty()) add_section(ca, snaps, iters, p, p.section_grid);
}

// Per-cell mean and CI of equally sized per-case maps (cases with another size left out).
void fold_maps(const std::vector<const std::vector<double>*>& maps, std::size_t cells,
               std::vector<double>& mean, std::vector<double>& ci95) {
  mean.assign(cells, kNaN);
  ci95.assign(cells, kNaN);
  for (std::size_t k = 0; k < cells; ++k) {
    std::vector<double> v;
    for (const auto* m : maps)
      if (m->size() == cells) v.push_back((*m)[k]);
    const MeanCI s = mean_ci95(v);
    mean[k] = s.mean;
    ci95[k] = s.ci95;
  }
}

// Largest particle radius of a case's first snapshot (0 without snapshots).
double largest_radius(const std::string& dir) {
  const auto files = list_snapshots(dir);
  if (files.empty()) return 0;
  double r = 0;
  for (double x : read_snapshot(files.front()).radius) r = std::max(r, x);
  return r;
}

// Class k (kFateNames order) of a case's counts, observed or by chance.
double fate_value(const CaseAnalysis& c, int k, bool chance) {
  if (chance) {
    const FateExpectation& e = c.fates_by_chance;
    const double v[5] = {e.persistent, e.captured, e.dispersed, e.other, e.switched};
    return v[k];
  }
  const FateCounts& f = c.fates;
  const std::int64_t v[5] = {f.persistent, f.captured, f.dispersed, f.other, f.switched};
  return static_cast<double>(v[k]);
}

std::vector<double> fate_column(const std::vector<CaseAnalysis>& cases, int k, bool chance) {
  std::vector<double> v;
  for (const auto& c : cases) v.push_back(c.has_fates ? fate_value(c, k, chance) : kNaN);
  return v;
}

// One collected Δψ map's contrast between the islands' inside and outside (dpsi_contrast, the
// weighting the snapshots' Δψ uses); NaN on both sides where the map's grid is not the islands'.
CaseDpsi fields_contrast(const FieldsDpsiMap& m, const std::vector<double>& coverage) {
  CaseDpsi cd;
  cd.lag = m.lag;
  cd.starts = m.intervals;
  cd.first = cd.last = kNaN;  // the fields' window, not individual starts
  for (int sp = 0; sp < 2; ++sp) {
    if (m.mean[sp].size() != coverage.size() || m.count[sp].size() != coverage.size()) {
      cd.species[sp] = {kNaN, kNaN};
      continue;
    }
    std::vector<double> sum(coverage.size()), count(coverage.size());
    for (std::size_t c = 0; c < coverage.size(); ++c) {
      const bool ok = std::isfinite(m.mean[sp][c]) && m.count[sp][c] > 0;
      count[c] = ok ? m.count[sp][c] : 0;
      sum[c] = ok ? m.mean[sp][c] * m.count[sp][c] : 0;
    }
    cd.species[sp] = dpsi_contrast(sum, count, coverage);
  }
  return cd;
}

// One lag's Δψ of a point's cases [deg] (cases without it, or with no start, left out).
PointDpsi fold_dpsi(const std::vector<CaseAnalysis>& cases,
                    std::vector<CaseDpsi> CaseAnalysis::*which, double lag) {
  PointDpsi pd;
  pd.lag = lag;
  pd.starts_min = std::numeric_limits<int>::max();
  for (int sp = 0; sp < 2; ++sp) {
    std::vector<double> in, outside, contrast;
    for (const auto& c : cases) {
      const CaseDpsi* d = find_lag(c.*which, lag);
      if (d == nullptr || d->starts == 0) continue;
      in.push_back(d->species[sp].inside * kDeg);
      outside.push_back(d->species[sp].outside * kDeg);
      contrast.push_back(d->species[sp].contrast() * kDeg);
      pd.starts_min = std::min(pd.starts_min, d->starts);
      pd.starts_max = std::max(pd.starts_max, d->starts);
    }
    pd.inside[sp] = mean_ci95(in);
    pd.outside[sp] = mean_ci95(outside);
    pd.contrast[sp] = mean_ci95(contrast);
  }
  if (pd.contrast[1].n + pd.contrast[0].n == 0) pd.starts_min = 0;
  return pd;
}
}  // namespace

std::vector<PointAnalysis> analyze_campaign(const std::string& dir,
                                            const CampaignAnalysisOptions& opt) {
  const auto cases = read_cases(dir);
  std::map<std::string, PointAnalysis> points;
  const std::string cache =
      opt.islands_cache.empty() ? (fs::path(dir) / "analysis").string() : opt.islands_cache;
  double r_large = 0;    // the largest particle radius of the campaign's snapshots (Fig. 5 slab)
  int auto_grid = 1000;  // Fig. 5 default: bins of about one large diameter (finest bed's)

  // Pass 1: the parameter points, their islands and the masks' cell coverage.
  for (const auto& c : cases) {
    auto [it, fresh] = points.try_emplace(c.point_id);
    if (!fresh) continue;
    PointAnalysis& p = it->second;
    const Scene sc = parse_scene(c.scene_text);
    p.point_id = c.point_id;
    p.params = c.params;
    p.theta_z = sc.theta_z;
    p.theta_x = sc.theta_x;
    p.density_ratio = sc.density_ratio;
    p.size_ratio = sc.d_large / sc.d_small;
    p.grid_n = c.grid_n;
    auto_grid = std::min(auto_grid, static_cast<int>(std::lround(2 * sc.radius / sc.d_large)));
    p.islands = cm::islands_on_shell(protocol_islands(p.theta_z, p.theta_x, opt.islands, cache),
                                     opt.islands.r);
    p.mixture = mixture_of(sc);
    p.light_species = lighter_species(p.density_ratio);
    for (const auto& is : p.islands)  // the primary islands' period (chains: n q)
      if (is.parent_orbit < 0)
        p.island_period = p.island_period == 0 ? is.period : std::lcm(p.island_period, is.period);
    const IslandMask mask = grouped_mask(p.islands);
    p.island_area_fraction = mask.area_fraction();
    p.coverage = mask.cell_coverage(LambertGrid(p.grid_n));
    r_large = std::max(r_large, largest_radius(c.dir));
  }

  // The Fig. 5 plane: a point's own two islands (different orbits farthest apart), else the
  // plane of the first point that has two, so that points without islands are cut alike.
  const PointAnalysis* plane_owner = nullptr;
  for (auto& [id, p] : points) {
    if (p.islands.size() < 2) continue;
    auto pair = farthest_island_pair(p.islands);
    if (pair.first < 0) pair = {0, 1};
    p.section_pair = pair;
    p.section_plane = upright(plane_through_islands(p.islands[pair.first], p.islands[pair.second]));
    p.section_plane_of = id;
    if (!plane_owner) plane_owner = &p;
  }
  for (auto& [id, p] : points) {
    if (r_large <= 0 || !plane_owner) {
      p.section_plane_of.clear();  // no snapshots, or no point with two islands: no section
      continue;
    }
    if (p.section_plane_of.empty()) {
      p.section_plane_of = plane_owner->point_id;
      p.section_pair = plane_owner->section_pair;
      p.section_plane = plane_owner->section_plane;
    }
    p.section_half_width = opt.section_half_width * 2 * r_large;
    p.section_grid = opt.section_grid > 0 ? opt.section_grid : std::clamp(auto_grid, 4, 200);
    CmIslandOptions kam = opt.islands;
    kam.kam = true;  // the tube boundaries cross the plane on the KAM shells 0.55 ... 0.95
    const PointAnalysis& owner = points.at(p.section_plane_of);
    p.section_tubes =
        tube_crossings(protocol_islands(owner.theta_z, owner.theta_x, kam, cache), p.section_plane);
  }

  // Pass 2: every case.
  for (const auto& c : cases) {
    PointAnalysis& p = points.at(c.point_id);
    const IslandMask mask = grouped_mask(p.islands);
    const LambertGrid grid(p.grid_n);
    CaseAnalysis ca;
    ca.case_id = c.case_id;
    ca.point_id = c.point_id;
    ca.params = c.params;
    ca.replica = c.replica;
    const bool have_islands = !p.islands.empty();
    // The mapped species' volume: the large particles, or the light ones of a density bed.
    const std::vector<double>& volume = p.mixture.mapped == 1 ? c.volume_large : c.volume_small;
    ca.enrichment_map =
        (have_islands && !volume.empty()) ? enrichment_from_map(volume, p.coverage).value : kNaN;
    ca.enrichment_snap = kNaN;
    ca.enrichment_window = kNaN;
    ca.shell_share_mapped = ca.shell_share_other = kNaN;
    ca.repose_deg = parse_scene(c.scene_text).repose.deg;
    if (!volume.empty())
      for (const auto& [qid, q] : points)
        if (!q.islands.empty() && q.coverage.size() == volume.size())
          ca.enrichment_vs[qid] = enrichment_from_map(volume, q.coverage).value;
    analyze_snapshots(ca, c.dir, mask, have_islands, p, grid, opt, c.window_first, c.window_last);
    if (have_islands)
      for (const auto& m : c.dpsi) ca.dpsi_fields.push_back(fields_contrast(m, p.coverage));
    if (p.light_species >= 0 && ca.light.empty() && !c.c_L.empty()) {
      ca.light = p.light_species == 1 ? c.c_L : c.c_S;
      p.light_source = "fields " + std::string(p.light_species == 1 ? "c_L" : "c_S") + ", r/R > " +
                       short_number(c.shell_inner);
    } else if (!ca.light.empty()) {
      p.light_source = "snapshots, r/R > " +
                       short_number(light_shell(p, parse_scene(c.scene_text).radius, opt)) +
                       ", iterations " + short_number(ca.light_from) + "-" +
                       short_number(ca.light_to) + " (" + std::to_string(ca.light_snapshots) +
                       " configurations)";
    }
    p.cases.push_back(std::move(ca));
  }

  std::vector<PointAnalysis> out;
  for (auto& [id, p] : points) {
    std::vector<double> em, es, ew, beta, ssm, sso, ratio;
    std::map<std::string, std::vector<double>> vs;
    std::vector<const std::vector<double>*> light, section;
    for (const auto& c : p.cases) {
      beta.push_back(c.repose_deg);
      em.push_back(c.enrichment_map);
      es.push_back(c.enrichment_snap);
      ew.push_back(c.enrichment_window);
      ssm.push_back(c.shell_share_mapped);
      sso.push_back(c.shell_share_other);
      ratio.push_back(c.shell_share_mapped / c.shell_share_other);
      for (const auto& [qid, v] : c.enrichment_vs) vs[qid].push_back(v);
      light.push_back(&c.light);
      if (!c.section.empty()) section.push_back(&c.section);
    }
    p.enrichment_map = mean_ci95(em);
    p.enrichment_snap = mean_ci95(es);
    p.enrichment_window = mean_ci95(ew);
    p.shell_share_mapped = mean_ci95(ssm);
    p.shell_share_other = mean_ci95(sso);
    p.shell_ratio = mean_ci95(ratio);
    p.repose = mean_ci95(beta);
    p.repose_min = *std::min_element(beta.begin(), beta.end());
    p.repose_max = *std::max_element(beta.begin(), beta.end());
    for (const auto& [qid, v] : vs) p.enrichment_vs[qid] = mean_ci95(v);
    for (int k = 0; k < 5; ++k) {
      p.fates[k] = mean_ci95(fate_column(p.cases, k, false));
      p.fates_by_chance[k] = mean_ci95(fate_column(p.cases, k, true));
    }
    if (!p.islands.empty()) {
      for (const double lag : opt.dpsi_lags)
        p.dpsi.push_back(fold_dpsi(p.cases, &CaseAnalysis::dpsi, lag));
      std::vector<double> lags;  // the collected lags, as the cases' fields files name them
      for (const auto& c : p.cases)
        for (const auto& d : c.dpsi_fields)
          if (std::find(lags.begin(), lags.end(), d.lag) == lags.end()) lags.push_back(d.lag);
      std::sort(lags.begin(), lags.end());
      for (const double lag : lags)
        p.dpsi_fields.push_back(fold_dpsi(p.cases, &CaseAnalysis::dpsi_fields, lag));
    }
    if (p.light_species >= 0)
      fold_maps(light, static_cast<std::size_t>(p.grid_n) * p.grid_n, p.light_mean, p.light_ci95);
    if (!section.empty()) {
      const auto cells = static_cast<std::size_t>(p.section_grid) * p.section_grid;
      fold_maps(section, cells, p.section_mean, p.section_ci95);
    }
    out.push_back(std::move(p));
  }
  return out;
}

namespace {
void write_stat(io::H5File& f, const std::string& obj, const std::string& name, const MeanCI& m) {
  f.set_attr(obj, name + "_mean", m.mean);
  f.set_attr(obj, name + "_ci95", m.ci95);
  f.set_attr(obj, name + "_n", static_cast<std::int64_t>(m.n));
}
// Fig. 5 of one point: per-bin mean and CI over its cases, the plane and the tube boundaries.
void write_section_stats(io::H5File& f, const std::string& g, const PointAnalysis& p) {
  const auto n = static_cast<hsize_t>(std::lround(std::sqrt(p.section_mean.size())));
  f.create_group(g);
  f.write(g + "/mean", p.section_mean, {n, n});
  f.write(g + "/ci95", p.section_ci95, {n, n});
  const Vec3& a = p.section_plane.e1;
  const Vec3& b = p.section_plane.e2;
  f.write(g + "/e1", std::vector<double>{a.x, a.y, a.z});
  f.write(g + "/e2", std::vector<double>{b.x, b.y, b.z});
  std::vector<double> tubes;
  for (const auto& t : p.section_tubes) tubes.insert(tubes.end(), {t.r, t.s1, t.s2});
  f.write(g + "/tube_crossings", tubes, {tubes.size() / 3, 3});
  std::vector<std::int64_t> snaps;
  for (const auto& c : p.cases) snaps.push_back(c.section_snapshots);
  f.write(g + "/snapshots", snaps);
  f.set_attr(g, "plane_of", p.section_plane_of);
  f.set_attr(g, "island_a", static_cast<std::int64_t>(p.section_pair.first));
  f.set_attr(g, "island_b", static_cast<std::int64_t>(p.section_pair.second));
  f.set_attr(g, "half_width_m", p.section_half_width);
}
// Figs. 6-7 from the snapshots, one group per lag: per case (in the order of the point's
// "cases") the starts and the inside / outside / contrast Δψ in degrees, and their statistics.
// `dpsi_fields`: the same from the maps the run collected (fields.h5 displacement*), "starts" the
// intervals each map averaged, first / last start NaN.
void write_dpsi(io::H5File& f, const std::string& g, const PointAnalysis& p,
                const std::vector<PointDpsi>& folded, std::vector<CaseDpsi> CaseAnalysis::*which,
                const std::string& definition) {
  f.create_group(g);
  f.set_attr(g, "definition", definition);
  for (const PointDpsi& pd : folded) {
    const std::string l = g + "/lag_" + short_number(pd.lag);
    f.create_group(l);
    f.set_attr(l, "lag", pd.lag);
    std::vector<std::int64_t> starts;
    std::vector<double> first, last, v[2][3];
    for (const auto& c : p.cases) {
      const CaseDpsi* d = find_lag(c.*which, pd.lag);
      const bool ok = d != nullptr && d->starts > 0;
      starts.push_back(d != nullptr ? d->starts : 0);
      first.push_back(ok ? d->first : kNaN);
      last.push_back(ok ? d->last : kNaN);
      for (int sp = 0; sp < 2; ++sp) {
        const DpsiContrast& dc = ok ? d->species[sp] : DpsiContrast{kNaN, kNaN};
        v[sp][0].push_back(dc.inside * kDeg);
        v[sp][1].push_back(dc.outside * kDeg);
        v[sp][2].push_back(dc.contrast() * kDeg);
      }
    }
    f.write(l + "/starts", starts);
    f.write(l + "/first_start", first);
    f.write(l + "/last_start", last);
    for (int sp = 0; sp < 2; ++sp) {
      const std::string name = sp == 1 ? "large" : "small";
      const MeanCI* stat[3] = {&pd.inside[sp], &pd.outside[sp], &pd.contrast[sp]};
      const char* what[3] = {"inside_", "outside_", "contrast_"};
      for (int q = 0; q < 3; ++q) {
        f.write(l + "/" + what[q] + name, v[sp][q]);
        write_stat(f, l, what[q] + name, *stat[q]);
      }
    }
  }
}
}  // namespace

void write_campaign_analysis(const std::string& path, const std::string& dir,
                             const std::vector<PointAnalysis>& points) {
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  f.set_attr("/", "kind", std::string("tumble campaign analysis"));
  f.set_attr("/", "campaign_dir", fs::absolute(dir).string());
  f.set_attr("/", "tumble_version", std::string(kVersion));
  f.set_attr("/", "git_hash", std::string(kGitHash));
  f.set_attr("/", "n_points", static_cast<std::int64_t>(points.size()));
  f.create_group("points");
  for (const auto& p : points) {
    const std::string g = "points/" + p.point_id;
    f.create_group(g);
    f.set_attr(g, "params", p.params);
    f.set_attr(g, "theta_z", p.theta_z);
    f.set_attr(g, "theta_x", p.theta_x);
    f.set_attr(g, "density_ratio", p.density_ratio);
    f.set_attr(g, "size_ratio", p.size_ratio);
    f.set_attr(g, "grid_n", static_cast<std::int64_t>(p.grid_n));
    f.set_attr(g, "island_area_fraction", p.island_area_fraction);
    f.set_attr(g, "n_islands", static_cast<std::int64_t>(p.islands.size()));
    f.set_attr(g, "light_species", static_cast<std::int64_t>(p.light_species));
    f.set_attr(g, "light_source", p.light_source);
    // Which species the enrichment counts and what each one is (scene/mixture.hpp).
    f.set_attr(g, "mixture", std::string(p.mixture.kind_name()));
    f.set_attr(g, "species_0", p.mixture.name[0]);
    f.set_attr(g, "species_1", p.mixture.name[1]);
    f.set_attr(g, "mapped_species", static_cast<std::int64_t>(p.mixture.mapped));
    f.set_attr(g, "minority_species", static_cast<std::int64_t>(p.mixture.minority));
    f.set_attr(g, "fraction_0", p.mixture.fraction[0]);
    f.set_attr(g, "fraction_1", p.mixture.fraction[1]);
    std::vector<double> verts, centre;
    std::vector<std::int64_t> offsets{0};
    for (const auto& is : p.islands) {
      for (const auto& v : is.boundary.vertices) {
        verts.push_back(v.x());
        verts.push_back(v.y());
      }
      offsets.push_back(static_cast<std::int64_t>(verts.size() / 2));
      centre.push_back(is.center.x());
      centre.push_back(is.center.y());
    }
    f.write(g + "/islands/vertices", verts, {verts.size() / 2, 2});
    f.write(g + "/islands/offsets", offsets);
    f.write(g + "/islands/center", centre, {centre.size() / 2, 2});
    const hsize_t n = p.grid_n;
    f.write(g + "/coverage", p.coverage, {n, n});
    std::string ids;
    std::vector<std::int64_t> replica, fates[5];
    std::vector<double> em, es, ew, beta, from, to, chance[5];
    for (const auto& c : p.cases) {
      ids += (ids.empty() ? "" : "\n") + c.case_id;
      beta.push_back(c.repose_deg);
      replica.push_back(c.replica);
      em.push_back(c.enrichment_map);
      es.push_back(c.enrichment_snap);
      ew.push_back(c.enrichment_window);
      const std::int64_t none = -1;
      for (int k = 0; k < 5; ++k) {
        fates[k].push_back(c.has_fates ? std::llround(fate_value(c, k, false)) : none);
        chance[k].push_back(c.has_fates ? fate_value(c, k, true) : kNaN);
      }
      from.push_back(c.has_fates ? c.fates_from : kNaN);
      to.push_back(c.has_fates ? c.fates_to : kNaN);
    }
    f.set_attr(g, "cases", ids);
    f.write(g + "/replica", replica);
    f.write(g + "/enrichment_map", em);
    f.write(g + "/enrichment_snap", es);
    write_stat(f, g, "enrichment_map", p.enrichment_map);
    write_stat(f, g, "enrichment_snap", p.enrichment_snap);
    f.write(g + "/enrichment_window", ew);
    write_stat(f, g, "enrichment_window", p.enrichment_window);
    f.write(g + "/repose_deg", beta);
    write_stat(f, g, "repose_deg", p.repose);
    std::vector<double> ssm, sso;
    for (const auto& c : p.cases) {
      ssm.push_back(c.shell_share_mapped);
      sso.push_back(c.shell_share_other);
    }
    f.write(g + "/shell_share_mapped", ssm);
    f.write(g + "/shell_share_other", sso);
    write_stat(f, g, "shell_share_mapped", p.shell_share_mapped);
    write_stat(f, g, "shell_share_other", p.shell_share_other);
    write_stat(f, g, "shell_ratio", p.shell_ratio);
    f.create_group(g + "/fates");
    f.create_group(g + "/fates/chance");
    for (int k = 0; k < 5; ++k) {
      f.write(g + "/fates/" + kFateNames[k], fates[k]);
      write_stat(f, g + "/fates", kFateNames[k], p.fates[k]);
      f.write(g + "/fates/chance/" + kFateNames[k], chance[k]);
      write_stat(f, g + "/fates/chance", kFateNames[k], p.fates_by_chance[k]);
    }
    f.set_attr(g + "/fates", "island_period", static_cast<std::int64_t>(p.island_period));
    f.set_attr(g + "/fates", "definition",
               std::string("persistent: the same CM island at both iterations; switched: another "
                           "island; chance: the expected counts for end positions relabelled at "
                           "random (fates.hpp)"));
    for (const auto& c : p.cases) {
      if (!c.has_fates) continue;  // the first case with fates, per particle, for the figure
      const FateResult& d = c.fate_detail;
      std::vector<double> xs, xe;
      for (std::size_t k = 0; k < d.id.size(); ++k) {
        xs.insert(xs.end(), {d.x_start[k].x, d.x_start[k].y, d.x_start[k].z});
        xe.insert(xe.end(), {d.x_end[k].x, d.x_end[k].y, d.x_end[k].z});
      }
      const std::string e = g + "/fates/example";
      f.write(e + "/id", d.id);
      f.write(e + "/fate", d.fate);
      f.write(e + "/x_start", xs, {d.id.size(), 3});
      f.write(e + "/x_end", xe, {d.id.size(), 3});
      f.set_attr(e, "case", c.case_id);
      f.set_attr(e, "from_iteration", c.fates_from);
      f.set_attr(e, "to_iteration", c.fates_to);
      break;
    }
    f.write(g + "/fates/from_iteration", from);
    f.write(g + "/fates/to_iteration", to);
    if (!p.light_mean.empty()) {
      f.write(g + "/light/mean", p.light_mean, {n, n});
      f.write(g + "/light/ci95", p.light_ci95, {n, n});
    }
    if (!p.enrichment_vs.empty()) f.create_group(g + "/enrichment_vs");
    for (const auto& [qid, stat] : p.enrichment_vs) {
      const std::string e = g + "/enrichment_vs/" + qid;
      std::vector<double> v;
      for (const auto& c : p.cases) {
        const auto it = c.enrichment_vs.find(qid);
        v.push_back(it == c.enrichment_vs.end() ? kNaN : it->second);
      }
      f.create_group(e);
      f.write(e + "/values", v);
      write_stat(f, e, "enrichment", stat);
    }
    if (!p.section_mean.empty()) write_section_stats(f, g + "/section", p);
    // Δψ inside / outside the islands, from the snapshots and from the collected maps.
    const std::string weighting =
        "inside / outside: each start cell's particles weighted by the share of its area inside "
        "/ outside the islands (dpsi_snapshots.hpp: dpsi_contrast)";
    const struct {
      const char* group;
      const std::vector<PointDpsi>& folded;
      std::vector<CaseDpsi> CaseAnalysis::*which;
      const char* source;
    } dpsi_kinds[2] = {
        {"/dpsi_snapshots", p.dpsi, &CaseAnalysis::dpsi,
         "from the snapshots, summed over every start in the Fig. 8 window whose end is in it; "
         "particles with r/R >= inner at the start, lab frame"},
        {"/dpsi_fields", p.dpsi_fields, &CaseAnalysis::dpsi_fields,
         "from the maps the run collected (fields.h5 displacement*: the campaign's window, its "
         "shell); starts: the intervals each map averaged"}};
    for (const auto& k : dpsi_kinds)
      if (!k.folded.empty())
        write_dpsi(
            f, g + k.group, p, k.folded, k.which,
            std::string("Delta psi [deg] over `lag` iterations ") + k.source + "; " + weighting);
  }
  out.commit();
}

}  // namespace tumble::analysis
