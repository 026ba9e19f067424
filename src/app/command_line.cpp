#include "app/command_line.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "app/campaign_commands.hpp"
#include "app/commands.hpp"
#include "base/error.hpp"
#include "base/version.hpp"

namespace tumble::app {
namespace {
// Whether `text` is a decimal integer's text: an optional sign, then digits only.
bool is_integer_text(const std::string& text) {
  const std::size_t sign = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  return text.size() > sign && text.find_first_not_of("0123456789", sign) == std::string::npos;
}

// CLI11 says "Could not convert: --seeds = 3000000000" for a value that is no number of the
// option's type: for an integer past an int's range (decimal_integer below lets through what fits
// a long long) as for "abc". This says which it is. "" where the message is not of that form.
std::string conversion_failure(const CLI::App* at, const std::string& what) {
  const std::string head = "Could not convert: ";
  const std::size_t eq = what.find(" = ");
  if (what.rfind(head, 0) != 0 || eq == std::string::npos) return "";
  const std::string name = what.substr(head.size(), eq - head.size());
  const std::string value = what.substr(eq + 3);
  const CLI::Option* o = at->get_option_no_throw(name);
  if (o == nullptr) return "";
  const std::string type = o->get_type_name();
  const bool is_float = type.find("FLOAT") != std::string::npos;
  if (!is_float && type.find("INT") == std::string::npos) return "";
  // CLI11 joins a list option's values with commas ("--cumulative 45,3000000000", "--pair 1 x"):
  // the one value that fails is named, not the list.
  const std::vector<std::string> values = CLI::detail::split(value, ',');
  auto is_number = [](const std::string& v) {
    char* end = nullptr;
    errno = 0;
    (void)std::strtod(v.c_str(), &end);
    return !v.empty() && end == v.c_str() + v.size() && errno != ERANGE;
  };
  for (const std::string& v : values)
    if (is_float ? !is_number(v) : !is_integer_text(v))
      return name + ": '" + v + "' is not " + (is_float ? "a number" : "an integer");
  if (is_float) return "";  // (every value a number: some other failure, CLI11's words)
  // (every value an integer: one is past the option's range; an int's, unless the option is wider)
  std::string past = value;
  for (const std::string& v : values)
    if (std::abs(std::strtod(v.c_str(), nullptr)) > 2147483647.0) {
      past = v;
      break;
    }
  return name + ": '" + past + "' is out of range for this option";
}

// An option that takes files took the next option as one: `cm drift --merge -o x.h5` said "File
// does not exist: -o". This says that the files are missing before it; "" for any other message.
std::string option_for_a_path(const CLI::App* at, const std::string& what) {
  const std::string tag = "does not exist: ";
  const std::size_t i = what.find(tag);
  const std::size_t colon = what.find(": ");
  if (i == std::string::npos || colon == std::string::npos) return "";
  const std::string value = what.substr(i + tag.size());
  if (value.empty() || value[0] != '-' || at->get_option_no_throw(value) == nullptr) return "";
  return what.substr(0, colon) + ": '" + value + "' is one of this command's options, not a " +
         "path (the option's value is missing before it)";
}

// CLI11's message, but for a first word that is no command: CLI11 says only "A subcommand is
// required" (`tumble fun` for `tumble run`); this names the word and the commands.
std::string parse_failure(const CLI::App* app, const CLI::Error& e) {
  // The command that wanted a subcommand: tumble itself, or the deepest one given (`tumble cm
  // foo` said only "A subcommand is required").
  const CLI::App* at = app;
  std::string path = "tumble";
  while (!at->get_subcommands().empty()) {
    at = at->get_subcommands().front();
    path += " " + at->get_name();
  }
  const std::vector<std::string> rest = at->remaining();
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && !at->get_subcommands({}).empty() &&
      (!rest.empty() || std::string(e.what()).find("subcommand") != std::string::npos)) {
    std::string names;
    for (const CLI::App* sub : at->get_subcommands({}))
      names += (names.empty() ? "" : ", ") + sub->get_name();
    if (rest.empty())
      return "a command is required" + (at == app ? "" : " after '" + path + "'") + ": " + names +
             " (" + path + " --help)\n";
    const std::string& word = rest.front();
    return (word[0] == '-'
                ? "unknown option '" + word + "' (" + path + "'s options come after its command)"
                : "unknown command '" + word + "'" + (at == app ? "" : " of " + path)) +
           "; the commands are " + names + " (" + path + " --help)\n";
  }
  if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr) {
    const std::string said = option_for_a_path(at, e.what());
    if (!said.empty()) return said + " (" + path + " --help)\n";
  }
  if (dynamic_cast<const CLI::ConversionError*>(&e) != nullptr) {
    const std::string said = conversion_failure(at, e.what());
    if (!said.empty()) return said + " (" + path + " --help)\n";
  }
  return CLI::FailureMessage::simple(app, e);
}

std::string failure_message(const CLI::App* app, const CLI::Error& e) {
  return "tumble: " + parse_failure(app, e);
}

// CLI11 (2.1) reads an integer with strtoll(text, 0): "010" as octal 8 (`merge --slices 010`
// looked for 8 slices), "0x8" as hex, and a number past the type's range as its limit, silently
// (`--max-steps 99999999999999999999`: no limit). Tumble's integers are decimal and in range.
std::string decimal_integer(std::string& text, bool is_unsigned) {
  const std::size_t i = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  if (text.size() > i + 1 && text[i] == '0' &&
      std::string("0123456789xXbBoO").find(text[i + 1]) != std::string::npos)
    return "'" + text + "' is not a decimal integer (a leading 0 reads as octal or hex)";
  if (!is_integer_text(text)) return "";  // (not an integer at all: conversion_failure says so)
  // (CLI11 turns -5 into 2^64 - 5 for an unsigned option)
  if (is_unsigned && text[0] == '-') return "'" + text + "' must not be negative";
  errno = 0;
  if (is_unsigned)
    (void)std::strtoull(text.c_str(), nullptr, 10);
  else
    (void)std::strtoll(text.c_str(), nullptr, 10);
  if (errno == ERANGE) return "'" + text + "' is out of range";
  return "";
}

// Every integer option of `app` and its subcommands, checked as decimal_integer.
void check_integers(CLI::App& app) {
  for (CLI::Option* o : app.get_options()) {
    const std::string type = o->get_type_name();
    if (type.find("INT") == std::string::npos) continue;
    const bool is_unsigned = type.find("UINT") != std::string::npos;
    o->check(CLI::Validator(
        [is_unsigned](std::string& text) { return decimal_integer(text, is_unsigned); }, "",
        "decimal integer"));
  }
  for (CLI::App* sub : app.get_subcommands({})) check_integers(*sub);
}

// Every text option of `app` and its subcommands refuses an empty value: `--max-memory ""` (a
// job script's unset variable) meant the default, `cm poincare -o ""` wrote to the default file.
void check_texts(CLI::App& app) {
  for (CLI::Option* o : app.get_options()) {
    if (o->get_type_name().find("TEXT") == std::string::npos) continue;
    o->check(CLI::Validator(
        [](std::string& text) { return text.empty() ? std::string("an empty value") : ""; }, "",
        "not empty"));
  }
  for (CLI::App* sub : app.get_subcommands({})) check_texts(*sub);
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
  check_integers(app);
  check_texts(app);
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
    std::string message = parse_failure(&app, e);
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw InputError(message);  // (main prints it after "tumble: ", as the real parse would)
  }
  throw std::logic_error("check_command_line: CLI11 parsed without calling pre_callback()");
}

}  // namespace tumble::app
