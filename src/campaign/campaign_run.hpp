#pragma once
// `tumble campaign FILE`: expand the campaign, skip what the manifest says is finished, run the
// rest over the rank groups, and fold this slice's results into ensemble statistics.
#include <mpi.h>

#include <iosfwd>
#include <set>
#include <string>
#include <vector>

namespace tumble::campaign {

struct CampaignOptions {
  std::string file;
  std::string output;            // overrides campaign.output_dir
  int slice_i = 1, slice_n = 1;  // --slice i/n
  bool list = false;             // print the expanded cases and exit
  bool status = false;           // print the slice's state; exit 0 if nothing is left to run
  bool retry_failed = false;     // run failed cases again (attempts continue counting)
  bool quiet = false;            // progress lines only every progress_interval
  int ranks_per_case = 0;        // --ranks-per-case: overrides campaign.ranks_per_case (0: keep)
  bool force = false;            // run into a directory that holds another campaign
};

// Parses --ranks-per-case's value (an integer >= 1); throws InputError.
int parse_ranks_per_case(const std::string& text);

// Parses "i/n" (1 <= i <= n); throws InputError.
void parse_slice(const std::string& text, int& i, int& n);

// Collective over `world`. Returns the exit code (base/exit_codes.hpp): 0; 4 when cases of the
// slice failed or have no result; with `status`, 10 when work is left. With `list` or `status`
// `world` may be MPI_COMM_NULL (one process, MPI not started).
int run_campaign(const CampaignOptions& opt, MPI_Comm world, std::ostream& out);

// Partial results of slice i of n live in DIR/partials/slice_I_of_N.h5; the whole campaign's
// statistics in DIR/ensemble.h5.
std::string partial_path(const std::string& dir, int i, int n);
// A row of DIR/cases.tsv, the table of the campaign that runs there.
struct CaseTableRow {
  std::string id, point, params;  // case id, point id, the point's parameters as shown
};
// Its rows in table order (no table: none).
std::vector<CaseTableRow> case_table(const std::string& dir);
// Their case ids.
std::set<std::string> case_table_ids(const std::string& dir);

}  // namespace tumble::campaign
