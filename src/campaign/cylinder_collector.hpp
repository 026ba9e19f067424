#pragma once
// The collector of a cylinder case (Rapaport 2007): the run itself samples S_a, S_r and the band
// count (run/series_observer.hpp) and keeps them in its checkpoints, so a resumed case ends with
// the whole series and any checkpoint may be resumed from; at the end of the run this observer
// takes the series and writes the case's fields file from it (campaign/cylinder_fields.hpp).
#include "analysis/cylinder_segregation.hpp"
#include "campaign/case_collector.hpp"

namespace tumble::campaign {

class CylinderCollector : public CaseCollector {
 public:
  explicit CylinderCollector(const CollectSpec& spec) : spec_(spec) {}
  void after_step(RunState&) override {}
  void finish(RunState& s) override;
  bool resumable_from(std::int64_t) override { return true; }
  void discard_saved() override {}
  void share(MPI_Comm) override {}
  std::string missing() const override;
  void write_fields(const std::string& path, const FieldsMeta& meta) const override;

 private:
  CollectSpec spec_;
  analysis::CylinderSeries series_;
  bool complete_ = false;
};

}  // namespace tumble::campaign
