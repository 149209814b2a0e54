// Running scenes: every built-in scene passes its own check, runs are bit-for-bit repeatable,
// and the recording is complete, parseable and never left looking complete on failure.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "scene/scene.hpp"

namespace grip::scene {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("grip_scene_test_" + name);
  fs::remove_all(d);
  return d;
}

// Runs the scene writing its recording and metrics into dir.
RunResult runRecorded(const Scene& s, const fs::path& dir) {
  RunOptions opt;
  opt.outDir = dir.string();
  return run(s, opt);
}

// The recording's lines, parsed.
std::vector<json> recordingLines(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<json> lines;
  while (std::getline(in, line)) lines.push_back(json::parse(line));
  return lines;
}

class BuiltinSceneTest : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinSceneTest, PassesItsCheck) {
  const Scene s = parseScene(*builtinScene(GetParam()));
  const RunResult r = run(s);
  ASSERT_FALSE(r.checks.empty());
  for (const CheckResult& c : r.checks) EXPECT_TRUE(c.passed) << c.label << ": " << c.detail;
}

// The bar of issue 5: `grip run` twice gives the same hash, for every built-in scene.
TEST_P(BuiltinSceneTest, RunsTwiceToTheSameHash) {
  const Scene s = parseScene(*builtinScene(GetParam()));
  const uint64_t a = run(s).stateHash;
  EXPECT_EQ(run(parseScene(*builtinScene(GetParam()))).stateHash, a);
  EXPECT_NE(a, 0u);
}

std::vector<std::string> builtinNames() {
  std::vector<std::string> names;
  for (const BuiltinScene& b : builtinScenes()) names.push_back(b.name);
  return names;
}
INSTANTIATE_TEST_SUITE_P(Builtin, BuiltinSceneTest, ::testing::ValuesIn(builtinNames()),
                         [](const auto& p) { return p.param; });

TEST(SceneRun, TheSameSceneTwiceGivesTheSameHash) {
  const Scene s = parseScene(*builtinScene("handover"));
  const uint64_t a = run(s).stateHash, b = run(s).stateHash;
  EXPECT_EQ(a, b);
  // ...and a different scene state gives a different one.
  json doc = *builtinScene("handover");
  applyOverride(doc, "bodies[0].mass=0.11");
  EXPECT_NE(run(parseScene(doc)).stateHash, a);
}

TEST(SceneRun, TrackingNoiseIsSeeded) {
  json doc = *builtinScene("flat_lift");
  applyOverride(doc, "hands[0].positionNoise=0.001");
  const uint64_t a = run(parseScene(doc)).stateHash, b = run(parseScene(doc)).stateHash;
  EXPECT_EQ(a, b);
  applyOverride(doc, "seed=2");
  EXPECT_NE(run(parseScene(doc)).stateHash, a);
}

TEST(SceneRun, TheRecordingIsCompleteAndParseable) {
  const fs::path dir = freshDir("rec");
  const Scene s = parseScene(*builtinScene("grasp_lift"));
  const RunResult r = runRecorded(s, dir);
  ASSERT_EQ(r.recordingPath, (dir / "recording.jsonl").string());
  EXPECT_FALSE(fs::exists(dir / "recording.jsonl.partial"));
  const std::vector<json> lines = recordingLines(r.recordingPath);
  ASSERT_EQ(lines.size(), static_cast<size_t>(s.steps()) + 2);
  const json& header = lines.front();
  EXPECT_TRUE(header["joints"].empty());
  EXPECT_EQ(header["format"], "grip-recording");
  EXPECT_EQ(header["bodies"].size(), 2u);
  EXPECT_EQ(header["hands"][0]["bones"].size(), 16u);
  int sticking = 0;
  for (size_t i = 1; i + 1 < lines.size(); ++i) {
    const json& f = lines[i];
    EXPECT_EQ(f["frame"], static_cast<int>(i));
    EXPECT_EQ(f["bodies"].size(), 2u);
    EXPECT_EQ(f["bodies"][1].size(), 7u);
    EXPECT_EQ(f["hands"][0]["bones"].size(), 16u);
    EXPECT_EQ(f["hands"][0]["visual"].size(), 16u);
    for (const json& c : f["contacts"]) {
      EXPECT_EQ(c["point"].size(), 3u);
      EXPECT_EQ(c["force"].size(), 3u);
      if (c["state"] == "stick") ++sticking;
    }
  }
  EXPECT_GT(sticking, 100);  // the pinch holds the cube most of the run
  // The last recorded frame is the final state.
  const json& last = lines[lines.size() - 2]["bodies"][1];
  EXPECT_DOUBLE_EQ(last[1].get<double>(), r.metrics["bodies"][1]["position"][1].get<double>());
  EXPECT_EQ(lines.back()["end"], true);
  EXPECT_EQ(lines.back()["stateHash"], r.metrics["stateHash"]);

  std::ifstream mf(dir / "metrics.json");
  const json m = json::parse(mf);
  EXPECT_EQ(m["stateHash"], r.metrics["stateHash"]);
  EXPECT_EQ(m["passed"], true);
  EXPECT_GT(m["hands"]["maxPenetrationTracked"].get<double>(), 0.0);
  EXPECT_LT(m["hands"]["maxPenetrationTracked"].get<double>(), 0.01);
  for (const char* k : {"hands", "interaction", "step", "record"})
    EXPECT_TRUE(m["timings"].contains(k));
  fs::remove_all(dir);
}

// The recording's header gives each joint's anchors in its bodies' frames: placed by the bodies'
// recorded poses they meet in every frame (open_door's hinge, within the joint's give).
TEST(SceneRun, TheRecordingPlacesEachJointsAnchors) {
  const fs::path dir = freshDir("rec_joints");
  const Scene s = parseScene(*builtinScene("open_door"));
  const std::vector<json> lines = recordingLines(runRecorded(s, dir).recordingPath);
  const json& header = lines.front();
  ASSERT_EQ(header["joints"].size(), s.joints.size());
  ASSERT_FALSE(s.joints.empty());
  auto vec = [](const json& v, size_t k) {
    return Vec3(v[k].get<double>(), v[k + 1].get<double>(), v[k + 2].get<double>());
  };
  auto at = [&](const json& pose, const json& local) {
    const Transform t{vec(pose, 0), Quat(pose[3].get<double>(), pose[4].get<double>(),
                                         pose[5].get<double>(), pose[6].get<double>())};
    return t.apply(vec(local, 0));
  };
  double widest = 0.0;
  int frames = 0;
  for (const json& f : lines) {
    if (!f.contains("frame")) continue;  // the header, the end line
    ++frames;
    for (const json& j : header["joints"]) {
      const Vec3 a = at(f["bodies"][j["a"].get<size_t>()], j["anchorA"]);
      const Vec3 b = at(f["bodies"][j["b"].get<size_t>()], j["anchorB"]);
      widest = std::max(widest, (a - b).norm());
    }
  }
  EXPECT_EQ(frames, s.steps());
  EXPECT_LT(widest, 2e-3);
  EXPECT_EQ(header["joints"][0]["type"], "hinge");
  fs::remove_all(dir);
}

TEST(SceneRun, RecordEveryThinsTheFrames) {
  const fs::path dir = freshDir("thin");
  json doc = *builtinScene("push_box");
  RunOptions opt;
  opt.outDir = dir.string();
  opt.recordEvery = 10;
  const Scene s = parseScene(doc);
  run(s, opt);
  std::ifstream in(dir / "recording.jsonl");
  std::string line;
  int n = 0;
  while (std::getline(in, line)) ++n;
  EXPECT_EQ(n, (s.steps() + 9) / 10 + 2);
  fs::remove_all(dir);
}

// A joint that breaks is in the metrics: the scene's second joint (a 2 kg ball on a rope that
// bears 1.5 times 1 kg's weight) breaks in the first step, holding the ball's weight; the first
// (1 kg on the same rope) never does.
TEST(SceneRun, BrokenJointsAreInTheMetrics) {
  const json doc = json::parse(R"({
    "grip_scene": 1, "name": "ropes", "duration": 0.5,
    "bodies": [
      {"name": "hook", "type": "static", "shape": {"type": "box", "halfExtents": [0.05, 0.05, 0.05]},
       "position": [0, 2, 0]},
      {"name": "light", "shape": {"type": "sphere", "radius": 0.05}, "position": [0, 1, 0], "mass": 1},
      {"name": "heavy", "shape": {"type": "sphere", "radius": 0.05}, "position": [1, 1, 0], "mass": 2}
    ],
    "joints": [
      {"type": "distance", "a": "hook", "b": "light", "anchor": [0, 2, 0], "anchorB": [0, 1, 0],
       "limit": [-1, 0], "breakForce": 14.7},
      {"type": "distance", "a": "hook", "b": "heavy", "anchor": [1, 2, 0], "anchorB": [1, 1, 0],
       "limit": [-1, 0], "breakForce": 14.7}
    ]})");
  const RunResult r = run(parseScene(doc));
  const json& breaks = r.metrics["jointBreaks"];
  ASSERT_EQ(breaks.size(), 1u);
  EXPECT_EQ(breaks[0]["joint"].get<int>(), 1);
  EXPECT_NEAR(breaks[0]["time"].get<double>(), 1.0 / 60.0, 1e-12);
  EXPECT_NEAR(breaks[0]["force"].get<double>(), 2.0 * 9.81, 0.01 * 2.0 * 9.81);
}

// Found by fuzz/fuzz_scene.cpp: a scene shortened after parsing, with a check measured from a
// time the run no longer reaches, read reference states that were never taken.
TEST(SceneRun, ACheckFromATimeTheRunNeverReachesIsRefused) {
  Scene s = parseScene(*builtinScene("push_box"));
  ASSERT_FALSE(s.checks.empty());
  s.checks.back().since = 0.5;
  s.duration = 0.25;
  try {
    run(s);
    FAIL() << "run() accepted a check from after the end";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "checks[" + std::to_string(s.checks.size() - 1) +
                                         "].since: must be before the end of the run (duration)");
  }
}

TEST(SceneRun, AnUnwritableOutputDirectoryIsRefusedAndLeavesNothing) {
  const fs::path dir = freshDir("ro");
  fs::create_directories(dir);
  { std::ofstream(dir / "file") << "x"; }
  RunOptions opt;
  opt.outDir = (dir / "file" / "sub").string();  // below a regular file
  const Scene s = parseScene(*builtinScene("grasp_lift"));
  EXPECT_THROW(run(s, opt), Error);
  fs::remove_all(dir);
}

TEST(SceneRun, ADiskThatFillsLeavesNoCompleteLookingRecording) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  // A directory whose recording.jsonl.partial is /dev/full: writes fail with ENOSPC.
  const fs::path dir = freshDir("full");
  fs::create_directories(dir);
  fs::create_symlink("/dev/full", dir / "recording.jsonl.partial");
  RunOptions opt;
  opt.outDir = dir.string();
  const Scene s = parseScene(*builtinScene("grasp_lift"));
  try {
    run(s, opt);
    FAIL() << "expected a write error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("write failed"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "recording.jsonl"));
  EXPECT_FALSE(fs::exists(dir / "metrics.json"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace grip::scene

namespace grip::scene {
namespace {

// docs/example_scene.json uses every field of the format once; it must parse, run and pass.
TEST(SceneRun, TheDocumentedExampleRunsAndPasses) {
  const char* src = std::getenv("GRIP_SOURCE_DIR");
  if (!src) GTEST_SKIP() << "GRIP_SOURCE_DIR not set (run through ctest)";
  const Scene s = parseScene(readSceneFile(std::string(src) + "/docs/example_scene.json"));
  EXPECT_EQ(s.hands.size(), 3u);
  const RunResult r = run(s);
  EXPECT_EQ(r.checks.size(), 7u);
  for (const CheckResult& c : r.checks) EXPECT_TRUE(c.passed) << c.label << ": " << c.detail;
}

}  // namespace
}  // namespace grip::scene
