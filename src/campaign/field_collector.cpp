#include "campaign/field_collector.hpp"

#include <algorithm>
#include <filesystem>

#include "analysis/radial_segregation.hpp"
#include "base/error.hpp"
#include "base/version.hpp"
#include "engine/simulation.hpp"
#include "h5/hdf5_file.hpp"
#include "run/run_state.hpp"

namespace tumble::campaign {
namespace fs = std::filesystem;

std::vector<std::string> field_names(const CollectSpec& s) {
  if (s.cylinder) return {"series/Sa", "series/Sr", "series/bands"};
  std::vector<std::string> n;
  if (s.concentration)
    n.insert(n.end(), {"concentration/c_L", "concentration/c_S", "concentration/solid_fraction"});
  if (s.displacement)
    for (std::size_t i = 0; i < s.displacement_periods.size(); ++i) {
      const std::string g = s.displacement_group(i);
      n.insert(n.end(), {g + "/dpsi_large", g + "/dpsi_small"});
    }
  if (s.series)
    n.insert(n.end(),
             {"series/shell_large_fraction", "series/radial_segregation", "series/mixing_index"});
  return n;
}

namespace {
Mat3 transpose(const Mat3& m) {
  Mat3 t;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) t.a[a][b] = m.a[b][a];
  return t;
}
std::vector<double> flat(const std::vector<Vec3>& v) {
  std::vector<double> out(3 * v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    for (int d = 0; d < 3; ++d) out[3 * i + d] = v[i][d];
  return out;
}
}  // namespace

FieldCollector::FieldCollector(const CollectPlan& plan, std::string state_path)
    : plan_(plan),
      grid_(plan.spec.grid),
      state_path_(std::move(state_path)),
      conc_(grid_.cells()),
      disp_(std::max<std::size_t>(plan.lags.size(), 1), analysis::DisplacementMap(grid_.cells())),
      ring_j_(std::max<std::int64_t>(plan.max_lag(), 1), -1),
      ring_(ring_j_.size()) {}

void FieldCollector::ensure_slots(const Particles& p) {
  if (slot_of_id_.size() != p.size()) {
    std::vector<std::int64_t> ids(p.id.begin(), p.id.end());
    std::sort(ids.begin(), ids.end());
    slot_of_id_.clear();
    for (std::size_t s = 0; s < ids.size(); ++s)
      slot_of_id_[ids[s]] = static_cast<std::uint32_t>(s);
  }
  slot_of_.resize(p.size());
  species_.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::uint32_t s = slot_of_id_.at(p.id[i]);
    slot_of_[i] = s;
    species_[s] = p.species[i];
  }
}

void FieldCollector::start(RunState& s) { observe(s); }
void FieldCollector::after_step(RunState& s) { observe(s); }

void FieldCollector::observe(RunState& s) {
  const Simulation& sim = s.sim;
  const std::int64_t step = sim.step_count();
  while (!finished() && plan_.sample_step(next_j_) <= step) {
    if (plan_.sample_step(next_j_) < step)  // the observer runs every step: cannot happen
      throw RunError("collector missed sample " + std::to_string(next_j_) + " (step " +
                     std::to_string(plan_.sample_step(next_j_)) + ", engine at " +
                     std::to_string(step) + ")");
    const Particles& bed = s.whole_bed();  // collective on a rank group
    if (!s.lead()) {
      next_j_ += 1;
      continue;
    }
    const double t = sim.time();
    const Mat3 q = sim.protocol().orientation(t);  // tumbler -> lab
    sample(bed, next_j_, t, sim.protocol().iteration(t),
           plan_.spec.frame == "tumbler" ? transpose(q) : Mat3::identity());
  }
}

bool FieldCollector::resumable_from(std::int64_t checkpoint_step) {
  return load() && (finished() || checkpoint_step < next_sample_step());
}

void FieldCollector::discard_saved() {
  fs::remove(state_path_);
  *this = FieldCollector(plan_, state_path_);
}

void FieldCollector::share(MPI_Comm group) {
  if (group == MPI_COMM_NULL) return;
  long long j = next_j_;
  MPI_Bcast(&j, 1, MPI_LONG_LONG, 0, group);
  next_j_ = j;
}

std::string FieldCollector::missing() const {
  return finished()
             ? ""
             : "the run ended before the collector's last sample (" + std::to_string(next_j_) + ")";
}

void FieldCollector::sample(const Particles& p, std::int64_t j, double time, double iteration,
                            const Mat3& to_frame) {
  const CollectSpec& s = plan_.spec;
  ensure_slots(p);
  const analysis::ShellBins bins = bin_shell(p, to_frame, grid_, plan_.radius, plan_.shell_inner);
  if (s.series) {
    const auto seg = analysis::radial_segregation(p, plan_.radius, plan_.shell_inner);
    series_.time.push_back(time);
    series_.iteration.push_back(iteration);
    series_.shell_large_fraction.push_back(seg.shell_large_fraction);
    series_.radial_segregation.push_back(seg.shell_large_fraction - seg.bed_large_fraction);
    series_.mixing_index.push_back(analysis::intensity_of_segregation(bins));
  }
  if (plan_.in_window(j)) {
    if (s.concentration) conc_.add(bins);
    if (s.displacement) {
      analysis::ShellDirections dirs = analysis::shell_directions(
          p, slot_of_, to_frame, grid_, plan_.radius, s.displacement_inner);
      // One ring of start directions serves every lag: slot j % max_lag holds sample j until
      // the longest lag has used it (this sample overwrites j - max_lag, used just below).
      const std::int64_t ring = plan_.max_lag();
      for (std::size_t k = 0; k < plan_.lags.size(); ++k) {
        const std::int64_t start = j - plan_.lags[k];
        const std::size_t from = static_cast<std::size_t>(start % ring);
        if (start < plan_.window_first || ring_j_[from] != start) continue;
        // A loaded ring of another particle count (a damaged state file) must not be indexed.
        if (ring_[from].cell.size() != dirs.u.size())
          throw CorruptInputError("collector state '" + state_path_ + "': its ring holds " +
                                  std::to_string(ring_[from].cell.size()) + " particles, the bed " +
                                  std::to_string(dirs.u.size()));
        disp_[k].add_interval(ring_[from], dirs.u, species_);
      }
      const std::size_t slot = static_cast<std::size_t>(j % ring);
      if (j + plan_.min_lag() <= plan_.window_last) {
        ring_[slot] = std::move(dirs);
        ring_j_[slot] = j;
      } else {
        ring_[slot] = {};  // no interval starts here: free the memory and the state file
        ring_j_[slot] = -1;
      }
    }
  }
  next_j_ = j + 1;
  persist();
}

std::string FieldCollector::group_of_lag(std::size_t k) const {
  return plan_.spec.displacement_periods.empty() ? "displacement"
                                                 : plan_.spec.displacement_group(k);
}

void FieldCollector::persist() const {
  io::AtomicH5Writer out(state_path_);
  io::H5File& f = out.file();
  f.set_attr("/", "kind", std::string("tumble collector state"));
  f.set_attr("/", "plan", plan_.spec.canonical());
  f.set_attr("/", "next_sample", static_cast<std::int64_t>(next_j_));
  f.write("series/time", series_.time);
  f.write("series/iteration", series_.iteration);
  f.write("series/shell_large_fraction", series_.shell_large_fraction);
  f.write("series/radial_segregation", series_.radial_segregation);
  f.write("series/mixing_index", series_.mixing_index);
  f.write("concentration/volume_large", conc_.volume_large);
  f.write("concentration/volume_small", conc_.volume_small);
  f.set_attr("/", "concentration_samples", static_cast<std::int64_t>(conc_.samples));
  for (std::size_t k = 0; k < disp_.size(); ++k) {
    const std::string g = group_of_lag(k);
    f.write(g + "/sum_large", disp_[k].sum_large);
    f.write(g + "/sum_small", disp_[k].sum_small);
    f.write(g + "/count_large", disp_[k].count_large);
    f.write(g + "/count_small", disp_[k].count_small);
    f.set_attr("/", g + "_intervals", static_cast<std::int64_t>(disp_[k].intervals));
  }
  f.write("ring/j", std::vector<std::int64_t>(ring_j_.begin(), ring_j_.end()));
  for (std::size_t k = 0; k < ring_.size(); ++k) {
    if (ring_j_[k] < 0) continue;
    const hsize_t n = ring_[k].u.size();
    f.write("ring/u" + std::to_string(k), flat(ring_[k].u), {n, 3});
    f.write("ring/cell" + std::to_string(k), ring_[k].cell);
  }
  out.commit();
}

bool FieldCollector::load() {
  if (!fs::exists(state_path_)) return false;
  io::H5File f(state_path_, io::H5File::Mode::Read);
  if (!f.has_attr("/", "plan") || f.attr_string("/", "plan") != plan_.spec.canonical())
    return false;
  // Sizes the collector was built with: a state file must agree, or its arrays would be indexed
  // past their ends (checked below; the checksums catch damaged bytes, this what they cannot).
  const std::size_t cells = conc_.volume_large.size();
  next_j_ = f.attr_int64("/", "next_sample");
  series_.time = f.read_double("series/time");
  series_.iteration = f.read_double("series/iteration");
  series_.shell_large_fraction = f.read_double("series/shell_large_fraction");
  series_.radial_segregation = f.read_double("series/radial_segregation");
  series_.mixing_index = f.read_double("series/mixing_index");
  conc_.volume_large = f.read_double("concentration/volume_large");
  conc_.volume_small = f.read_double("concentration/volume_small");
  conc_.samples = f.attr_int64("/", "concentration_samples");
  for (std::size_t k = 0; k < disp_.size(); ++k) {
    const std::string g = group_of_lag(k);
    disp_[k].sum_large = f.read_double(g + "/sum_large");
    disp_[k].sum_small = f.read_double(g + "/sum_small");
    disp_[k].count_large = f.read_double(g + "/count_large");
    disp_[k].count_small = f.read_double(g + "/count_small");
    disp_[k].intervals = f.attr_int64("/", g + "_intervals");
  }
  const auto rj = f.read_int64("ring/j");
  if (rj.size() != ring_j_.size()) return false;
  for (std::size_t k = 0; k < rj.size(); ++k) {
    ring_j_[k] = rj[k];
    ring_[k] = {};
    if (rj[k] < 0) continue;
    const auto u = f.read_double("ring/u" + std::to_string(k));
    ring_[k].u.resize(u.size() / 3);
    for (std::size_t i = 0; i < ring_[k].u.size(); ++i)
      ring_[k].u[i] = {u[3 * i], u[3 * i + 1], u[3 * i + 2]};
    ring_[k].cell = f.read_int32("ring/cell" + std::to_string(k));
  }
  check_loaded(cells);
  return true;
}

void FieldCollector::check_loaded(std::size_t cells) const {
  auto corrupt = [&](const std::string& what) {
    throw CorruptInputError("collector state '" + state_path_ + "': " + what +
                            "; the file is damaged (delete it to collect this case again)");
  };
  if (next_j_ < 0 || next_j_ > plan_.last_sample + 1)
    corrupt("next_sample = " + std::to_string(next_j_) + " (the plan has " +
            std::to_string(plan_.last_sample + 1) + " samples)");
  const std::size_t len = series_.time.size();
  for (const auto* v : {&series_.iteration, &series_.shell_large_fraction,
                        &series_.radial_segregation, &series_.mixing_index})
    if (v->size() != len) corrupt("the series datasets have different lengths");
  if (len > static_cast<std::size_t>(next_j_)) corrupt("more series samples than samples taken");
  std::vector<const std::vector<double>*> maps = {&conc_.volume_large, &conc_.volume_small};
  for (const auto& d : disp_) {
    maps.insert(maps.end(), {&d.sum_large, &d.sum_small, &d.count_large, &d.count_small});
    if (d.intervals < 0) corrupt("a negative interval count");
  }
  for (const auto* v : maps)
    if (v->size() != cells)
      corrupt("a map has " + std::to_string(v->size()) + " cells, the grid " +
              std::to_string(cells));
  if (conc_.samples < 0) corrupt("a negative sample count");
  std::size_t slots = 0;
  for (std::size_t k = 0; k < ring_.size(); ++k) {
    if (ring_j_[k] < 0) continue;
    if (ring_j_[k] >= next_j_) corrupt("ring/j holds a sample not taken yet");
    if (ring_[k].cell.size() != ring_[k].u.size() || (slots && ring_[k].u.size() != slots))
      corrupt("ring/u" + std::to_string(k) + " and ring/cell" + std::to_string(k) +
              " do not have one row per particle");
    slots = ring_[k].u.size();
    for (const std::int32_t c : ring_[k].cell)
      if (c < -1 || c >= static_cast<std::int64_t>(cells))
        corrupt("ring/cell" + std::to_string(k) + " holds cell " + std::to_string(c));
  }
}

void write_case_attributes(io::H5File& f, const FieldsMeta& m, const CollectSpec& spec) {
  f.set_attr("/", "kind", std::string("tumble case fields"));
  f.set_attr("/", "case_id", m.case_id);
  f.set_attr("/", "point_id", m.point_id);
  f.set_attr("/", "params", m.params);
  f.set_attr("/", "tier", m.tier);
  f.set_attr("/", "replica", static_cast<std::int64_t>(m.replica));
  f.set_attr("/", "seed", static_cast<std::int64_t>(m.seed));
  f.set_attr("/", "collect", spec.canonical());
  f.set_attr("/", "tumble_version", std::string(kVersion));
  f.set_attr("/", "git_hash", std::string(kGitHash));
  f.set_attr("/", "scene", m.scene_text);
}

void FieldCollector::write_fields(const std::string& path, const FieldsMeta& m) const {
  const CollectSpec& s = plan_.spec;
  const hsize_t n = static_cast<hsize_t>(s.grid);
  io::AtomicH5Writer out(path);
  io::H5File& f = out.file();
  write_case_attributes(f, m, s);
  f.set_attr("/", "grid_n", static_cast<std::int64_t>(s.grid));
  f.set_attr("/", "frame", s.frame);
  // The species' roles: c_L and the *_large datasets are species 1's, c_S and *_small species
  // 0's, whatever tells them apart; these say what each is and which one the maps show.
  const Mixture& mix = plan_.mixture;
  f.set_attr("/", "mixture", std::string(mix.kind_name()));
  f.set_attr("/", "species_0", mix.name[0]);
  f.set_attr("/", "species_1", mix.name[1]);
  f.set_attr("/", "mapped_species", static_cast<std::int64_t>(mix.mapped));
  f.set_attr("/", "minority_species", static_cast<std::int64_t>(mix.minority));
  f.set_attr("/", "window_first_iteration",
             static_cast<double>(plan_.window_first) / s.samples_per_iteration);
  f.set_attr("/", "window_last_iteration",
             static_cast<double>(plan_.window_last) / s.samples_per_iteration);
  if (s.concentration) {
    const double cell_volume = analysis::shell_cell_volume(grid_, plan_.radius, plan_.shell_inner);
    f.write("concentration/c_L", conc_.c_large(), {n, n});
    f.write("concentration/c_S", conc_.c_small(), {n, n});
    f.write("concentration/solid_fraction", conc_.solid_fraction(cell_volume), {n, n});
    f.write("concentration/volume_large", conc_.volume_large, {n, n});
    f.write("concentration/volume_small", conc_.volume_small, {n, n});
    f.set_attr("concentration", "samples", static_cast<std::int64_t>(conc_.samples));
    f.set_attr("concentration", "shell_inner", plan_.shell_inner);
  }
  if (s.displacement)
    for (std::size_t k = 0; k < s.displacement_periods.size(); ++k) {
      const std::string g = s.displacement_group(k);
      f.write(g + "/dpsi_large", disp_[k].mean_large(), {n, n});
      f.write(g + "/dpsi_small", disp_[k].mean_small(), {n, n});
      f.write(g + "/count_large", disp_[k].count_large, {n, n});
      f.write(g + "/count_small", disp_[k].count_small, {n, n});
      f.set_attr(g, "intervals", static_cast<std::int64_t>(disp_[k].intervals));
      f.set_attr(g, "periods", s.displacement_periods[k]);
      f.set_attr(g, "inner", s.displacement_inner);
    }
  if (s.series) {
    f.write("series/time", series_.time);
    f.write("series/iteration", series_.iteration);
    f.write("series/shell_large_fraction", series_.shell_large_fraction);
    f.write("series/radial_segregation", series_.radial_segregation);
    f.write("series/mixing_index", series_.mixing_index);
  }
  out.commit();
}

}  // namespace tumble::campaign
