#include "cm/poincare.hpp"

#include <cmath>

namespace tumble::cm {
namespace {

PoincareSet run_set(const Protocol& pr, const ShellChart& chart, const PoincareOptions& opt,
                    bool second, const Progress& progress) {
  PoincareSet s;
  s.name = second ? "second" : "first";
  s.seeds = opt.seeding == Seeding::Shell ? chart.equal_area_seeds(opt.seeds)
                                          : chart.interface_seeds(opt.seeds);
  const std::size_t n = s.seeds.size() * static_cast<std::size_t>(opt.periods);
  s.bulk.reserve(n);
  s.bulk_seed.reserve(n);
  s.bulk_period.reserve(n);
  for (std::size_t k = 0; k < s.seeds.size(); ++k) {
    Vec3 p = second ? phase_map(pr, Axis::X, s.seeds[k]) : s.seeds[k];
    for (int it = 1; it <= opt.periods; ++it) {
      p = period_map(pr, p);
      if (in_layer(p, chart.eps())) {
        s.layer.push_back(p);
        s.layer_chart.push_back(chart.to_chart(p));
        s.layer_seed.push_back(k);
        s.layer_period.push_back(it);
      } else {
        s.bulk.push_back(chart.to_chart(p));
        s.bulk_seed.push_back(k);
        s.bulk_period.push_back(it);
      }
    }
    report(progress, static_cast<double>(k + 1) / s.seeds.size());
  }
  return s;
}

}  // namespace

std::vector<PoincareSet> poincare_section(const Protocol& pr, const PoincareOptions& opt,
                                          const Progress& progress) {
  const ShellChart chart(opt.r, pr.layer_eps());
  const double sets = (opt.first_rotation ? 1.0 : 0.0) + (opt.second_rotation ? 1.0 : 0.0);
  std::vector<PoincareSet> out;
  if (opt.first_rotation)
    out.push_back(run_set(pr, chart, opt, false, sub_progress(progress, 0, 1 / sets)));
  if (opt.second_rotation)
    out.push_back(run_set(pr, chart, opt, true, sub_progress(progress, 1 - 1 / sets, 1 / sets)));
  return out;
}

double poincare_memory_bytes(const Protocol& pr, const PoincareOptions& opt) {
  const ShellChart chart(opt.r, pr.layer_eps());
  const double layer_share = 1 - std::pow(chart.rim() / chart.outer(), 2);
  const double sets = (opt.first_rotation ? 1.0 : 0.0) + (opt.second_rotation ? 1.0 : 0.0);
  const double iterates = static_cast<double>(opt.seeds) * opt.periods;
  return sets * (iterates * (32 + 16 + (2 * 56 + 40) * layer_share) + 24.0 * opt.seeds);
}

}  // namespace tumble::cm
