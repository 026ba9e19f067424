// `tumble merge DIR`: fold the partial statistics of a campaign's slices into DIR/ensemble.h5.
#include <iostream>

#include "app/campaign_commands.hpp"
#include "campaign/merge.hpp"

namespace tumble::app {

void register_merge(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "merge", "fold the slices of a campaign into DIR/ensemble.h5 (Chan's formula, PETSc Vecs)");
  struct Opts {
    std::string dir;
    int slices = 0;
  };
  auto opts = std::make_shared<Opts>();
  cmd->add_option("dir", opts->dir, "campaign directory")->required();
  cmd->add_option("--slices", opts->slices,
                  "merge the partial results of this many slices (default: the only slicing "
                  "present)")
      ->check(CLI::Range(1, 1000000));
  cmd->callback([opts]() {
    const int rc = campaign::merge_campaign(opts->dir, opts->slices, std::cout);
    if (rc != 0) throw CLI::RuntimeError(rc);
  });
}

}  // namespace tumble::app
