#pragma once
// The exit codes of every `tumble` subcommand (README, "Exit codes"): one convention, so that a
// job script can tell bad input from a corrupt file from a run that failed.
namespace tumble::exit_code {

inline constexpr int kOk = 0;
inline constexpr int kRunFailed = 1;     // a run-time failure (NaN, escaped particle, I/O)
inline constexpr int kBadInput = 2;      // refused before any work: a key, an option, a file
inline constexpr int kCorruptInput = 3;  // a file Tumble wrote reads back damaged
inline constexpr int kFailedCases = 4;   // a campaign finished with failed or excluded cases
inline constexpr int kWorkLeft = 10;     // cases still to run (`campaign --status`, `merge`), or a
                                         // `run`/`campaign` stopped by a signal at its checkpoints

}  // namespace tumble::exit_code
