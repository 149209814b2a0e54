// grip: the command line. `grip --help` lists the subcommands.
#include <exception>
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"grip: a deterministic rigid-body engine for physics-based hand interaction"};
  app.require_subcommand(1);
  std::vector<grip::cli::Command> commands;
  commands.push_back(grip::cli::addDemoCommand(app));
  commands.push_back(grip::cli::addRunCommand(app));
  commands.push_back(grip::cli::addScenesCommand(app));
  commands.push_back(grip::cli::addEvalCommand(app));
  commands.push_back(grip::cli::addViewCommand(app));
  commands.push_back(grip::cli::addSweepCommand(app));
#ifdef GRIP_HAVE_VOXEL
  commands.push_back(grip::cli::addPrepCommand(app));
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::cerr << "grip: " << e.what() << "\n";
    return 2;
  }
  try {
    for (const auto& c : commands)
      if (c.sub->parsed()) return c.run();
  } catch (const grip::Error& e) {
    std::cerr << "grip: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "grip: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
