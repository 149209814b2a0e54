// `grip eval placement`: the accuracy evaluation of thesis 5.2 (Table 5.2) for both interaction
// methods, printed as mean ± sd / median positioning error and time per trial.
#include <cstdio>

#include "commands.hpp"
#include "scene/placement.hpp"

namespace grip::cli {

namespace {
struct EvalArgs {
  scene::PlacementDef def;
  bool trialsShown = false;
};

int evalPlacement(const EvalArgs& a) {
  const std::vector<scene::PlacementMethod> r = scene::evaluatePlacement(a.def);
  std::printf("%s", scene::placementTable(a.def, r).c_str());
  if (a.trialsShown) {
    std::printf("\ntrial  start -> target (m)                 method      error/mm  time/s\n");
    for (const scene::PlacementMethod& m : r) {
      for (size_t i = 0; i < m.trials.size(); ++i) {
        const scene::PlacementTrial& t = m.trials[i];
        std::printf("%5zu  (%6.3f, %6.3f) -> (%6.3f, %6.3f)  %-11s %8.2f  %6.2f\n", i + 1,
                    t.start.x(), t.start.z(), t.target.x(), t.target.z(), m.method.c_str(),
                    1000.0 * t.error, t.time);
      }
    }
  }
  return 0;
}
}  // namespace

Command addEvalCommand(CLI::App& app) {
  auto* sub = app.add_subcommand("eval", "evaluations of the thesis (chapter 5)");
  auto* placement = sub->add_subcommand(
      "placement", "section 5.2: move a cube to a target square, Coulomb vs kinematic");
  sub->require_subcommand(1);
  auto a = std::make_shared<EvalArgs>();
  placement->add_option("--trials", a->def.trials, "randomized trials (default 20)");
  placement->add_option("--seed", a->def.seed, "seed of the layouts and the noise (default 1)");
  placement->add_option("--noise", a->def.noise, "tracking noise, m rms (default 0.001)");
  placement->add_flag("--show-trials", a->trialsShown, "print every trial");
  return {sub, [a] { return evalPlacement(*a); }};
}

}  // namespace grip::cli
