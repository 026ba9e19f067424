#include "app/command_line.hpp"

#include <string>

#include "app/campaign_commands.hpp"
#include "app/commands.hpp"
#include "base/error.hpp"
#include "base/version.hpp"

namespace tumble::app {
namespace {
std::string failure_message(const CLI::App* app, const CLI::Error& e) {
  return "tumble: " + CLI::FailureMessage::simple(app, e);
}

// Leaves the options, their checks and the subcommands' requirements; removes what each
// subcommand does once parsed (checks make no MPI call and write nothing: commands do).
void drop_callbacks(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    sub->final_callback(std::function<void()>{});
    sub->parse_complete_callback(std::function<void()>{});
    drop_callbacks(*sub);
  }
}
}  // namespace

std::unique_ptr<CLI::App> make_command_line() {
  auto app =
      std::make_unique<CLI::App>("Tumble: DEM campaigns of granular segregation in tumblers");
  app->set_version_flag("--version", std::string(kVersion) + " (" + kGitHash + ")");
  app->require_subcommand(1);
  app->failure_message(failure_message);
  register_run(*app);
  register_campaign(*app);
  register_merge(*app);
  register_cm(*app);
  register_analyze(*app);
  return app;
}

void check_command_line(int argc, char** argv) {
  const std::unique_ptr<CLI::App> app = make_command_line();
  drop_callbacks(*app);
  try {
    app->parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::string message = CLI::FailureMessage::simple(app.get(), e);
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw InputError(message);  // (main prints it after "tumble: ", as the real parse would)
  }
}

}  // namespace tumble::app
