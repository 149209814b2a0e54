// Subcommands of the `grip` command line. Each registers itself on the app and returns the
// exit code through the callback it installs. Errors: one line on stderr, non-zero exit.
#pragma once

#include <CLI/CLI.hpp>

namespace grip::cli {

// A subcommand and what runs when it was chosen (returns the exit code).
struct Command {
  CLI::App* sub = nullptr;
  std::function<int()> run;
};
Command addDemoCommand(CLI::App& app);
Command addRunCommand(CLI::App& app);
Command addScenesCommand(CLI::App& app);
Command addEvalCommand(CLI::App& app);
Command addViewCommand(CLI::App& app);
Command addSweepCommand(CLI::App& app);
#ifdef GRIP_HAVE_VOXEL
Command addPrepCommand(CLI::App& app);
#endif

}  // namespace grip::cli
