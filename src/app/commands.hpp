#pragma once
// Each subcommand lives in its own thin file: it registers its options on the CLI11 app and returns
// a callback that runs it. main.cpp only wires them together.
#include <CLI/CLI.hpp>
#include <string>

namespace tumble::app {
// `tumble run SCENE.toml [--set key=value ...] [--restart FILE]` (cmd_run.cpp)
void register_run(CLI::App& app);
// `tumble cm poincare|orbits|mcm ...`: the continuum model (cmd_cm.cpp)
void register_cm(CLI::App& app);
// `tumble analyze classify|section|light|enrichment|campaign` (cmd_analyze.cpp)
void register_analyze(CLI::App& app);
// Sets the memory a scene may need (scene/fill.hpp, set_memory_limit): `max_memory` ("2G") when
// given, else the machine's available memory. `tumble run` and `tumble campaign` (cmd_run.cpp)
void arm_memory_limit(const std::string& max_memory);
}  // namespace tumble::app
