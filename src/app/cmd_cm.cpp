// `tumble cm poincare|orbits|manifolds|mcm|drift`: the continuum model (docs/cm.md). Thin: parse,
// validate every option against its allowed range, every input file against this run's protocol
// and the memory the run's arrays need against what is available, all before any work; call
// src/cm with a progress line for long runs; say where the results went.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/output_file.hpp"
#include "app/progress_line.hpp"
#include "base/error.hpp"
#include "base/memory.hpp"
#include "cm/cm_io.hpp"
#include "cm/file_protocol.hpp"
#include "cm/kam.hpp"
#include "cm/mcm_summary.hpp"
#include "h5/hdf5_file.hpp"

namespace tumble::app {
namespace {

using namespace tumble::cm;

// Throws the CLI11 error that names the option and what it accepts.
template <class T>
void require(bool ok, const std::string& option, const std::string& allowed, T value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "must be " << allowed << " (got " << value << ")";
  throw CLI::ValidationError(option, msg.str());
}

// What a run's arrays need: bytes, the options that set them, what is stored.
struct Need {
  double bytes;
  std::string keys, what;
};

// Options every subcommand shares: the memory a run may use and how often it says how far it is.
struct RunArgs {
  std::string max_memory;
  double progress_interval = 10;

  void add(CLI::App* cmd) {
    cmd->add_option("--max-memory", max_memory,
                    "refuse a run estimated to need more memory than this (e.g. 2G; default: "
                    "the machine's available memory)");
    cmd->add_option("--progress-interval", progress_interval,
                    "seconds between progress lines of a long run (0: none)");
  }
  void validate() const {
    require(progress_interval >= 0 && progress_interval <= 1e6, "--progress-interval",
            "in [0, 1e6] seconds", progress_interval);
  }

  // Refuses a run whose arrays would not fit in --max-memory or the machine's available memory,
  // before they are allocated (a reservation of that size ends in std::bad_alloc, or in swapping
  // for hours). The message gives the estimate, its parts and the options to lower.
  void require_memory(const std::vector<Need>& needs) const {
    double limit = 0;
    std::string origin;
    if (!max_memory.empty()) {
      limit = parse_memory_size(max_memory, "--max-memory");
      origin = "--max-memory " + max_memory;
    } else {
      limit = available_memory_bytes();
      origin = "the " + format_bytes(limit) + " available on this machine";
    }
    double total = 0;
    for (const auto& n : needs) total += n.bytes;
    if (limit <= 0 || total <= limit) return;
    const Need& largest = *std::max_element(
        needs.begin(), needs.end(), [](const Need& a, const Need& b) { return a.bytes < b.bytes; });
    std::string parts;
    for (const auto& n : needs)
      if (n.bytes >= 0.01 * total)
        parts += (parts.empty() ? "" : "; ") + format_bytes(n.bytes) + " for " + n.what;
    if (needs.size() == 1) parts = "for " + needs[0].what;
    throw CLI::ValidationError(largest.keys, "need about " + format_bytes(total) + " (" + parts +
                                                 "), more than " + origin + "; lower " +
                                                 largest.keys);
  }
};

// A file given as input must exist before any work is done (bad input, exit 2).
void require_file(const std::string& path, const std::string& option) {
  if (!std::filesystem::exists(path)) throw InputError(option + " '" + path + "': no such file");
  if (!std::filesystem::is_regular_file(path))
    throw InputError(option + " '" + path + "' is not a file (a directory?)");
}

// The drift grid of --drift (or one of --merge). A file that is no HDF5 or lacks the grid's
// datasets is the wrong file (bad input, exit 2), like a grid with a bad cell (read_drift_grid); a
// grid whose data fail their checksums is a damaged file (exit 3). (--merge called any wrong file
// damaged, exit 3.)
DriftGrid read_drift_file(const std::string& path, const std::string& option = "--drift") {
  require_file(path, option);
  bool grid = false;
  try {
    const io::H5File f(path, io::H5File::Mode::Read);
    grid = f.exists("/v_ax") && f.exists("/sigma_ax");
  } catch (const std::exception& e) {
    throw InputError(option + " '" + path + "' cannot be read as HDF5: " + e.what());
  }
  if (!grid)
    throw InputError(option + " '" + path +
                     "' is not a drift grid: it has no /v_ax and /sigma_ax (docs/cm.md)");
  return read_drift_grid(path);
}

void warn(const std::string& text) {
  if (!text.empty()) std::fprintf(stderr, "tumble: warning: %s\n", text.c_str());
}

std::string tag(double a, double b) {
  std::ostringstream s;
  s << a << "_" << b;
  return s.str();
}

// Options every subcommand shares: the protocol and the flow model.
struct ProtocolArgs {
  double theta_z = 0, theta_x = 0, eps = 0.15;
  std::string model = "exact";

  void add(CLI::App* cmd, bool with_model) {
    cmd->add_option("--theta-z", theta_z, "rotation about z per iteration, degrees")->required();
    cmd->add_option("--theta-x", theta_x, "rotation about x per iteration, degrees")->required();
    cmd->add_option("--eps", eps, "flowing-layer depth epsilon (Yu 2022 App. A)");
    if (with_model)
      cmd->add_option("--model", model, "flow map: exact | integrated | pwi (eps -> 0)");
  }
  Protocol validate() const {
    require(theta_z > 0 && theta_z <= 360, "--theta-z", "in (0, 360] degrees", theta_z);
    require(theta_x > 0 && theta_x <= 360, "--theta-x", "in (0, 360] degrees", theta_x);
    require(eps > 0 && eps <= 0.5, "--eps", "in (0, 0.5]", eps);
    const std::map<std::string, FlowModel> models{{"exact", FlowModel::Exact},
                                                  {"integrated", FlowModel::Integrated},
                                                  {"pwi", FlowModel::Pwi}};
    require(models.count(model) == 1, "--model", "one of exact, integrated, pwi", model);
    return Protocol::degrees(theta_z, theta_x, eps, models.at(model));
  }
};

void check_radius(double r, const Protocol& pr) {
  require(r > pr.layer_eps() && r < 1, "--r", "in (eps, 1)", r);
}

std::vector<double> default_kam_radii() {
  std::vector<double> r;
  for (int k = 11; k <= 19; ++k) r.push_back(0.05 * k);  // 0.55 ... 0.95 (Fig. 1(b))
  return r;
}

void print_points(const std::vector<PeriodicPoint>& pts, int max_period) {
  for (int n = 1; n <= max_period; ++n) {
    int e = 0, h = 0, p = 0;
    for (const auto& q : pts) {
      if (q.period != n) continue;
      (q.type == Stability::Elliptic ? e : q.type == Stability::Hyperbolic ? h : p)++;
    }
    std::printf("  period %d: %d elliptic, %d hyperbolic, %d parabolic\n", n, e, h, p);
  }
}

void register_poincare(CLI::App& cm) {
  struct Args {
    ProtocolArgs proto;
    RunArgs run;
    PoincareOptions opt;
    std::string seeding = "shell", phase = "first", out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = cm.add_subcommand("poincare", "Poincare section on a shell (Yu 2022 Fig. 1(a))");
  args->proto.add(cmd, true);
  cmd->add_option("--r", args->opt.r, "shell radius");
  cmd->add_option("--seeds", args->opt.seeds, "number of seeds");
  cmd->add_option("--periods", args->opt.periods, "protocol iterations");
  cmd->add_option("--seeding", args->seeding, "shell (equal-area, bulk) | interface");
  cmd->add_option("--seed-phase", args->phase,
                  "seed at the start of the first | second rotation, or both (Fig. 12(a))");
  cmd->add_option("-o,--output", args->out, "HDF5 output (default results/cm/poincare_TZ_TX.h5)");
  args->run.add(cmd);
  cmd->callback([args] {
    const Protocol pr = args->proto.validate();
    auto& o = args->opt;
    check_radius(o.r, pr);
    require(o.seeds >= 1 && o.seeds <= 1000000, "--seeds", "in [1, 1e6]", o.seeds);
    require(o.periods >= 1 && o.periods <= 10000000, "--periods", "in [1, 1e7]", o.periods);
    require(args->seeding == "shell" || args->seeding == "interface", "--seeding",
            "shell or interface", args->seeding);
    require(args->phase == "first" || args->phase == "second" || args->phase == "both",
            "--seed-phase", "first, second or both", args->phase);
    args->run.validate();
    o.seeding = args->seeding == "shell" ? Seeding::Shell : Seeding::Interface;
    o.first_rotation = args->phase != "second";
    o.second_rotation = args->phase != "first";
    args->run.require_memory({{poincare_memory_bytes(pr, o), "--seeds or --periods",
                               "the iterates of the section (seed sets x --seeds x --periods)"}});
    const std::string out =
        args->out.empty()
            ? "results/cm/poincare_" + tag(args->proto.theta_z, args->proto.theta_x) + ".h5"
            : args->out;
    prepare_output_file(out);
    ProgressLine progress("cm poincare", args->run.progress_interval);
    const auto sets = poincare_section(pr, o, progress.stage("iterating the seeds"));
    write_poincare(out, pr, o, sets);
    for (const auto& s : sets)
      std::printf("%s rotation seeds: %zu bulk and %zu layer iterates\n", s.name.c_str(),
                  s.bulk.size(), s.layer.size());
    std::printf("wrote %s\n", out.c_str());
  });
}

struct OrbitArgs {
  PeriodicSearch search;
  IslandOptions islands;
  // The options of the search, and with `with_islands` of the island scan. Returned, so that a
  // command that can read them from a file instead excludes them there (they were silently
  // ignored: `cm mcm --islands F --grid 8`).
  std::vector<CLI::Option*> add(CLI::App* cmd, bool with_islands = true) {
    std::vector<CLI::Option*> added;
    added.push_back(cmd->add_option("--max-period", search.max_period, "largest period searched"));
    added.push_back(
        cmd->add_option("--grid", search.grid, "Newton starting points per chart axis"));
    if (!with_islands) return added;
    added.push_back(cmd->add_option("--island-iterations", islands.iterations,
                                    "iterates of P^n per island test orbit"));
    added.push_back(cmd->add_option("--boundary-iterations", islands.final_iterations,
                                    "iterates of the island boundary orbit"));
    added.push_back(cmd->add_option(
        "--island-rays", islands.rays,
        "rays scanned from each elliptic point; the largest certified curve is the "
        "boundary (docs/cm.md: more rays find larger islands, closer to the regular "
        "set)"));
    added.push_back(
        cmd->add_option("--island-chains", islands.max_chain_q,
                        "largest q of the secondary island chains (resonances p/q outside an "
                        "island's last invariant curve) given islands of their own; 0: none "
                        "(docs/cm.md)")
            ->capture_default_str());
    added.push_back(
        cmd->add_option(
               "--island-order", order,
               "how a boundary orbit is ordered and certified: circle (by k rho mod 1, the "
               "default) or angle (about the centre: star-shaped curves only; docs/cm.md)")
            ->capture_default_str());
    return added;
  }
  std::string order = "circle";
  void validate() {
    require(order == "circle" || order == "angle", "--island-order", "circle or angle", order);
    islands.order = order == "angle" ? IslandOptions::Order::angle : IslandOptions::Order::circle;
    require(search.max_period >= 1 && search.max_period <= 12, "--max-period", "in [1, 12]",
            search.max_period);
    require(search.grid >= 2 && search.grid <= 1000, "--grid", "in [2, 1000]", search.grid);
    require(islands.iterations >= 50 && islands.iterations <= 1000000, "--island-iterations",
            "in [50, 1e6]", islands.iterations);
    require(islands.final_iterations >= 50 && islands.final_iterations <= 1000000,
            "--boundary-iterations", "in [50, 1e6]", islands.final_iterations);
    require(islands.rays >= 1 && islands.rays <= 64, "--island-rays", "in [1, 64]", islands.rays);
    require(islands.max_chain_q >= 0 && islands.max_chain_q <= 30, "--island-chains", "in [0, 30]",
            islands.max_chain_q);
  }
  // What the periodic-point search and the island search hold (upper bounds).
  Need search_need() const {
    return {periodic_search_memory_bytes(search), "--grid or --max-period",
            "the periodic points (at most one per Newton start: --grid^2 x --max-period)"};
  }
  Need island_need() const {
    return {island_memory_bytes(islands), "--island-iterations or --boundary-iterations",
            "an island test orbit"};
  }
  std::string search_stage() const {
    return "periodic points, period <= " + std::to_string(search.max_period) + ", grid " +
           std::to_string(search.grid);
  }
};

void register_orbits(CLI::App& cm) {
  struct Args {
    ProtocolArgs proto;
    RunArgs run;
    OrbitArgs orbits;
    double r = 0.95;
    std::vector<double> kam = default_kam_radii();
    bool no_kam = false;
    std::string out;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = cm.add_subcommand(
      "orbits", "periodic points, their type, island boundaries and KAM tubes (Yu 2022 App. B)");
  args->proto.add(cmd, true);
  cmd->add_option("--r", args->r, "shell radius of the search");
  args->orbits.add(cmd);
  cmd->add_option("--kam-radii", args->kam, "shells for the KAM-tube islands (Fig. 1(b))")
      ->delimiter(',');
  cmd->add_flag("--no-kam", args->no_kam, "islands on the shell --r only");
  cmd->add_option("-o,--output", args->out, "HDF5 output (default results/cm/orbits_TZ_TX.h5)");
  args->run.add(cmd);
  cmd->callback([args] {
    const Protocol pr = args->proto.validate();
    check_radius(args->r, pr);
    args->orbits.validate();
    args->run.validate();
    if (args->no_kam) args->kam.clear();
    for (double r : args->kam)
      require(r > pr.layer_eps() && r < 1, "--kam-radii", "in (eps, 1)", r);
    args->run.require_memory({args->orbits.search_need(), args->orbits.island_need()});
    const std::string out =
        args->out.empty()
            ? "results/cm/orbits_" + tag(args->proto.theta_z, args->proto.theta_x) + ".h5"
            : args->out;
    prepare_output_file(out);
    ProgressLine progress("cm orbits", args->run.progress_interval);
    const SectionMap map(pr, ShellChart(args->r, pr.layer_eps()));
    const auto points =
        find_periodic_points(map, args->orbits.search, progress.stage(args->orbits.search_stage()));
    std::ostringstream shell;
    shell << "islands on r = " << args->r;
    auto islands = find_islands(map, points, args->orbits.islands, progress.stage(shell.str()));
    std::printf("periodic points on r = %g:\n", args->r);
    print_points(points, args->orbits.search.max_period);
    const auto chained = std::count_if(islands.begin(), islands.end(),
                                       [](const Island& i) { return i.parent_orbit >= 0; });
    std::printf(
        "islands on r = %g: %zu (%td in secondary chains), covering %.4f of the bulk "
        "(view from below)\n",
        args->r, islands.size(), chained, island_bulk_area_fraction(map.chart(), islands));
    std::vector<double> kam;
    for (double r : args->kam)
      if (std::abs(r - args->r) > 1e-9) kam.push_back(r);
    if (!kam.empty()) {
      const auto tubes =
          kam_tubes(pr, points, args->r, kam, {args->orbits.search, args->orbits.islands},
                    progress.stage("KAM tubes on " + std::to_string(kam.size()) + " shells"));
      std::printf("KAM-tube islands on %zu other shells: %zu\n", kam.size(), tubes.size());
      islands.insert(islands.end(), tubes.begin(), tubes.end());
    }
    write_orbits(out, pr, args->r, points, islands);
    std::printf("wrote %s\n", out.c_str());
  });
}

void register_manifolds(CLI::App& cm) {
  struct Args {
    ProtocolArgs proto;
    RunArgs run;
    OrbitArgs orbits;
    ManifoldOptions opt;
    double r = 0.95;
    std::string which = "both", orbits_file, out;
    bool max_period_given = false;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = cm.add_subcommand("manifolds",
                                "stable/unstable manifolds of hyperbolic points (Yu 2022 App. B)");
  args->proto.add(cmd, true);
  cmd->add_option("--r", args->r, "shell radius");
  args->orbits.search.max_period = 3;
  // (No island options: manifolds need none. With --orbits, --max-period picks the periods traced.)
  const auto search = args->orbits.add(cmd, false);
  search[0]->description("largest period searched, or with --orbits traced");
  auto* orbits_file =
      cmd->add_option("--orbits", args->orbits_file,
                      "read the periodic points from this orbits file (same protocol and --r)");
  search[1]->excludes(orbits_file);
  cmd->add_option("--kind", args->which, "stable | unstable | both");
  cmd->add_option("--iterations", args->opt.iterations, "protocol iterations");
  cmd->add_option("--length", args->opt.length, "initial segment length (R)");
  cmd->add_option("--spacing", args->opt.spacing, "re-insertion distance (R)");
  cmd->add_option("--max-points", args->opt.max_points,
                  "points recorded per manifold, all iterations together; tracing stops before "
                  "an iteration that would exceed them");
  cmd->add_option("-o,--output", args->out, "HDF5 output (default results/cm/manifolds_TZ_TX.h5)");
  args->run.add(cmd);
  cmd->callback([args, max_period = search[0]] {
    args->max_period_given = max_period->count() > 0;
    const Protocol pr = args->proto.validate();
    check_radius(args->r, pr);
    args->orbits.validate();
    args->run.validate();
    auto& o = args->opt;
    require(args->which == "stable" || args->which == "unstable" || args->which == "both", "--kind",
            "stable, unstable or both", args->which);
    require(o.iterations >= 1 && o.iterations <= 100, "--iterations", "in [1, 100]", o.iterations);
    require(o.length > 0 && o.length <= 0.1, "--length", "in (0, 0.1]", o.length);
    require(o.spacing > 0 && o.spacing < o.length, "--spacing", "in (0, length)", o.spacing);
    require(o.max_points >= 100 && o.max_points <= 100000000, "--max-points", "in [100, 1e8]",
            o.max_points);
    if (!args->orbits_file.empty()) {
      std::string warning;
      const FileProtocol fp = require_orbits_file_of(args->orbits_file, "--orbits", pr, &warning);
      warn(warning);
      // The points' chart coordinates belong to the shell they were found on.
      if (fp.r && std::abs(*fp.r - args->r) > 1e-9) {
        std::ostringstream msg;
        msg << "--orbits '" << args->orbits_file
            << "' holds the periodic points of the shell r = " << *fp.r << ", this run's --r is "
            << args->r << ": give --r " << *fp.r << " or the orbits file of r = " << args->r;
        throw InputError(msg.str());
      }
    }
    // Manifolds are traced and written one at a time (ManifoldsWriter): one is in memory.
    std::vector<Need> needs{{manifold_memory_bytes(o), "--max-points", "one manifold's points"}};
    if (args->orbits_file.empty()) needs.push_back(args->orbits.search_need());
    args->run.require_memory(needs);
    const std::string out =
        args->out.empty()
            ? "results/cm/manifolds_" + tag(args->proto.theta_z, args->proto.theta_x) + ".h5"
            : args->out;
    prepare_output_file(out);
    ProgressLine progress("cm manifolds", args->run.progress_interval);
    const SectionMap map(pr, ShellChart(args->r, pr.layer_eps()));
    const auto points = args->orbits_file.empty()
                            ? find_periodic_points(map, args->orbits.search,
                                                   progress.stage(args->orbits.search_stage()))
                            : read_periodic_points(args->orbits_file);
    // One point per orbit: the manifolds of the others are its images under P. (From a file, the
    // periods up to --max-period where it is given: it was ignored, every period traced.)
    const int max_period =
        args->orbits_file.empty() || args->max_period_given ? args->orbits.search.max_period : 1000;
    std::vector<std::size_t> traced;
    std::vector<int> done_orbit;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const auto& h = points[i];
      if (h.type != Stability::Hyperbolic || h.period > max_period) continue;
      if (std::find(done_orbit.begin(), done_orbit.end(), h.orbit) != done_orbit.end()) continue;
      done_orbit.push_back(h.orbit);
      traced.push_back(i);
    }
    const int kinds = args->which == "both" ? 2 : 1;
    const std::size_t total = traced.size() * kinds;
    if (traced.empty()) {  // (said: the file has an empty /manifolds, not a silent gap)
      std::string where = args->orbits_file.empty() ? "" : " in " + args->orbits_file;
      if (max_period < 1000) where += " up to period " + std::to_string(max_period);
      std::printf("no hyperbolic periodic point%s: no manifolds to trace\n", where.c_str());
    }
    ManifoldsWriter writer(out, pr, args->r, points);
    std::size_t count = 0;
    for (std::size_t i : traced) {
      const auto& h = points[i];
      for (bool unstable : {true, false}) {
        if ((unstable && args->which == "stable") || (!unstable && args->which == "unstable"))
          continue;
        ++count;
        const std::string name = "manifold " + std::to_string(count) + "/" + std::to_string(total) +
                                 " (" + (unstable ? "unstable" : "stable") + ", period-" +
                                 std::to_string(h.period) + " point " + std::to_string(i) + ")";
        auto m = trace_manifold(map, h, unstable, o, progress.stage(name));
        m.point = static_cast<int>(i);
        std::printf("  period-%d point %zu: %s manifold, %zu points over %d iterations%s\n",
                    h.period, i, unstable ? "unstable" : "stable", m.xyz.size(), m.iterations_done,
                    m.truncated ? " (stopped at --max-points)" : "");
        writer.add(m);
      }
    }
    writer.commit();
    std::printf("wrote %s\n", out.c_str());
  });
}

// Pe as a sentence: "none" and "infinite" say why (mcm.hpp, mcm_peclet).
std::string peclet_line(const McmSummary& s) {
  char buf[160];
  if (std::isnan(s.peclet))
    return "Pe = none (neither drift nor diffusion: no drift, and c = 0 or sigma_ax = 0)";
  if (std::isinf(s.peclet)) return "Pe = infinite (drift without diffusion: c = 0 or sigma_ax = 0)";
  if (s.peclet == 0) return "Pe = 0 (diffusion without drift)";
  std::snprintf(buf, sizeof buf, "Pe = L<|v_ax|>/((c sigma)^2 dt_ref) = %s  (L = %.4g R)",
                peclet_text(s.peclet).c_str(), s.island_length);
  return buf;
}

void register_mcm(CLI::App& cm) {
  struct Args {
    ProtocolArgs proto;
    RunArgs run;
    OrbitArgs orbits;
    McmOptions opt;
    std::string drift = "synthetic", islands_file, out;
    bool no_drift = false;
    std::vector<int> cumulative{30, 45};
    double island_length = 10.0 / 70.0;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = cm.add_subcommand(
      "mcm", "modified continuum model: tracers with axial drift and diffusion (Yu 2022 Fig. 9)");
  args->proto.add(cmd, false);
  args->orbits.search.max_period = 3;
  const auto island_search = args->orbits.add(cmd);
  cmd->add_option("--r", args->opt.r, "tracer shell radius");
  cmd->add_option("--tracers", args->opt.tracers, "number of tracers");
  cmd->add_option("--drift", args->drift,
                  "drift grid: an HDF5 file (docs/cm.md) or 'synthetic' (App. A shape)");
  cmd->add_flag("--no-drift", args->no_drift, "v_ax = 0 (diffusion only)");
  cmd->add_option("--c", args->opt.c, "diffusion weight c (alpha of Sec. III B)");
  cmd->add_option("--snapshot", args->opt.snapshot, "iteration N of the snapshot");
  cmd->add_option("--cumulative", args->cumulative, "FROM,TO iterations of cumulative positions")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--stride", args->opt.cumulative_stride, "record every STRIDE iterations");
  cmd->add_option("--dt", args->opt.dt, "layer integration step (1/omega)");
  cmd->add_option("--dt-ref", args->opt.dt_ref, "diffusion time step of the paper (1/omega)");
  cmd->add_option("--seed", args->opt.seed, "random seed");
  auto* islands_file =
      cmd->add_option("--islands", args->islands_file,
                      "orbits file with the CM islands of this protocol and shell (default: "
                      "computed on the shell --r)");
  for (CLI::Option* o : island_search) o->excludes(islands_file);
  cmd->add_option("--island-length", args->island_length, "L_island of the Peclet number (R)");
  cmd->add_option("-o,--output", args->out, "HDF5 output (default results/cm/mcm_TZ_TX_cC.h5)");
  args->run.add(cmd);
  cmd->callback([args] {
    const Protocol pr = args->proto.validate();
    auto& o = args->opt;
    check_radius(o.r, pr);
    args->orbits.validate();
    args->run.validate();
    require(o.tracers >= 1 && o.tracers <= 10000000, "--tracers", "in [1, 1e7]", o.tracers);
    require(o.c >= 0 && o.c <= 1000, "--c", "in [0, 1000]", o.c);
    require(o.snapshot >= 0 && o.snapshot <= 100000, "--snapshot", "in [0, 1e5]", o.snapshot);
    require(args->cumulative.size() == 2 && args->cumulative[0] >= 0 &&
                args->cumulative[0] <= args->cumulative[1] && args->cumulative[1] <= 100000,
            "--cumulative", "FROM,TO with 0 <= FROM <= TO <= 1e5",
            args->cumulative.size() == 2  // (the values, not how many: "(got 2)" for 45,30)
                ? std::to_string(args->cumulative[0]) + "," + std::to_string(args->cumulative[1])
                : std::to_string(args->cumulative.size()) + " values");
    require(o.cumulative_stride >= 1, "--stride", ">= 1", o.cumulative_stride);
    // (Below 1e-7 the layer crossings take more steps than any run: --dt 1e-300 never ended.)
    require(o.dt >= 1e-7 && o.dt <= 0.1, "--dt", "in [1e-7, 0.1]", o.dt);
    require(o.dt_ref >= 1e-7 && o.dt_ref <= 0.1, "--dt-ref", "in [1e-7, 0.1]", o.dt_ref);
    require(args->island_length > 0 && args->island_length <= 2, "--island-length", "in (0, 2]",
            args->island_length);
    o.cumulative_from = args->cumulative[0];
    o.cumulative_to = args->cumulative[1];
    o.drift = !args->no_drift;
    // Input files before any work: the drift grid (checked cell by cell, at most 16 MB) and
    // the islands, which must be of this protocol and have this shell.
    const DriftGrid grid =
        args->drift == "synthetic" ? synthetic_drift({}) : read_drift_file(args->drift);
    std::vector<Island> islands;
    if (!args->islands_file.empty()) {
      std::string warning;
      const FileProtocol fp = require_orbits_file_of(args->islands_file, "--islands", pr, &warning);
      warn(warning);
      const auto shells = island_shells(args->islands_file, fp);
      if (!shells.empty() && std::none_of(shells.begin(), shells.end(),
                                          [&](double r) { return std::abs(r - o.r) < 1e-9; })) {
        std::ostringstream msg;
        msg << "--islands '" << args->islands_file << "' has islands on the shells r =";
        for (double r : shells) msg << " " << r;
        msg << " only, this run's --r is " << o.r
            << ": give one of those with --r, or compute the orbits of r = " << o.r;
        throw InputError(msg.str());
      }
      islands = islands_on_shell(read_islands(args->islands_file), o.r);
    }
    std::vector<Need> needs{{mcm_memory_bytes(o), "--tracers, --cumulative or --stride",
                             "the tracer positions (--tracers x recorded iterations)"}};
    if (args->islands_file.empty()) {
      needs.push_back(args->orbits.search_need());
      needs.push_back(args->orbits.island_need());
    }
    args->run.require_memory(needs);
    std::ostringstream c;
    c << o.c;
    const std::string out =
        args->out.empty() ? "results/cm/mcm_" + tag(args->proto.theta_z, args->proto.theta_x) +
                                "_c" + c.str() + (o.drift ? "" : "_nodrift") + ".h5"
                          : args->out;
    prepare_output_file(out);
    ProgressLine progress("cm mcm", args->run.progress_interval);
    const ShellChart chart(o.r, pr.layer_eps());
    if (args->islands_file.empty()) {
      const SectionMap map(pr, chart);
      const auto points = find_periodic_points(map, args->orbits.search,
                                               progress.stage(args->orbits.search_stage()));
      islands = find_islands(map, points, args->orbits.islands, progress.stage("islands"));
    }
    const int last = std::max(o.snapshot, o.cumulative_to);
    const auto res = run_mcm(pr, grid, o,
                             progress.stage(std::to_string(o.tracers) + " tracers x " +
                                            std::to_string(last) + " iterations"));
    const auto s = summarize_mcm(chart, islands, grid, o, res, args->island_length);
    write_mcm(out, pr, o, grid, res, s);
    std::printf("drift grid: %s%s, <|v_ax|> = %.4g, <sigma_ax> = %.4g (units omega R)\n",
                grid.source.c_str(), o.drift ? "" : " (drift off)", grid.mean_abs_v(),
                grid.mean_sigma());
    std::printf("%s\n", peclet_line(s).c_str());
    std::printf("islands: %zu, %.4f of the bulk area\n", islands.size(), s.bulk_area_fraction);
    std::printf(
        "tracers in islands at N = %d: %.4f of %lld bulk tracers (initially %.4f); "
        "cumulative N = %d..%d: %.4f\n",
        o.snapshot, s.bulk_inside_fraction, static_cast<long long>(s.bulk_tracers),
        s.initial_bulk_inside_fraction, o.cumulative_from, o.cumulative_to,
        s.cumulative_bulk_inside_fraction);
    std::printf("wrote %s\n", out.c_str());
  });
}

void register_drift(CLI::App& cm) {
  struct Args {
    SyntheticDrift sd;
    RunArgs run;
    std::string out = "results/cm/drift_synthetic.h5";
    std::vector<std::string> merge;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = cm.add_subcommand(
      "drift",
      "write the synthetic drift grid (docs/cm.md) to HDF5, or merge measured grids (--merge)");
  cmd->add_option("--merge", args->merge,
                  "measured drift grids (drift_grid.h5 of runs with output.drift_grid = on) to "
                  "merge into one: their per-cell statistics summed")
      ->check(CLI::ExistingFile);
  cmd->add_option("--n", args->sd.n, "grid cells per side");
  cmd->add_option("--drift-per-pass", args->sd.drift_per_pass,
                  "largest axial displacement per layer transit (R)");
  cmd->add_option("--z-reversal", args->sd.z_reversal, "axial position where drift reverses");
  cmd->add_option("--sigma", args->sd.sigma, "sigma_ax (omega R)");
  cmd->add_option("--eps", args->sd.eps, "flowing-layer depth (sets the transit time pi eps)");
  cmd->add_option("-o,--output", args->out, "HDF5 output");
  cmd->add_option("--max-memory", args->run.max_memory,
                  "refuse a grid estimated to need more memory than this (e.g. 2G; default: the "
                  "machine's available memory)");
  cmd->callback([args] {
    if (!args->merge.empty()) {
      // Grids of several runs (replicas, or pieces of one run) as one field: exact, since each
      // file keeps its per-cell sums.
      std::vector<DriftGrid> grids;
      std::string source = "merged:";
      for (const auto& path : args->merge) {
        grids.push_back(read_drift_file(path, "--merge"));
        grids.back().source = path;
        source += " " + path;
      }
      const DriftGrid merged = merge_drift_grids(grids, source);
      prepare_output_file(args->out);
      write_drift_grid(args->out, merged);
      std::printf(
          "%zu grids, %.0f samples; <|v_ax|> = %.4g, <sigma_ax> = %.4g (omega R); wrote %s\n",
          grids.size(), merged.statistics.samples(), merged.mean_abs_v(), merged.mean_sigma(),
          args->out.c_str());
      return;
    }
    const auto& s = args->sd;
    require(s.n >= 2 && s.n <= kMaxDriftGridN, "--n", "in [2, 1000]", s.n);
    require(s.drift_per_pass >= 0 && s.drift_per_pass <= 0.5, "--drift-per-pass", "in [0, 0.5]",
            s.drift_per_pass);
    require(s.z_reversal > 0 && s.z_reversal <= 2, "--z-reversal", "in (0, 2]", s.z_reversal);
    require(s.sigma >= 0 && s.sigma <= 100, "--sigma", "in [0, 100]", s.sigma);
    require(s.eps > 0 && s.eps <= 0.5, "--eps", "in (0, 0.5]", s.eps);
    args->run.require_memory({{drift_grid_memory_bytes(s.n), "--n", "the n x n grid"}});
    prepare_output_file(args->out);
    const auto grid = synthetic_drift(s);
    write_drift_grid(args->out, grid);
    std::printf("<|v_ax|> = %.4g, <sigma_ax> = %.4g (omega R); wrote %s\n", grid.mean_abs_v(),
                grid.mean_sigma(), args->out.c_str());
  });
}

}  // namespace

void register_cm(CLI::App& app) {
  auto* cm = app.add_subcommand("cm", "continuum model: sections, orbits, islands, manifolds, MCM");
  cm->require_subcommand(1);
  cm->option_defaults()->always_capture_default();  // show defaults in --help
  register_poincare(*cm);
  register_orbits(*cm);
  register_manifolds(*cm);
  register_mcm(*cm);
  register_drift(*cm);
}

}  // namespace tumble::app
