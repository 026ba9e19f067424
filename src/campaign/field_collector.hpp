#pragma once
// The in-situ collector of one sphere case (campaign/case_collector.hpp): takes the samples of its
// CollectPlan (the c_L map, the Δψ map and the segregation/mixing series) and writes the case's
// fields file. On a rank group the samples are taken of the gathered bed (RunState::whole_bed,
// one gather per sample, not per step) by the group's rank 0, which alone keeps the sums and
// writes state.h5; the other ranks only follow which samples are still to come.
//
// Kill-safety: after every sample the collector's whole state (running sums, series, the ring of
// start directions that Δψ still needs) is written atomically to state.h5. A resumed case restarts
// the engine from its last checkpoint, which is never later than the collector's last sample, and
// the engine repeats the steps since then bitwise; the collector simply waits for its next sample.
// So a killed and resumed case produces exactly the fields of an uninterrupted one.
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "analysis/concentration.hpp"
#include "analysis/displacement.hpp"
#include "campaign/case_collector.hpp"
#include "campaign/collect_plan.hpp"
#include "h5/hdf5_file.hpp"
#include "projection/lambert.hpp"

namespace tumble::campaign {

// Names of the per-case fields (datasets of the fields file and of the ensemble), by collect spec.
std::vector<std::string> field_names(const CollectSpec& spec);

// The attributes every case fields file carries (sphere and cylinder cases alike): identity,
// parameters, collection, code version and the resolved scene.
void write_case_attributes(io::H5File& f, const FieldsMeta& meta, const CollectSpec& spec);

class FieldCollector : public CaseCollector {
 public:
  FieldCollector(const CollectPlan& plan, std::string state_path);

  // Restores the state written before a kill. Returns false (and starts empty) if there is none
  // or it belongs to another plan.
  bool load();
  // CaseCollector: resumable from a checkpoint not later than the last sample saved.
  bool resumable_from(std::int64_t checkpoint_step) override;
  void discard_saved() override;
  void share(MPI_Comm group) override;
  std::string missing() const override;
  // Index of the next sample to take, and its step: a resumed engine must be behind it.
  std::int64_t next_sample() const { return next_j_; }
  std::int64_t next_sample_step() const { return plan_.sample_step(next_j_); }
  bool finished() const { return next_j_ > plan_.last_sample; }

  // The observer: acts only at the steps of its samples.
  void start(RunState& s) override;
  void after_step(RunState& s) override;
  // One sample of a configuration (tests call this directly). `to_frame` maps lab positions to
  // the analysis frame.
  void sample(const Particles& p, std::int64_t j, double time, double iteration,
              const Mat3& to_frame);

  void write_fields(const std::string& path, const FieldsMeta& meta) const override;

  const analysis::ConcentrationMap& concentration() const { return conc_; }
  // The Δψ map of lag k (in the order of collect.displacement_periods).
  const analysis::DisplacementMap& displacement(std::size_t k = 0) const { return disp_.at(k); }
  struct Series {
    std::vector<double> time, iteration, shell_large_fraction, radial_segregation, mixing_index;
  };
  const Series& series() const { return series_; }

 private:
  void observe(RunState& s);
  void persist() const;
  void ensure_slots(const Particles& p);

  CollectPlan plan_;
  analysis::LambertGrid grid_;
  std::string state_path_;
  // Refuses (CorruptInputError) a loaded state whose sizes or indices do not fit the plan.
  void check_loaded(std::size_t cells) const;
  std::int64_t next_j_ = 0;
  Series series_;
  analysis::ConcentrationMap conc_;
  std::vector<analysis::DisplacementMap> disp_;   // one per lag
  std::string group_of_lag(std::size_t k) const;  // its group in the state and fields files
  // Ring of start directions for Δψ, shared by the lags: slot j % max_lag holds sample
  // ring_j_[..] (-1: empty).
  std::vector<std::int64_t> ring_j_;
  std::vector<analysis::ShellDirections> ring_;
  // Particle slots: position in global-id order (the engine reorders particles in memory).
  std::unordered_map<std::int64_t, std::uint32_t> slot_of_id_;
  std::vector<std::uint32_t> slot_of_;  // by current memory index (rebuilt per sample)
  std::vector<std::int32_t> species_;   // by slot
};

}  // namespace tumble::campaign
