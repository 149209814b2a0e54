// `grip demo`: a stack of boxes hit by a thrown ball, printed as it happens; then a built-in hand
// scene (default: grasp_lift) run and recorded like `grip run NAME --out DIR`.
#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "dynamics/scenes.hpp"
#include "scene/scene.hpp"
#include "web/report.hpp"

namespace grip::cli {

namespace {
int runDemo(int boxes, double seconds, double hz) {
  World world;
  scenes::addGround(world);
  const std::vector<BodyId> stack = scenes::addBoxStack(world, boxes, 0.2, 1.0);
  BodyDef ball;
  ball.shape = Shape::sphere(0.12);
  ball.mass = 3.0;
  ball.position = Vec3(-4.0, 0.5, 0.0);
  ball.linearVelocity = Vec3(9.0, 3.2, 0.0);  // thrown at the stack
  ball.name = "ball";
  const BodyId ballId = world.createBody(ball);

  std::printf("grip demo: %d boxes (0.2 m, 1 kg) stacked; a 3 kg ball thrown at 9.5 m/s\n", boxes);
  const int steps = static_cast<int>(seconds * hz);
  for (int i = 0; i < steps; ++i) {
    world.step(1.0 / hz);
    for (const ContactEvent& e : world.contactBeginEvents()) {
      if ((e.a == ballId || e.b == ballId) && e.approachSpeed > 0.5) {
        const BodyId other = e.a == ballId ? e.b : e.a;
        std::printf("  t=%5.2f s  ball hits %-8s at %4.1f m/s\n", world.time(),
                    world.name(other).c_str(), e.approachSpeed);
      }
    }
  }
  int toppled = 0;
  for (size_t i = 0; i < stack.size(); ++i) {
    const Vec3 p = world.pose(stack[i]).p;
    const double rest = 0.1 + 0.2 * static_cast<double>(i);
    if (std::abs(p.y() - rest) > 0.05 || std::abs(p.x()) > 0.05) ++toppled;
  }
  const Vec3 bp = world.pose(ballId).p;
  std::printf("after %.1f s: %d of %d boxes knocked out of place; ball at (%.2f, %.2f, %.2f)\n",
              seconds, toppled, boxes, bp.x(), bp.y(), bp.z());
  std::printf("awake bodies %d, state hash %016llx\n", world.stats().awakeBodies,
              static_cast<unsigned long long>(world.stateHash()));
  return 0;
}

// A built-in hand scene, recorded into `out`.
int runHandScene(const std::string& name, const std::string& out) {
  const auto doc = scene::builtinScene(name);
  if (!doc) throw Error(name, "no such built-in scene (`grip scenes` lists them)");
  const scene::Scene sc = scene::parseScene(*doc);
  std::printf("\nhand scene %s: %s\n", sc.name.c_str(), sc.description.c_str());
  scene::RunOptions opt;
  opt.outDir = out;
  const scene::RunResult r = scene::run(sc, opt);
  for (const scene::CheckResult& c : r.checks) {
    std::printf("  %s  %s: %s\n", c.passed ? "PASS" : "FAIL", c.label.c_str(), c.detail.c_str());
  }
  std::printf("state hash %s; recording written to %s, metrics to %s (format: docs/scenes.md)\n",
              r.metrics["stateHash"].get<std::string>().c_str(), r.recordingPath.c_str(),
              r.metricsPath.c_str());
  const std::string page = (std::filesystem::path(out) / "report.html").string();
  web::writeReport(r.recordingPath, r.metrics, page);
  std::printf("see it: open %s in a browser (or `grip view %s`)\n", page.c_str(),
              r.recordingPath.c_str());
  std::printf("more scenes: `grip scenes`; run one with `grip run NAME --out DIR`\n");
  return r.allPassed() ? 0 : 3;
}
}  // namespace

Command addDemoCommand(CLI::App& app) {
  auto* sub = app.add_subcommand("demo", "run the built-in demo scene and print what happened");
  auto boxes = std::make_shared<int>(10);
  auto seconds = std::make_shared<double>(4.0);
  auto hz = std::make_shared<double>(60.0);
  auto scene = std::make_shared<std::string>("grasp_lift");
  auto out = std::make_shared<std::string>("grip-demo");
  sub->add_option("--boxes", *boxes, "boxes in the stack")->check(CLI::Range(1, 200));
  sub->add_option("--seconds", *seconds, "simulated time")->check(CLI::Range(0.0, 3600.0));
  sub->add_option("--hz", *hz, "steps per second")->check(CLI::Range(1.0, 10000.0));
  sub->add_option("--scene", *scene, "built-in hand scene to run after the stack (\"\": none)");
  sub->add_option("--out", *out, "where the hand scene's recording and metrics go");
  return {sub, [=] {
            const int rc = runDemo(*boxes, *seconds, *hz);
            if (rc != 0 || scene->empty()) return rc;
            return runHandScene(*scene, *out);
          }};
}

}  // namespace grip::cli
