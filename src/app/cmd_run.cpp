// `tumble run SCENE.toml`: one DEM realization. Parses, validates the whole scene before any work,
// and calls the library.
#include <mpi.h>

#include <filesystem>
#include <iostream>
#include <optional>
#include <tuple>

#include "app/commands.hpp"
#include "base/agreed_input.hpp"
#include "base/environment.hpp"
#include "base/error.hpp"
#include "base/exit_codes.hpp"
#include "base/memory.hpp"
#include "base/stop_request.hpp"
#include "base/usable_directory.hpp"
#include "io/bed_io.hpp"
#include "io/checkpoint.hpp"
#include "run/realization.hpp"
#include "run/settled_bed.hpp"
#include "scene/fill.hpp"
#include "scene/scene.hpp"

namespace tumble::app {

void arm_memory_limit(const std::string& max_memory) {
  if (!max_memory.empty())
    set_memory_limit(parse_memory_size(max_memory, "--max-memory"), "--max-memory " + max_memory);
  else if (const double avail = available_memory_bytes(); avail > 0)
    set_memory_limit(avail, "this machine has available (MemAvailable)");
}

void register_run(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "run", "run one DEM realization of a scene (on all ranks of mpirun, domain-decomposed)");
  struct Opts {
    std::string scene;
    std::vector<std::string> overrides;
    std::string restart;
    bool resume = false, list_keys = false, check = false;
    long long max_steps = -1;
    std::string max_memory;
  };
  auto opts = std::make_shared<Opts>();
  cmd->add_option("scene", opts->scene, "scene file (TOML)");
  cmd->add_option("--set,-s", opts->overrides, "override a key: section.key=value (repeatable)");
  CLI::Option* restart =
      cmd->add_option("--restart", opts->restart, "continue from this checkpoint file");
  cmd->add_flag("--resume", opts->resume, "continue from OUTPUT_DIR/checkpoint.h5 if present")
      ->excludes(restart);  // (two checkpoints named: which one goes on is not for us to guess)
  // The value as CLI11 will read it (" -1" passes a test of the text): -1, the default, meant
  // "no limit", and a given -5 silently so. A check, not the command's own test, so that mpirun
  // agrees on it with the other refusals of the command line (app/command_line.hpp).
  cmd->add_option("--max-steps", opts->max_steps,
                  "stop after this many protocol steps (default: at the protocol's end)")
      ->check([](const std::string& text) {
        long long n = 0;
        if (!CLI::detail::lexical_cast(text, n) || n >= 0) return std::string();
        return "must be >= 0 (leave it out to run to the protocol's end), not " + std::to_string(n);
      });
  cmd->add_option("--max-memory", opts->max_memory,
                  "refuse a scene estimated to need more memory than this (e.g. 2G; default: the "
                  "machine's available memory)");
  cmd->add_flag("--check", opts->check, "validate the scene, print it resolved, and exit");
  cmd->add_flag("--list-keys", opts->list_keys,
                "list every scene key with its range or choices, default and meaning, and exit");
  cmd->callback([opts]() {
    if (opts->list_keys) {
      for (const auto& k : scene_schema()) {
        std::cout << k.key << "  ";
        if (k.type == KeySpec::Text && k.choices.empty())
          std::cout << "text";
        else if (k.type == KeySpec::Text)
          for (std::size_t i = 0; i < k.choices.size(); ++i)
            std::cout << (i ? "|" : "") << k.choices[i];
        else
          std::cout << "[" << k.lo << ", " << k.hi << "]"
                    << (k.word.empty() ? "" : " or " + k.word);
        std::cout << "  (default " << default_text(k) << ")  " << k.help << "\n";
      }
      return;
    }
    // The same arguments and files on every rank: a bad one is said once, by rank 0.
    std::optional<Scene> loaded;
    agreed_input(MPI_COMM_WORLD, [&] {
      if (opts->scene.empty())
        throw InputError("scene: a scene file is required (or --list-keys to list the keys)");
      arm_memory_limit(opts->max_memory);
      loaded = load_scene(opts->scene, opts->overrides);
      // The folders this run writes into can be made and written (a file in the way, no
      // permission): asked here, of the run's own scene, not in every scene read back from a
      // file (another user's results). A bed cache that exists may be read-only (beds shared).
      for (const auto& [key, dir, read_only_ok] :
           {std::tuple<const char*, const std::string&, bool>{"scene.output_dir",
                                                              loaded->output_dir, false},
            {"fill.bed_cache", loaded->bed_cache, true}})
        if (const std::string why = cannot_make_directory(dir, read_only_ok); !why.empty())
          throw InputError("scene error: key '" + std::string(key) + "' = '" + dir +
                           "' cannot be used: " + why);
      // A missing checkpoint is bad input (exit 2), found before the bed is made or the HDF5
      // library is asked to open it.
      if (!opts->restart.empty() && !std::filesystem::is_regular_file(opts->restart))
        throw InputError("--restart '" + opts->restart + "': no such checkpoint file");
      if (!opts->restart.empty()) io::check_is_checkpoint(opts->restart);
      // A bed to fill without gravity never settles (a scene without it is valid for an engine
      // given its particles: a bed file or a checkpoint).
      if (opts->restart.empty() && loaded->bed_file.empty() && loaded->g <= 0)
        throw InputError(settling_needs_gravity());
      // A bed the user names is read and checked now, before the output folder is made (the run
      // reads it again when it starts: 0.1 s for 89k particles), unless a checkpoint replaces it.
      const bool from_checkpoint =
          !opts->restart.empty() ||
          (opts->resume && std::filesystem::exists(loaded->output_dir + "/checkpoint.h5"));
      if (!loaded->bed_file.empty() && !from_checkpoint)
        (void)io::read_bed(loaded->bed_file, *loaded);
    });
    const Scene& scene = *loaded;
    // (The engine and the domain read the environment only after the bed is made.)
    check_environment(MPI_COMM_WORLD);
    if (opts->check) {
      // A checkpoint the run would start from is read and checked as the run would (its
      // contents, the scene it was written with): --check said only that the file was one.
      const std::string checkpoint =
          !opts->restart.empty() ? opts->restart : scene.output_dir + "/checkpoint.h5";
      if (!opts->restart.empty() || (opts->resume && std::filesystem::exists(checkpoint)))
        agreed_input(MPI_COMM_WORLD, [&] { check_restart_from(scene, checkpoint); });
      std::cout << scene_to_text(scene);
      if (scene.bed_file.empty()) {
        std::cout << "# bed: ";
        if (!scene.cylinder()) {
          const BedPlan plan = plan_bed(scene, false);
          std::cout << plan.n_large << " large + " << plan.n_small << " small = ";
        }
        std::cout << planned_particle_count(scene) << " particles; time step " << scene.time_step()
                  << " s (stability bound " << time_step_bound(scene) << " s); "
                  << scene.protocol_steps() << " steps\n";
      }
      return;
    }
    RunOptions ro;
    ro.restart_file = opts->restart;
    ro.resume = opts->resume;
    ro.max_steps = opts->max_steps;
    ro.log = &std::cout;
    // Under mpirun every rank runs this one realization together (domain decomposition).
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    if (ranks > 1) ro.comm = MPI_COMM_WORLD;
    // SIGUSR1/SIGTERM/SIGINT: a checkpoint at the next neighbour rebuild, then exit 10.
    install_stop_handlers();
    try {
      run_realization(scene, ro);
    } catch (const StopRequest& e) {
      int rank = 0;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      if (rank == 0)
        std::cout << "[run] " << e.what() << "; go on with: tumble run " << opts->scene
                  << " --resume (the same --set options)\n";
      throw CLI::RuntimeError(exit_code::kWorkLeft);
    }
  });
}

}  // namespace tumble::app
