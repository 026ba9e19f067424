// `tumble`: one executable, git-style subcommands. Each subcommand is a thin file in src/app/.
#include <mpi.h>

#include <iostream>

#include "app/campaign_commands.hpp"
#include "app/commands.hpp"
#include "base/error.hpp"
#include "base/exit_codes.hpp"
#include "base/version.hpp"
#include "contact/laws.hpp"

int main(int argc, char** argv) {
  // No threads make MPI calls: a campaign's rank 0 dispatches between its own case's time steps.
  MPI_Init(&argc, &argv);
  std::cout.setf(std::ios::unitbuf);  // progress lines reach logs and pipes at once
  tumble::contact::register_laws();   // before any scene is read (scene/law_registry.hpp)
  CLI::App app{"Tumble: DEM campaigns of granular segregation in tumblers"};
  app.set_version_flag("--version", std::string(tumble::kVersion) + " (" + tumble::kGitHash + ")");
  app.require_subcommand(1);
  tumble::app::register_run(app);
  tumble::app::register_campaign(app);
  tumble::app::register_merge(app);
  tumble::app::register_cm(app);
  tumble::app::register_analyze(app);
  int rc = 0;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    rc = app.exit(e);
  } catch (const tumble::CorruptInputError& e) {  // before InputError, its base
    std::cerr << "tumble: corrupt input: " << e.what() << "\n";
    rc = tumble::exit_code::kCorruptInput;
  } catch (const tumble::InputError& e) {
    std::cerr << "tumble: " << e.what() << "\n";
    rc = 2;
  } catch (const std::exception& e) {
    std::cerr << "tumble: error: " << e.what() << "\n";
    rc = 1;
  }
  MPI_Finalize();
  return rc;
}
