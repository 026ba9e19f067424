// `tumble analyze classify|section|light|enrichment|campaign`: the analyses of Yu 2022 that
// compare DEM particles with the CM islands, on snapshots or a campaign directory
// (docs/report.md). Thin: parse, validate, call src/analysis, print and write.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/light_concentration.hpp"
#include "app/commands.hpp"
#include "app/output_file.hpp"
#include "base/error.hpp"
#include "cm/cm_io.hpp"
#include "islands/analysis_io.hpp"
#include "islands/campaign_analysis.hpp"
#include "islands/cm_islands.hpp"

namespace tumble::app {

namespace {

using namespace tumble::analysis;

template <class T>
void require(bool ok, const std::string& option, const std::string& allowed, T value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "must be " << allowed << " (got " << value << ")";
  throw CLI::ValidationError(option, msg.str());
}

// The analyses of this file map the spherical tumbler (Lambert maps, the shell near its wall), and
// all but `light` the islands of the biaxial protocol's (θz, θx): a snapshot of a cylinder, or of
// another protocol, gave numbers that mean nothing (or ran minutes for them). Refused, naming it.
void require_sphere(const SnapshotData& s, bool biaxial) {
  if (s.shape != "sphere")
    throw InputError("'" + s.path + "' is a snapshot of tumbler.shape = " + s.shape +
                     ": this analysis maps the spherical tumbler (the cylinder's segregation, "
                     "S_a and S_r, is in its run's results.h5: postproc/plot_cylinder.py)");
  if (biaxial && s.mode != "biaxial")
    throw InputError("'" + s.path + "' is a snapshot of protocol.mode = " + s.mode +
                     ": the islands are those of the biaxial protocol's (theta_z, theta_x)");
}

// Where the islands come from: a given orbits file, or the protocol of the snapshot (computed
// once and cached in --islands-cache, the directory `tumble cm orbits` writes to by default).
struct IslandArgs {
  std::string file, cache = "results/cm";
  double r = 0.95;
  void add(CLI::App* cmd) {
    cmd->add_option("--islands", file, "orbits file of `tumble cm orbits` (default: computed)")
        ->check(CLI::ExistingFile);
    cmd->add_option("--islands-cache", cache, "where computed islands are cached");
    cmd->add_option("--r", r, "CM shell of the islands");
  }
  // Before any snapshot is read or island computed (an orbit search takes minutes).
  void validate() const { require(r > 0.15 && r < 1, "--r", "in (0.15, 1)", r); }
  std::vector<cm::Island> all(const SnapshotData& s, bool kam) const {
    if (!file.empty()) return load_islands(file);
    CmIslandOptions o;
    o.r = r;
    o.kam = kam;
    return protocol_islands(s.theta_z, s.theta_x, o, cache);
  }
};

void register_classify(CLI::App& an) {
  struct Args {
    IslandArgs islands;
    std::string from, to, out;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = an.add_subcommand("classify", "Fig. 8: persistent / captured / dispersed / other");
  cmd->add_option("FROM", a->from, "snapshot at the first iteration")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("TO", a->to, "snapshot at the last iteration")
      ->required()
      ->check(CLI::ExistingFile);
  a->islands.add(cmd);
  cmd->add_option("-o,--output", a->out, "HDF5 output (per-particle fates and the counts)");
  cmd->callback([a] {
    a->islands.validate();
    if (!a->out.empty()) prepare_output_file(a->out);
    const SnapshotData s0 = read_snapshot(a->from), s1 = read_snapshot(a->to);
    require_sphere(s0, true);
    require_sphere(s1, true);
    // (The mixture's mapped species, as a campaign counts: species 1 of a density-bidisperse bed
    // is its heavy majority. The mask groups chain islands with their primary, as a campaign's.)
    const int mapped = s0.mixture.mapped;
    const IslandMask mask = shell_mask(a->islands.all(s0, false), a->islands.r);
    const FateResult r = classify_fates(s0, s1, mask, mapped);
    const auto& c = r.counts;
    std::printf("islands: %d covering %.4f of the view from below\n", mask.size(),
                mask.area_fraction());
    const FateExpectation e = chance_fates(r);
    std::printf(
        "iterations %.3g -> %.3g, %lld %s particles: persistent (same island) %lld, switched "
        "island %lld, captured %lld, dispersed %lld, other %lld\n"
        "by chance (end positions relabelled at random): persistent %.1f, switched %.1f, "
        "captured %.1f, dispersed %.1f, other %.1f\n",
        s0.iteration, s1.iteration, static_cast<long long>(c.total()),
        s0.mixture.name[mapped].c_str(), static_cast<long long>(c.persistent),
        static_cast<long long>(c.switched), static_cast<long long>(c.captured),
        static_cast<long long>(c.dispersed), static_cast<long long>(c.other), e.persistent,
        e.switched, e.captured, e.dispersed, e.other);
    if (!a->out.empty()) {
      write_fates(a->out, s0, s1, r);
      std::printf("wrote %s\n", a->out.c_str());
    }
  });
}

void register_section(CLI::App& an) {
  struct Args {
    IslandArgs islands;
    std::vector<std::string> snaps;
    std::vector<int> pair;
    int grid = 40;
    double half_width = 1.0;
    std::string out = "section.h5";
  };
  auto a = std::make_shared<Args>();
  auto* cmd = an.add_subcommand("section", "Fig. 5: c_L in the plane through two islands");
  cmd->add_option("SNAPSHOTS", a->snaps, "snapshots to average")
      ->required()
      ->check(CLI::ExistingFile);
  a->islands.add(cmd);
  cmd->add_option("--pair", a->pair,
                  "the two islands (indices on shell --r; default: the two "
                  "farthest apart of different orbits)")
      ->expected(2);
  cmd->add_option("--grid", a->grid, "bins per in-plane axis");
  cmd->add_option("--half-width", a->half_width, "slab half-width, in large diameters");
  cmd->add_option("-o,--output", a->out, "HDF5 output");
  cmd->callback([a] {
    require(a->grid >= 4 && a->grid <= 1000, "--grid", "in [4, 1000]", a->grid);
    require(a->half_width > 0 && a->half_width <= 100, "--half-width", "in (0, 100]",
            a->half_width);
    a->islands.validate();
    // What can be checked before the islands are known (their search takes minutes): two
    // different indices, not negative. The upper bound (the island count) is checked below.
    if (a->pair.size() == 2)
      require(a->pair[0] >= 0 && a->pair[1] >= 0 && a->pair[0] != a->pair[1], "--pair",
              "two different island indices >= 0",
              std::to_string(a->pair[0]) + " " + std::to_string(a->pair[1]));
    prepare_output_file(a->out);
    std::vector<SnapshotData> snaps;
    for (const auto& p : a->snaps) {
      snaps.push_back(read_snapshot(p));
      require_sphere(snaps.back(), true);
    }
    const auto all = a->islands.all(snaps.front(), true);
    const auto shell = cm::islands_on_shell(all, a->islands.r);
    require(shell.size() >= 2, "--islands", "a protocol with at least two islands", shell.size());
    auto [ia, ib] = farthest_island_pair(shell);
    if (a->pair.size() == 2) {
      ia = a->pair[0];
      ib = a->pair[1];
      const int n = static_cast<int>(shell.size());
      require(ia >= 0 && ia < n && ib >= 0 && ib < n && ia != ib, "--pair",
              "two different island indices below " + std::to_string(n), ia);
    } else if (ia < 0) {
      ia = 0;  // one orbit only: its first two islands
      ib = 1;
    }
    const SectionPlane plane = plane_through_islands(shell[ia], shell[ib]);
    // The slab is measured in large diameters: twice the largest radius in the snapshot.
    double rmax = 0;
    for (double r : snaps.front().radius) rmax = std::max(rmax, r);
    const double hw = a->half_width * 2 * rmax;
    SectionMap map(a->grid);
    for (const auto& s : snaps) map.add(s, plane, hw);
    const auto tubes = tube_crossings(all, plane);
    write_section(a->out, a->snaps, map, plane, hw, tubes, ia, ib);
    std::printf("plane through islands %d and %d; %zu tube boundary points; wrote %s\n", ia, ib,
                tubes.size(), a->out.c_str());
  });
}

void register_light(CLI::App& an) {
  struct Args {
    std::vector<std::string> snaps;
    int grid = 24;
    double inner = 0.97;
    std::string out = "light.h5";
  };
  auto a = std::make_shared<Args>();
  auto* cmd =
      an.add_subcommand("light", "Fig. 13: lighter-particle concentration (density-bidisperse)");
  cmd->add_option("SNAPSHOTS", a->snaps, "snapshots to average")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--grid", a->grid, "N of the N x N Lambert grid");
  cmd->add_option("--inner", a->inner, "shell inner radius r/R (Fig. 13: one diameter, 0.97)");
  cmd->add_option("-o,--output", a->out, "HDF5 output");
  cmd->callback([a] {
    require(a->grid >= 2 && a->grid <= 1000, "--grid", "in [2, 1000]", a->grid);
    require(a->inner >= 0 && a->inner < 1, "--inner", "in [0, 1)", a->inner);
    prepare_output_file(a->out);
    std::vector<SnapshotData> snaps;
    for (const auto& p : a->snaps) {
      snaps.push_back(read_snapshot(p));
      require_sphere(snaps.back(), false);
    }
    const int light = lighter_species(snaps.front().density_ratio);
    require(light >= 0, "SNAPSHOTS", "of a density-bidisperse bed (particles.density_ratio != 1)",
            snaps.front().density_ratio);
    const auto c = light_concentration(snaps, LambertGrid(a->grid), a->inner);
    write_light(a->out, a->snaps, c, a->grid, light, a->inner);
    std::printf("lighter species %d over %zu snapshots; wrote %s\n", light, snaps.size(),
                a->out.c_str());
  });
}

void register_enrichment(CLI::App& an) {
  struct Args {
    IslandArgs islands;
    std::vector<std::string> snaps;
    double inner = 0.9;
    std::string out;
  };
  auto a = std::make_shared<Args>();
  auto* cmd =
      an.add_subcommand("enrichment",
                        "large share inside the islands / islands' area share, per snapshot "
                        "(e.g. the last snapshot of each replica) with its 95% CI");
  cmd->add_option("SNAPSHOTS", a->snaps, "snapshots (one per replica)")
      ->required()
      ->check(CLI::ExistingFile);
  a->islands.add(cmd);
  cmd->add_option("--inner", a->inner, "shell inner radius r/R");
  cmd->add_option("-o,--output", a->out, "HDF5 output");
  cmd->callback([a] {
    require(a->inner >= 0 && a->inner < 1, "--inner", "in [0, 1)", a->inner);
    a->islands.validate();
    if (!a->out.empty()) prepare_output_file(a->out);
    // Every snapshot checked before the first islands are computed (minutes).
    std::vector<SnapshotData> snaps;
    for (const auto& p : a->snaps) {
      snaps.push_back(read_snapshot(p));
      require_sphere(snaps.back(), true);
    }
    std::vector<Enrichment> values;
    std::vector<double> v;
    for (const SnapshotData& s : snaps) {
      const std::string& p = s.path;
      const IslandMask mask = shell_mask(a->islands.all(s, false), a->islands.r);
      values.push_back(enrichment_from_particles(s, mask, a->inner, s.mixture.mapped));
      v.push_back(values.back().value);
      std::printf("%s: enrichment %.4f (inside %.4f of %g %s, islands %.4f of the view)\n",
                  p.c_str(), values.back().value, values.back().inside_share, values.back().counted,
                  s.mixture.name[s.mixture.mapped].c_str(), values.back().area_share);
    }
    const MeanCI m = mean_ci95(v);
    std::printf("mean %.4f +- %.4f (95%% CI, N = %d)\n", m.mean, m.ci95, m.n);
    if (!a->out.empty()) {
      write_enrichment(a->out, a->snaps, values, m, a->inner);
      std::printf("wrote %s\n", a->out.c_str());
    }
  });
}

void register_campaign_analysis(CLI::App& an) {
  struct Args {
    std::string dir, out;
    CampaignAnalysisOptions opt;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = an.add_subcommand("campaign",
                                "every analysis for every case of a campaign "
                                "directory, with 95% CIs per parameter point");
  cmd->add_option("DIR", a->dir, "campaign directory")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", a->out, "HDF5 output (default DIR/analysis.h5)");
  cmd->add_option("--from", a->opt.fates_from,
                  "Fig. 8 start iteration (default, with no --to either: the first snapshot at "
                  "or after iteration 7, once radial segregation has settled as in Yu 2022, "
                  "that leaves a whole number of the islands' period to the last one; a shorter "
                  "run: the earliest that does; else the first snapshot)");
  cmd->add_option("--to", a->opt.fates_to, "Fig. 8 end iteration (default: last snapshot)");
  cmd->add_option("--r", a->opt.islands.r, "CM shell of the islands");
  cmd->add_option("--light-inner", a->opt.light_inner,
                  "Fig. 13 shell r/R from snapshots (default -1: one light-particle diameter, "
                  "1 - d/R; 0.97 for Yu 2022's 2 mm grains)");
  cmd->add_option("--islands-cache", a->opt.islands_cache,
                  "where computed islands are cached (default DIR/analysis)");
  cmd->add_option("--section-grid", a->opt.section_grid,
                  "Fig. 5 bins per in-plane axis (default 0: one per large diameter)");
  cmd->add_option("--section-half-width", a->opt.section_half_width,
                  "Fig. 5 slab half-width, in large diameters");
  cmd->add_option("--dpsi-lags", a->opt.dpsi_lags,
                  "Figs. 6-7 from the snapshots: Delta psi over each lag (iterations, e.g. 6 18), "
                  "summed over every start in the Fig. 8 window whose end is in it, inside and "
                  "outside the islands (default: none; the fields' lags are the report's)");
  cmd->add_option("--dpsi-inner", a->opt.dpsi_inner,
                  "Delta psi of the particles with r/R >= this at the start");
  cmd->callback([a] {
    require(a->opt.islands.r > 0.15 && a->opt.islands.r < 1, "--r", "in (0.15, 1)",
            a->opt.islands.r);
    for (const double lag : a->opt.dpsi_lags)
      require(lag > 0 && lag <= 1000, "--dpsi-lags", "in (0, 1000] iterations", lag);
    require(a->opt.dpsi_inner >= 0 && a->opt.dpsi_inner < 1, "--dpsi-inner", "in [0, 1)",
            a->opt.dpsi_inner);
    require(a->opt.section_grid == 0 || (a->opt.section_grid >= 4 && a->opt.section_grid <= 1000),
            "--section-grid", "0 (one bin per large diameter) or in [4, 1000]",
            a->opt.section_grid);
    require(a->opt.section_half_width > 0 && a->opt.section_half_width <= 100,
            "--section-half-width", "in (0, 100]", a->opt.section_half_width);
    require(a->opt.light_inner == -1 || (a->opt.light_inner >= 0 && a->opt.light_inner < 1),
            "--light-inner", "-1 (one diameter) or in [0, 1)", a->opt.light_inner);
    // < 0 (the default) means the first / last snapshot; any other value is an iteration.
    require(a->opt.fates_to < 0 || a->opt.fates_from <= a->opt.fates_to, "--from",
            "<= --to (iterations)", a->opt.fates_from);
    const std::string out = a->out.empty() ? a->dir + "/analysis.h5" : a->out;
    prepare_output_file(out);
    const auto points = analyze_campaign(a->dir, a->opt);
    require(!points.empty(), "DIR", "a campaign directory with finished cases (cases/*/fields.h5)",
            a->dir);
    for (const auto& p : points) {
      std::printf(
          "point %s (%s): %zu cases, %zu islands (%.3f of the view), enrichment of the %s "
          "particles %.3f +- %.3f (N = %d)\n",
          p.point_id.c_str(), p.params.c_str(), p.cases.size(), p.islands.size(),
          p.island_area_fraction, p.mixture.name[p.mixture.mapped].c_str(), p.enrichment_map.mean,
          p.enrichment_map.ci95, p.enrichment_map.n);
      std::printf("point %s mixture: %s\n", p.point_id.c_str(), p.mixture.describe().c_str());
      if (p.repose_min == p.repose_max)
        std::printf("point %s repose tilt beta %.4g deg in every case\n", p.point_id.c_str(),
                    p.repose_min);
      else
        std::printf(
            "point %s repose tilt beta %.3f +- %.3f deg (N = %d; %.2f to %.2f: measured "
            "on each replica's bed)\n",
            p.point_id.c_str(), p.repose.mean, p.repose.ci95, p.repose.n, p.repose_min,
            p.repose_max);
      if (p.enrichment_window.n > 0)
        std::printf(
            "point %s enrichment from the snapshots of the collection window (stroboscopic): "
            "%.3f +- %.3f (N = %d)\n",
            p.point_id.c_str(), p.enrichment_window.mean, p.enrichment_window.ci95,
            p.enrichment_window.n);
      if (p.shell_ratio.n > 0) {
        const int m = p.mixture.mapped;
        std::printf(
            "point %s radial segregation (window snapshots, the enrichment's shell): %s in the "
            "shell %.3f, %s %.3f; ratio %.2f +- %.2f (N = %d; 1 = no preference)\n",
            p.point_id.c_str(), p.mixture.name[m].c_str(), p.shell_share_mapped.mean,
            p.mixture.name[1 - m].c_str(), p.shell_share_other.mean, p.shell_ratio.mean,
            p.shell_ratio.ci95, p.shell_ratio.n);
      }
      if (!p.light_source.empty())
        std::printf("point %s light-particle map (Fig. 13) from %s\n", p.point_id.c_str(),
                    p.light_source.c_str());
    }
    for (const auto& p : points) {
      if (p.fates[0].n == 0) continue;
      const MeanCI* f = p.fates;
      const MeanCI* c = p.fates_by_chance;
      std::printf(
          "point %s Fig. 8 (mean +- 95%% CI, N = %d): persistent %.1f +- %.1f (chance %.1f), "
          "switched %.1f +- %.1f (chance %.1f), captured %.1f +- %.1f (chance %.1f), dispersed "
          "%.1f +- %.1f (chance %.1f), other %.1f +- %.1f (chance %.1f)\n",
          p.point_id.c_str(), f[0].n, f[0].mean, f[0].ci95, c[0].mean, f[4].mean, f[4].ci95,
          c[4].mean, f[1].mean, f[1].ci95, c[1].mean, f[2].mean, f[2].ci95, c[2].mean, f[3].mean,
          f[3].ci95, c[3].mean);
      // A window asked for that a case's snapshots do not reach (a shorter run, a continuation
      // not joined) is compared at the nearest snapshots instead: say so, per case.
      for (const auto& cs : p.cases) {
        if (!cs.has_fates) continue;
        const bool from_off =
            a->opt.fates_from >= 0 && std::fabs(cs.fates_from - a->opt.fates_from) > 1e-3;
        const bool to_off = a->opt.fates_to >= 0 && std::fabs(cs.fates_to - a->opt.fates_to) > 1e-3;
        if (from_off || to_off)
          std::printf(
              "warning: point %s case %s: no snapshot at the window's %s (%g); its Fig. 8 and "
              "Delta psi window is %g -> %g, the nearest snapshots\n",
              p.point_id.c_str(), cs.case_id.c_str(), from_off ? "start" : "end",
              from_off ? a->opt.fates_from : a->opt.fates_to, cs.fates_from, cs.fates_to);
      }
      // "The same island" holds only over whole periods: a period-3 island sits elsewhere after
      // 1 or 2 iterations, and its particles would be counted as switched.
      for (const auto& cs : p.cases) {
        const double span = cs.fates_to - cs.fates_from;
        // Snapshot times sit within a time step of whole iterations: 1e-3 iterations is slack.
        if (cs.has_fates && p.island_period > 0 &&
            std::fabs(span - p.island_period * std::round(span / p.island_period)) > 1e-3) {
          std::printf(
              "warning: point %s: the Fig. 8 window %g -> %g is not a whole number of the "
              "islands' period (%d iterations): persistent and switched mix islands that "
              "trade places; choose --from/--to %d iterations apart (or a multiple)\n",
              p.point_id.c_str(), cs.fates_from, cs.fates_to, p.island_period, p.island_period);
          break;
        }
      }
    }
    for (const auto& p : points)
      for (const auto& d : p.dpsi) {
        if (d.contrast[1].n + d.contrast[0].n == 0) {
          std::printf(
              "warning: point %s: no start in the Fig. 8 window has a snapshot %g iterations "
              "later: no Delta psi over that lag (widen --from/--to or continue the runs)\n",
              p.point_id.c_str(), d.lag);
          continue;
        }
        for (int sp = 1; sp >= 0; --sp)
          std::printf(
              "point %s Delta psi over %g iterations from snapshots (%d-%d starts per case), "
              "%s: inside %.1f +- %.1f, outside %.1f +- %.1f, contrast outside - inside %+.1f "
              "+- %.1f deg (N = %d)\n",
              p.point_id.c_str(), d.lag, d.starts_min, d.starts_max, p.mixture.name[sp].c_str(),
              d.inside[sp].mean, d.inside[sp].ci95, d.outside[sp].mean, d.outside[sp].ci95,
              d.contrast[sp].mean, d.contrast[sp].ci95, d.contrast[sp].n);
      }
    for (const auto& p : points)
      for (const auto& [qid, m] : p.enrichment_vs)
        if (qid != p.point_id)
          std::printf("point %s against the islands of %s: enrichment %.3f +- %.3f (N = %d)\n",
                      p.point_id.c_str(), qid.c_str(), m.mean, m.ci95, m.n);
    write_campaign_analysis(out, a->dir, points);
    std::printf("wrote %s\n", out.c_str());
  });
}

}  // namespace

void register_analyze(CLI::App& app) {
  auto* an =
      app.add_subcommand("analyze",
                         "analyses against the CM islands: Fig. 8 fates, Fig. 5 section, Fig. 13 "
                         "lighter-particle concentration, island enrichment (docs/report.md)");
  an->require_subcommand(1);
  register_classify(*an);
  register_section(*an);
  register_light(*an);
  register_enrichment(*an);
  register_campaign_analysis(*an);
}

}  // namespace tumble::app
