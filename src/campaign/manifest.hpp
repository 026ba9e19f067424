#pragma once
// The campaign manifest: one JSON line per event of a case (assigned, done, failed), appended and
// never rewritten. The latest line of a case is its state. Each invocation appends to its own file
// DIR/manifest/slice_I_of_N.jsonl (job-array tasks never write the same file); readers take the
// union. A line is written with one write(2) on an O_APPEND descriptor, so a killed process leaves
// either the whole line or nothing; after a machine crash a torn last line is ignored on reading.
#include <map>
#include <string>
#include <vector>

namespace tumble::campaign {

struct CaseRecord {
  std::string case_id, point_id;
  std::string status;  // running | done | failed
  std::string params;  // canonical "theta_z=57;theta_x=57;..." (display precision)
  std::string tier;
  int replica = 0, attempt = 0;
  long long seed = 0;
  int group = -1, rank = -1;  // rank group (its leader / its size) and its leader's world rank
  std::string ranks;          // the group's world ranks: "4-7" (consecutive) or "1,3"
  std::string host;           // the leader's host
  std::string hosts;          // every host of the group, in rank order, each once
  std::string output;         // case directory, relative to the campaign directory
  std::string start, end;     // UTC, ISO 8601
  double wall = 0;            // seconds of this attempt
  long long resumed_from_step = 0;  // > 0: continued from a checkpoint at this step
  std::string checksum;             // of the per-case fields file (done)
  std::string failure;              // input | run | time_limit | exception (failed)
  std::string diagnostic;           // the error message (failed)
  bool final_failure = false;       // failed and not to be retried under the policy
  std::string slice;                // "i/n" of the invocation that wrote the line
  double t = 0;                     // unix time of the line (orders lines across files)
};

std::string to_json(const CaseRecord& r);
bool from_json(const std::string& line, CaseRecord& r);

class ManifestWriter {
 public:
  // Opens (creating) `path` for appending and takes an exclusive lock on it, so the same slice
  // cannot run twice at once. Throws InputError naming the file if the lock is held.
  explicit ManifestWriter(const std::string& path);
  ~ManifestWriter();
  ManifestWriter(const ManifestWriter&) = delete;
  ManifestWriter& operator=(const ManifestWriter&) = delete;
  // Throws RunError naming the file and the system's reason (a full disk) if the line cannot be
  // written; the file is then as before the call.
  void append(const CaseRecord& r);
  void sync();  // fsync: durability against machine crashes (process crashes need none)
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  // A test hook (off unless the environment sets it): TUMBLE_TEST_MANIFEST_FULL="<first>:<count>"
  // makes this writer's appends number first .. first+count-1 (from 1, retries counted) fail as
  // on a full disk, so that CI can check the campaign's halt
  // (tests/campaign/manifest_full_check.py).
  long long appends_ = 0, full_from_ = 0, full_count_ = 0;
};

struct ManifestState {
  std::map<std::string, CaseRecord> latest;                // by case id
  std::map<std::string, int> attempts;                     // highest attempt seen, by case id
  std::map<std::string, std::vector<CaseRecord>> history;  // every line, by case id
  int torn_lines = 0;
};
// Reads every DIR/manifest/*.jsonl (missing directory: empty state).
ManifestState read_manifests(const std::string& campaign_dir);

std::string utc_now();
double unix_now();

}  // namespace tumble::campaign
