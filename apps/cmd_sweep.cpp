// `grip sweep`: grip's work-precision sweep over the reference scenes (docs/accuracy.md).
// bench/peers_sweep runs the same scenes with Bullet and ODE beside grip.
#include "commands.hpp"
#include "sweep/sweep.hpp"

namespace grip::cli {

Command addSweepCommand(CLI::App& app) {
  auto* sub = app.add_subcommand(
      "sweep", "run time against error on the reference scenes: writes sweep.csv, sweep.svg");
  auto c = std::make_shared<sweep::CommandLine>();
  sweep::addOptions(*sub, *c);
  return {sub, [c] { return sweep::runCommand({sweep::gripEngine()}, *c); }};
}

}  // namespace grip::cli
