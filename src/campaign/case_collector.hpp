#pragma once
// What a campaign case measures in situ and leaves as its fields file: an observer of the run
// (run/observer.hpp) that also says whether the case may resume from a checkpoint and whether the
// run gave it everything it needs. A sphere case collects the c_L and Δψ maps and its series
// (campaign/field_collector.hpp); a cylinder case keeps the run's S_a, S_r and band series
// (campaign/cylinder_collector.hpp). case_runner.cpp drives both through this one interface, on
// one rank or on a rank group.
#include <mpi.h>

#include <cstdint>
#include <memory>
#include <string>

#include "campaign/collect_plan.hpp"
#include "run/observer.hpp"
#include "scene/scene.hpp"

namespace tumble::campaign {

struct FieldsMeta {
  std::string case_id, point_id, params, tier, scene_text;
  int replica = 0;
  long long seed = 0;
};

class CaseCollector : public Observer {
 public:
  // Rank 0 of the case's group: restores what was saved before an interruption and says whether
  // a run continued from a checkpoint at `checkpoint_step` ends with exactly the fields of an
  // uninterrupted one.
  virtual bool resumable_from(std::int64_t checkpoint_step) = 0;
  // Rank 0: forgets any saved state (the case starts afresh).
  virtual void discard_saved() = 0;
  // Collective over the case's group: every rank learns rank 0's progress (which samples are
  // still to come), so that all take part in the same collective steps.
  virtual void share(MPI_Comm group) = 0;
  // After the run: "" if the collector has all it needs, else what is missing.
  virtual std::string missing() const = 0;
  // Rank 0: the case's fields file, written atomically.
  virtual void write_fields(const std::string& path, const FieldsMeta& meta) const = 0;
};

// The collector for the case's scene (sphere or cylinder); its saved state, if any, lives in
// `case_dir`.
std::unique_ptr<CaseCollector> make_case_collector(const CollectPlan& plan, const Scene& scene,
                                                   const std::string& case_dir);

}  // namespace tumble::campaign
