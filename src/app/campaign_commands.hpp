#pragma once
// The campaign subcommands (issue 4). Each lives in its own thin file; main.cpp wires them in.
#include <CLI/CLI.hpp>

namespace tumble::app {
// `tumble campaign FILE [--slice i/n] [--output DIR] [--list|--status] ...` (cmd_campaign.cpp)
void register_campaign(CLI::App& app);
// `tumble merge DIR [--slices N]`: fold the slices' partial statistics (cmd_merge.cpp)
void register_merge(CLI::App& app);
}  // namespace tumble::app
