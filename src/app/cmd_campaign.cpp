// `tumble campaign FILE`: many realizations over rank groups in one mpirun (campaign/). Parses the
// options and calls the library; the campaign file is validated in full before any work.
#include <mpi.h>

#include <iostream>

#include "app/campaign_commands.hpp"
#include "app/commands.hpp"
#include "base/agreed_input.hpp"
#include "base/environment.hpp"
#include "base/stop_request.hpp"
#include "campaign/campaign_run.hpp"

namespace tumble::app {

void register_campaign(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "campaign", "run a campaign of realizations over MPI rank groups (docs/campaign.md)");
  struct Opts {
    campaign::CampaignOptions run;
    std::string slice = "1/1";
    std::string ranks_per_case;
    std::string max_memory;
  };
  auto opts = std::make_shared<Opts>();
  cmd->add_option("file", opts->run.file, "campaign file (TOML)")->required();
  cmd->add_option("--slice", opts->slice,
                  "run slice i of n (job arrays): a deterministic, cost-balanced subset");
  cmd->add_option("--output,-o", opts->run.output, "campaign directory (overrides output_dir)")
      ->check([](const std::string& v) {
        return v.find_first_not_of(" \t") == std::string::npos
                   ? std::string("must name a directory (it is empty)")
                   : std::string();
      });
  cmd->add_option("--ranks-per-case", opts->ranks_per_case,
                  "ranks per case (overrides campaign.ranks_per_case; a sweep's own value wins)");
  cmd->add_option("--max-memory", opts->max_memory,
                  "a case whose scene is estimated to need more memory than this is invalid (e.g. "
                  "2G; default: the machine's available memory)");
  CLI::Option* list =
      cmd->add_flag("--list", opts->run.list, "print the expanded cases of the slice and exit");
  cmd->add_flag("--status", opts->run.status,
                "print what is done/failed/left in the slice; exit 0 if nothing is left to run")
      ->excludes(list);  // (both: --list won, and a script reading the exit code got 0)
  cmd->add_flag("--retry-failed", opts->run.retry_failed,
                "run failed cases again (their attempts keep counting)");
  cmd->add_flag("--force", opts->run.force,
                "run into a directory that holds another campaign (its table and statistics "
                "are replaced)");
  cmd->add_flag("--quiet,-q", opts->run.quiet, "progress lines only every progress_interval");
  cmd->callback([opts]() {
    // `--list` and `--status` run without MPI in one process (app/main.cpp): no communicator.
    int mpi = 0;
    MPI_Initialized(&mpi);
    const MPI_Comm world = mpi ? MPI_COMM_WORLD : MPI_COMM_NULL;
    // Errors are said once, by rank 0: the options and files are agreed over the ranks, and
    // run_campaign gives every rank rank 0's refusal or error.
    agreed_input(world, [&] {
      arm_memory_limit(opts->max_memory);
      campaign::parse_slice(opts->slice, opts->run.slice_i, opts->run.slice_n);
      if (!opts->ranks_per_case.empty())
        opts->run.ranks_per_case = campaign::parse_ranks_per_case(opts->ranks_per_case);
    });
    check_environment(world);  // (else each case would meet it only after its bed)
    // SIGUSR1/SIGTERM/SIGINT: every case checkpoints and the campaign ends, resumable.
    if (!opts->run.list && !opts->run.status) install_stop_handlers();
    const int rc = campaign::run_campaign(opts->run, world, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace tumble::app
