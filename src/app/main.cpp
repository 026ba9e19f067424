// `tumble`: one executable, git-style subcommands. Each subcommand is a thin file in src/app/.
#include <mpi.h>

#include <cstdlib>
#include <iostream>
#include <memory>
#include <string>

#include "app/command_line.hpp"
#include "base/agreed_input.hpp"
#include "base/comm.hpp"
#include "base/error.hpp"
#include "base/exit_codes.hpp"
#include "base/temporary_files.hpp"
#include "contact/laws.hpp"
#include "h5/hdf5_file.hpp"

namespace {
// Whether an MPI launcher (mpirun, mpiexec, srun) started this process: its rank is in the
// environment (Open MPI; PMIx; MPICH, Intel MPI and srun's PMI-2).
bool under_mpi_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

// Whether this command line needs MPI. Starting MPI costs ~0.5 s, more than a whole Poincaré
// section or a refused option: the continuum model and the analyses are serial and make no MPI
// call (nor does anything they link), help/version print and exit, and `run --check` validates.
// `campaign --list` and `--status` read files in one process: the job-array scripts ask for the
// status outside the launcher, where a singleton MPI start fails on some clusters (an MPICH
// without mpiexec on PATH, Open MPI built without PMI-1 inside a Slurm allocation, Flux) and
// would keep every slice from running. Under a launcher they start MPI (rank 0 prints once).
bool needs_mpi(int argc, char** argv) {
  const char* command = nullptr;
  bool reads_only = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h" || a == "--version" || a == "--check" || a == "--list-keys")
      return false;  // (`run --check` validates and plans the bed: no MPI either)
    if (a == "--list" || a == "--status") reads_only = true;
    if (!command && !a.empty() && a[0] != '-') command = argv[i];
  }
  const std::string c = command ? command : "";
  if (c == "campaign" && reads_only) return under_mpi_launcher();
  return !(c.empty() || c == "cm" || c == "analyze");
}
}  // namespace

int main(int argc, char** argv) {
  // No threads make MPI calls: a campaign's rank 0 dispatches between its own case's time steps.
  const bool mpi = needs_mpi(argc, argv);
  if (mpi) MPI_Init(&argc, &argv);
  // A temporary file being written is removed if SIGTERM, SIGINT or SIGHUP ends the process (run
  // and campaign replace the first two with their stop handlers, which do the same on a second).
  tumble::remove_temporaries_on_signal();
  std::cout.setf(std::ios::unitbuf);  // progress lines reach logs and pipes at once
  tumble::contact::register_laws();   // before any scene is read (scene/law_registry.hpp)
  const std::unique_ptr<CLI::App> app = tumble::app::make_command_line();
  int rc = 0;
  try {
    // Under mpirun the command line is checked on every rank and agreed before any command runs
    // (app/command_line.hpp): a refusal is said once, by rank 0, and on every rank.
    if (mpi && tumble::size_of(MPI_COMM_WORLD) > 1)
      tumble::agreed_input(MPI_COMM_WORLD, [&] { tumble::app::check_command_line(argc, argv); });
    app->parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11 prints --help and --version (exit 0) and its own message for a bad option; its codes
    // (104-109) are replaced by the one for bad input. A subcommand's own exit code reaches here
    // as a RuntimeError (`campaign --status`: work left) and is kept.
    const int cli_rc = app->exit(e);
    namespace ec = tumble::exit_code;
    rc = e.get_name() == "RuntimeError" || cli_rc == ec::kOk ? cli_rc : ec::kBadInput;
  } catch (const tumble::CorruptInputError& e) {  // before InputError, its base
    std::cerr << "tumble: corrupt input: " << e.what() << "\n";
    rc = tumble::exit_code::kCorruptInput;
  } catch (const tumble::InputError& e) {
    std::cerr << "tumble: " << e.what() << "\n";
    rc = tumble::exit_code::kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "tumble: error: " << e.what() << "\n";
    rc = tumble::exit_code::kRunFailed;
  }
  // A file HDF5 could not close (a full disk: its caches could not be flushed) stays open inside
  // the library, and HDF5 1.10 then crashes while shutting down (in MPI_Finalize or at exit),
  // turning a reported I/O error (exit 1) into a segfault (139). Its message is out and nothing
  // damaged was left (h5/hdf5_file.cpp): leave without the library's shutdown.
  if (tumble::io::files_left_open()) {
    std::cout.flush();
    std::cerr.flush();
    std::_Exit(rc == tumble::exit_code::kOk ? tumble::exit_code::kRunFailed : rc);
  }
  if (mpi) MPI_Finalize();
  return rc;
}
