#pragma once
// The `tumble` command line: the CLI11 app with every subcommand registered, and its check under
// mpirun before any subcommand runs.
#include <CLI/CLI.hpp>
#include <memory>

namespace tumble::app {

// The app with run, campaign, merge, cm and analyze registered; its refusals are printed as
// "tumble: <CLI11's message>", the prefix of every other refusal.
std::unique_ptr<CLI::App> make_command_line();

// Parses and checks argv with a second app that stops before any subcommand runs, and throws
// InputError with the message the real parse would print when CLI11 refuses it. Under mpirun main
// runs it through agreed_input before the real parse: every rank parses the same arguments, so a
// mistyped option was printed once per rank (64 copies under mpirun -n 64); and a rank given other
// arguments (Open MPI's MPMD syntax, a wrapper) refused alone while the others ran the command
// and waited for it in its first collective call for ever.
void check_command_line(int argc, char** argv);

}  // namespace tumble::app
