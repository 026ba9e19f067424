#pragma once
// One attempt at one case, on the rank group it was handed to: build and validate its scene, run
// the realization with the case's collector (resuming from the case's checkpoint if there is
// one), write the per-case fields file atomically, and report. Every failure becomes an outcome
// (never an exception): the campaign goes on with the other cases.
//
// On a group of several ranks every rank calls run_case with the same task; the group's rank 0
// (its leader) owns the case directory, the log and the fields file, decides whether to resume,
// and its outcome is the one reported. Every decision that ends an attempt is taken by all ranks
// of the group together, so a failure seen by one rank never leaves the others waiting.
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <string>

#include "campaign/campaign_spec.hpp"
#include "campaign/expand.hpp"

namespace tumble::campaign {

struct CaseTask {
  std::size_t case_index = 0;
  int attempt = 1;
  std::int64_t seed = 0;
  bool fresh = false;  // wipe the case directory first (a retry with a new seed)
};

struct CaseOutcome {
  bool ok = false;
  std::string failure;     // input | run | time_limit | exception
  std::string diagnostic;  // the message
  bool retryable = false;  // an invalid scene fails the same way every time
  std::string checksum;    // of fields.h5
  std::string start, end;  // UTC
  double wall = 0;         // seconds
  // Of them, the protocol loop's (run_realization's RunResult::wall_seconds; 0: not reached): the
  // rate the ETA takes, as it takes the running cases' (their progress reports count the loop
  // only), not the bed's settling and β's hours of turn.
  double protocol_wall = 0;
  long long resumed_from_step = 0;
};

// A case handed to its group after a stop request reached it ends "stopped" with a diagnostic
// that begins so: it did not begin (nothing ran, nothing was kept).
inline constexpr const char* kNotBegun = "not begun";
inline bool ended_not_begun(const CaseOutcome& o) {
  return o.failure == "stopped" && o.diagnostic.rfind(kNotBegun, 0) == 0;
}

// How far a running case has come: its group's leader reports it to the dispatcher every
// progress interval (campaign.progress_interval) while the protocol runs, so that the campaign's
// ETA rests on the running cases' own rates before any case has finished (a case may take days).
// Also once when the case begins (`preparing`: it may first settle its bed and measure β, hours
// on a paper-scale bed, which the protocol's steps do not count) and once when its protocol
// begins (step = first_step, seconds 0).
struct CaseProgress {
  std::size_t case_index = 0;
  int attempt = 1;
  bool preparing = false;        // before the protocol: the steps below are 0
  std::int64_t first_step = 0;   // where this call of the run began (a resumed case: later than 0)
  std::int64_t step = 0;         // at the report
  std::int64_t total_steps = 0;  // the whole protocol
  double seconds = 0;            // wall seconds of this call's protocol loop so far
};

struct CaseContext {
  const CampaignSpec* spec = nullptr;
  const Expansion* expansion = nullptr;
  std::string campaign_dir, bed_cache;
  // The case's ranks: MPI_COMM_NULL (or one rank) runs it serially, several ranks decompose it
  // exactly as `mpirun -n k tumble run` does.
  MPI_Comm group = MPI_COMM_NULL;
  // Called between time steps (and settling blocks) on the dispatching rank, so that it keeps
  // handing out cases while its own group computes; empty elsewhere.
  std::function<void()> poll;
  // Called on the group's leader with the case's progress (CaseProgress); empty: not reported.
  std::function<void(const CaseProgress&)> progress;
};

// DIR/cases/<case id>: the case's scene output, checkpoint, collector state, fields and log.
std::string case_dir(const std::string& campaign_dir, const std::string& case_id);
std::string case_output(const std::string& case_id);  // the same, relative to DIR
std::string fields_path(const std::string& campaign_dir, const std::string& case_id);

CaseOutcome run_case(const CaseContext& ctx, const CaseTask& task);

// The outcome as one JSON line (sent to the dispatcher) and back.
std::string encode(const CaseTask& t, const CaseOutcome& o);
bool decode(const std::string& line, CaseTask& t, CaseOutcome& o);
std::string encode(const CaseProgress& p);
bool decode(const std::string& line, CaseProgress& p);

}  // namespace tumble::campaign
