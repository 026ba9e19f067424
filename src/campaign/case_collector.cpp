#include "campaign/case_collector.hpp"

#include "campaign/cylinder_collector.hpp"
#include "campaign/field_collector.hpp"

namespace tumble::campaign {

std::unique_ptr<CaseCollector> make_case_collector(const CollectPlan& plan, const Scene& scene,
                                                   const std::string& case_dir) {
  if (scene.cylinder()) return std::make_unique<CylinderCollector>(plan.spec);
  return std::make_unique<FieldCollector>(plan, case_dir + "/state.h5");
}

}  // namespace tumble::campaign
