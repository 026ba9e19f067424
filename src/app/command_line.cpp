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

void add_commands(CLI::App& app) {
  app.set_version_flag("--version", std::string(kVersion) + " (" + kGitHash + ")");
  app.require_subcommand(1);
  app.failure_message(failure_message);
  register_run(app);
  register_campaign(app);
  register_merge(app);
  register_cm(app);
  register_analyze(app);
}

// An app that stops once the command line is parsed and checked, before any subcommand's callback
// runs: CLI11 calls the root's pre_callback() first, after every option, check and requirement
// has been processed. (Not by removing the callbacks: they own the variables the options write.)
struct ParsedOnly {};
class CheckOnlyApp : public CLI::App {
 public:
  using CLI::App::App;
  void pre_callback() override { throw ParsedOnly{}; }
};
}  // namespace

std::unique_ptr<CLI::App> make_command_line() {
  auto app =
      std::make_unique<CLI::App>("Tumble: DEM campaigns of granular segregation in tumblers");
  add_commands(*app);
  return app;
}

void check_command_line(int argc, char** argv) {
  CheckOnlyApp app("Tumble: DEM campaigns of granular segregation in tumblers");
  add_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const ParsedOnly&) {
    return;
  } catch (const CLI::ParseError& e) {
    // (--help and --version, bundled where main's look for them misses them, `-qh`: the real
    // parse prints them)
    if (e.get_exit_code() == 0) return;
    std::string message = CLI::FailureMessage::simple(&app, e);
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw InputError(message);  // (main prints it after "tumble: ", as the real parse would)
  }
  throw std::logic_error("check_command_line: CLI11 parsed without calling pre_callback()");
}

}  // namespace tumble::app
