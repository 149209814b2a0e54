// The command line of `grip sweep` and bench/peers_sweep (the same options, the same files).
#include <cstdio>

#include "sweep/sweep.hpp"

namespace grip::sweep {

void addOptions(CLI::App& app, CommandLine& c) {
  app.add_option("--out", c.out, "output directory for sweep.csv and sweep.svg")
      ->capture_default_str();
  app.add_option("--scene", c.options.scenes, "a scene to run (repeatable; default: all)")
      ->take_all();
  app.add_flag("--quick", c.options.quick, "a small grid and a short pile (tests, CI)");
  app.add_option("--repeats", c.options.repeats, "timing rounds per setting, the fastest kept")
      ->capture_default_str();
}

int runCommand(const std::vector<Engine>& engines, const CommandLine& c) {
  validate(c.options);
  makeOutputDir(c.out);  // fail before the run, not after it
  std::printf("%-7s %-14s %9s %3s %3s %12s %12s\n", "engine", "scene", "dt", "sub", "it", "s/sim s",
              "error");
  const std::vector<Sample> samples = run(engines, c.options, [](const Sample& s) {
    std::printf("%-7s %-14s %9.6f %3d %3d %12.4g %12.4g%s\n", s.engine.c_str(), s.scene.c_str(),
                s.settings.dt, s.settings.substeps, s.settings.iterations, s.seconds, s.error,
                s.isDefault ? "  (default)" : "");
    std::fflush(stdout);
  });
  write(samples, c.out);
  std::printf("wrote %s/sweep.csv and %s/sweep.svg (%zu samples)\n", c.out.c_str(), c.out.c_str(),
              samples.size());
  return 0;
}

}  // namespace grip::sweep
