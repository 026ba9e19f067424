#include "campaign/cylinder_collector.hpp"

#include "campaign/cylinder_fields.hpp"
#include "run/run_state.hpp"

namespace tumble::campaign {

void CylinderCollector::finish(RunState& s) {
  series_ = s.series.cylinder;
  complete_ = s.sim.step_count() >= s.total_steps;
}

std::string CylinderCollector::missing() const {
  return complete_ ? "" : "the run stopped before its last step";
}

void CylinderCollector::write_fields(const std::string& path, const FieldsMeta& meta) const {
  write_cylinder_fields(path, meta, spec_, series_);
}

}  // namespace tumble::campaign
