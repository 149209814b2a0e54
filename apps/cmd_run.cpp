// `grip run SCENE`: runs a scene file or a built-in scene headless, writes the recording and
// metrics, prints a summary, the checks and the state hash. Exit: 0 all checks passed, 3 some
// check failed, 1 bad input or an output error (one line on stderr).
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "commands.hpp"
#include "scene/scene.hpp"
#include "web/report.hpp"

namespace grip::cli {

namespace {

struct RunArgs {
  std::string scene;
  std::string out;
  std::string method;
  std::vector<std::string> sets;
  int recordEvery = 1;
  bool quiet = false;
  bool html = false;
};

// A file path if one exists there, else the name of a built-in scene. `baseDir` receives the
// folder that relative paths in the scene are taken from.
nlohmann::json loadDocument(const std::string& what, std::string& baseDir) {
  std::error_code ec;
  if (std::filesystem::exists(what, ec)) {
    baseDir = std::filesystem::absolute(what, ec).parent_path().string();
    return scene::readSceneFile(what);
  }
  baseDir = scene::builtinBaseDir();
  if (auto doc = scene::builtinScene(what)) return *doc;
  throw Error(what, "no such scene file or built-in scene (`grip scenes` lists the built-in ones)");
}

void progressBar(int step, int steps) {
  const int width = 40;
  const int filled = static_cast<int>(static_cast<long long>(width) * step / steps);
  std::fprintf(stderr, "\r[%.*s%*s] %3d%%", filled, "########################################",
               width - filled, "", static_cast<int>(100LL * step / steps));
  if (step == steps) std::fprintf(stderr, "\r%*s\r", width + 8, "");
  std::fflush(stderr);
}

int runScene(const RunArgs& a) {
  if (a.html && a.out.empty())
    throw Error("--html", "needs --out DIR (the report goes beside the recording)");
  std::string baseDir;
  nlohmann::json doc = loadDocument(a.scene, baseDir);
  for (const std::string& s : a.sets) scene::applyOverride(doc, s);
  if (!a.method.empty()) {
    if (!doc.contains("interaction") || !doc["interaction"].is_object())
      doc["interaction"] = nlohmann::json::object();
    doc["interaction"]["method"] = a.method;
  }
  const scene::Scene sc = scene::parseScene(doc, baseDir);
  scene::RunOptions opt;
  opt.outDir = a.out;
  opt.recordEvery = a.recordEvery;
  if (!a.quiet && isatty(STDERR_FILENO)) opt.progress = progressBar;
  const scene::RunResult r = scene::run(sc, opt);

  const nlohmann::json& m = r.metrics;
  if (!a.quiet) {
    std::printf("%s: %d steps, %.2f s simulated in %.3f s (%.0fx real time), method %s\n",
                sc.name.c_str(), r.steps, r.simulatedTime, m["wallTime"].get<double>(),
                m["realtimeFactor"].get<double>(), m["method"].get<std::string>().c_str());
    const nlohmann::json& h = m["hands"];
    if (!sc.hands.empty()) {
      std::printf(
          "hands: %lld contacts begun, %lld slip onsets, max penetration %.1f mm tracked / %.1f mm "
          "visual\n",
          h["contactsBegun"].get<long long>(), h["slipOnsets"].get<long long>(),
          1000.0 * h["maxPenetrationTracked"].get<double>(),
          1000.0 * h["maxPenetrationVisual"].get<double>());
    }
    for (const nlohmann::json& b : m["jointBreaks"]) {
      std::printf("joints[%lld] broke at %.3f s (%.3g N, %.3g N m)\n", b["joint"].get<long long>(),
                  b["time"].get<double>(), b["force"].get<double>(), b["torque"].get<double>());
    }
    for (const scene::CheckResult& c : r.checks) {
      std::printf("  %s  %s: %s\n", c.passed ? "PASS" : "FAIL", c.label.c_str(), c.detail.c_str());
    }
    if (!r.recordingPath.empty()) {
      std::printf("wrote %s and %s\n", r.recordingPath.c_str(), r.metricsPath.c_str());
    }
  }
  if (a.html) {
    const std::string page = (std::filesystem::path(a.out) / "report.html").string();
    const web::ReportStats st = web::writeReport(r.recordingPath, m, page);
    if (!a.quiet)
      std::printf("wrote %s (%.1f MB, %d of %d frames embedded; open it in a browser)\n",
                  page.c_str(), static_cast<double>(st.bytes) / 1e6, st.framesKept, st.framesIn);
  }
  std::printf("state hash %s\n", m["stateHash"].get<std::string>().c_str());
  if (!r.allPassed()) {
    std::fprintf(
        stderr, "grip: %s: %zu check(s) failed\n", sc.name.c_str(),
        static_cast<size_t>(std::count_if(r.checks.begin(), r.checks.end(),
                                          [](const scene::CheckResult& c) { return !c.passed; })));
    return 3;
  }
  return 0;
}

}  // namespace

Command addRunCommand(CLI::App& app) {
  auto* sub = app.add_subcommand("run", "run a scene file or a built-in scene headless");
  auto a = std::make_shared<RunArgs>();
  sub->add_option("scene", a->scene, "a scene file (JSON) or a built-in scene name")->required();
  sub->add_option("--out", a->out, "write recording.jsonl and metrics.json into this directory");
  sub->add_option("--method", a->method, "hand interaction method")
      ->check(CLI::IsMember({"coulomb", "kinematic"}));
  sub->add_option("--set", a->sets, "override a scene value: KEY=VALUE, e.g. world.substeps=8");
  sub->add_option("--record-every", a->recordEvery, "record every n-th step")
      ->check(CLI::Range(1, 1000000));
  sub->add_flag("--html", a->html,
                "also write report.html: the viewer with the recording (needs --out)");
  sub->add_flag("--quiet,-q", a->quiet, "print only the state hash (and errors)");
  return {sub, [a] { return runScene(*a); }};
}

}  // namespace grip::cli
