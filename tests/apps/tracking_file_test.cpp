// Hands from recorded tracking files (OpenXR joints or Leap Motion bones): the committed example
// drives a flat hand that lifts a box like the keyframed flat_lift scene, both forms give the
// bones they encode, and bad files are refused naming the file and the JSON path.
//
// GRIP_WRITE_EXAMPLES=1 rewrites assets/tracking/flat_lift_openxr.json from flat_lift's script.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "scene/scene.hpp"

namespace grip::scene {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

double round(double x, double unit) {
  return std::round(x / unit) * unit;
}

// [x, y, z, qw, qx, qy, qz], positions to 0.01 mm, quaternions to 1e-6.
json joint(const Vec3& p, const Quat& q) {
  return {round(p.x(), 1e-5), round(p.y(), 1e-5), round(p.z(), 1e-5), round(q.w(), 1e-6),
          round(q.x(), 1e-6), round(q.y(), 1e-6), round(q.z(), 1e-6)};
}

// The 26 OpenXR joints of a pose: each finger bone spans two joints; a joint's -Z runs toward
// the tip and +Y out of the back of the hand (the bone frame's +Z).
json openXRJoints(const HandDef& def, const HandPose& pose) {
  const HandShapes shapes = makeHandShapes(def);
  const Transform& palm = pose.bones[kPalmBone];
  std::vector<json> j(kXrJointCount, joint(palm.p, palm.q));
  j[1] = joint(palm.apply(Vec3(0, 0, def.scale * def.palmHalfExtents.z())), palm.q);
  const int chains[5][4] = {
      {2, 3, 4, 5}, {7, 8, 9, 10}, {12, 13, 14, 15}, {17, 18, 19, 20}, {22, 23, 24, 25}};
  for (int f = 0; f < 5; ++f) {
    for (int seg = 0; seg < 3; ++seg) {
      const int b = boneIndex(Finger(f), seg);
      const Transform& t = pose.bones[b];
      const Mat3 r = t.q.toRotationMatrix();
      Mat3 m;
      m.col(0) = r.col(0), m.col(1) = r.col(2), m.col(2) = -r.col(1);
      const Quat q(m);
      const Vec3 y = r.col(1) * shapes.halfLength[b];
      j[static_cast<size_t>(chains[f][seg])] = joint(t.p - y, q);
      if (seg == 2) j[static_cast<size_t>(chains[f][3])] = joint(t.p + y, q);
    }
  }
  return json(j);
}

std::string sourceDir() {
  const char* s = std::getenv("GRIP_SOURCE_DIR");
  return s ? s : builtinBaseDir();
}

// flat_lift's hand, sampled at 10 Hz.
json flatLiftRecording() {
  const Scene s = parseScene(*builtinScene("flat_lift"));
  const HandSpec& h = s.hands[0];
  ScriptedHandDef d;
  d.hand = h.def;
  for (const KeySpec& k : h.keys) d.keys.push_back({k.time, *k.palm, k.pose, std::nullopt});
  const ScriptedHand hand(d);
  json frames = json::array();
  for (int i = 0; i <= 25; ++i) {
    const double t = 0.1 * i;
    frames.push_back({{"time", round(t, 1e-9)}, {"joints", openXRJoints(h.def, hand.sample(t))}});
  }
  return {{"format", "grip-tracking"}, {"version", 1}, {"source", "openxr"}, {"frames", frames}};
}

TEST(TrackingFile, TheCommittedExampleIsFlatLiftsHandAt10Hz) {
  const std::string path = sourceDir() + "/assets/tracking/flat_lift_openxr.json";
  const json expected = flatLiftRecording();
  if (std::getenv("GRIP_WRITE_EXAMPLES")) std::ofstream(path) << expected.dump() << "\n";
  const json committed = readJsonFile(path, "tracking file");
  ASSERT_EQ(committed["frames"].size(), expected["frames"].size());
  for (size_t i = 0; i < committed["frames"].size(); ++i) {
    const json& a = committed["frames"][i]["joints"];
    const json& b = expected["frames"][i]["joints"];
    for (size_t k = 0; k < 26; ++k)
      for (size_t c = 0; c < 7; ++c)
        EXPECT_NEAR(a[k][c].get<double>(), b[k][c].get<double>(), 1e-9) << i << " " << k;
  }
}

TEST(TrackingFile, TheRecordedHandLiftsTheBoxLikeTheScript) {
  const std::string path = sourceDir() + "/docs/example_tracked_scene.json";
  const Scene s = parseScene(readSceneFile(path), fs::path(path).parent_path().string());
  ASSERT_EQ(s.hands.size(), 1u);
  EXPECT_EQ(s.hands[0].tracked.size(), 26u);
  const RunResult r = run(s);
  ASSERT_EQ(r.checks.size(), 3u);
  for (const CheckResult& c : r.checks) EXPECT_TRUE(c.passed) << c.label << ": " << c.detail;
  EXPECT_EQ(run(s).stateHash, r.stateHash);
}

TEST(TrackingFile, OpenXRJointsGiveTheBonesTheyEncode) {
  const Scene s = parseScene(*builtinScene("flat_lift"));
  const HandDef def;
  const HandPose pose = poseHand(def, s.hands[0].keys[3].palm.value(), handShape(GraspPose::Power));
  json doc = {{"format", "grip-tracking"},
              {"version", 1},
              {"source", "openxr"},
              {"frames", {{{"time", 0.0}, {"joints", openXRJoints(def, pose)}}}}};
  const auto frames = parseTracking(doc);
  ASSERT_EQ(frames.size(), 1u);
  ASSERT_TRUE(frames[0].second.tracked);
  for (int b = 0; b < kBonesPerHand; ++b) {
    EXPECT_LT((frames[0].second.bones[b].p - pose.bones[b].p).norm(), 2e-5) << boneName(b);
    EXPECT_LT(frames[0].second.bones[b].q.angularDistance(pose.bones[b].q), 1e-3) << boneName(b);
  }
}

// A Leap hand in desktop mode (mm, device frame = world frame scaled).
json leapFrame(double t, const HandDef& def, const HandPose& pose) {
  const HandShapes shapes = makeHandShapes(def);
  auto mm = [](const Vec3& p) { return json{1000 * p.x(), 1000 * p.y(), 1000 * p.z()}; };
  const Transform& palm = pose.bones[kPalmBone];
  json digits = json::array();
  for (int f = 0; f < 5; ++f) {
    const Transform& first = pose.bones[boneIndex(Finger(f), 0)];
    const Vec3 base = first.p - first.rotate(Vec3::UnitY()) * shapes.halfLength[1 + 3 * f];
    json bones = json::array({json::array({mm(palm.p), mm(base)})});
    for (int seg = 0; seg < 3; ++seg) {
      const int b = boneIndex(Finger(f), seg);
      const Vec3 y = pose.bones[b].rotate(Vec3::UnitY()) * shapes.halfLength[b];
      bones.push_back(json::array({mm(pose.bones[b].p - y), mm(pose.bones[b].p + y)}));
    }
    digits.push_back(bones);
  }
  const Vec3 n = -palm.rotate(Vec3::UnitY()), d = -palm.rotate(Vec3::UnitZ());
  return {{"time", t},
          {"palm",
           {{"position", mm(palm.p)},
            {"normal", {n.x(), n.y(), n.z()}},
            {"direction", {d.x(), d.y(), d.z()}}}},
          {"digits", digits}};
}

TEST(TrackingFile, LeapBonesInMillimetresGiveTheSameHand) {
  const HandDef def;
  Transform palm;
  palm.p = Vec3(0.05, 0.3, -0.02);
  palm.q = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  const HandPose pose = poseHand(def, palm, handShape(GraspPose::Pinch));
  json doc = {{"format", "grip-tracking"},
              {"version", 1},
              {"source", "leap"},
              {"leap", {{"mount", "desktop"}}},
              {"frames", {leapFrame(0.0, def, pose), {{"time", 0.1}, {"tracked", false}}}}};
  const auto frames = parseTracking(doc);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_FALSE(frames[1].second.tracked);
  for (int b = 0; b < kBonesPerHand; ++b) {
    EXPECT_LT((frames[0].second.bones[b].p - pose.bones[b].p).norm(), 1e-9) << boneName(b);
  }
  // On a Rift DK2 mount the same data lands elsewhere (device frame -> headset frame).
  doc["leap"]["mount"] = "rift-dk2";
  const Vec3 p = parseTracking(doc)[0].second.bones[kPalmBone].p;
  EXPECT_NEAR(p.x(), -palm.p.x(), 1e-12);
  EXPECT_NEAR(p.y(), -palm.p.z(), 1e-12);
  EXPECT_NEAR(p.z(), -palm.p.y() - 0.08, 1e-12);
}

std::string errorOf(const json& trackingDoc) {
  const fs::path dir = fs::temp_directory_path() / "grip_tracking_test";
  fs::create_directories(dir);
  std::ofstream(dir / "t.json") << trackingDoc.dump();
  json scene = json::parse(R"({"grip_scene": 1, "duration": 0.1, "bodies": [],
                               "hands": [{"tracking": "t.json"}]})");
  try {
    parseScene(scene, dir.string());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(TrackingFile, BadFilesAreRefusedNamingTheFileAndThePath) {
  const std::string f = (fs::temp_directory_path() / "grip_tracking_test" / "t.json").string();
  const std::string at = "hands[0].tracking: " + f + ": ";
  json good = {{"format", "grip-tracking"},
               {"version", 1},
               {"source", "openxr"},
               {"frames", {{{"time", 0.0}, {"active", false}}}}};
  EXPECT_EQ(errorOf(good), "");
  json bad = good;
  bad["source"] = "kinect";
  EXPECT_EQ(errorOf(bad), at + "source: must be one of openxr, leap (got \"kinect\")");
  bad = good;
  bad["format"] = "bvh";
  EXPECT_EQ(errorOf(bad), at + "format: must be \"grip-tracking\" (got \"bvh\")");
  bad = good;
  bad["version"] = 2;
  EXPECT_EQ(errorOf(bad), at + "version: unsupported version 2 (this grip reads 1)");
  bad = good;
  bad["frames"][0] = {{"time", 0.0}, {"joints", json::array({1, 2})}};
  EXPECT_NE(errorOf(bad).find(at + "frames[0].joints: must be an array of the 26"),
            std::string::npos)
      << errorOf(bad);
  bad = good;
  bad["frames"].push_back({{"time", 0.0}, {"active", false}});
  EXPECT_EQ(errorOf(bad), at + "frames[1].time: must be later than the frame before");
  bad = good;
  bad["frames"] = json::array();
  EXPECT_EQ(errorOf(bad), at + "frames: must be a non-empty array");
  bad = good;
  bad["leap"] = {{"mount", "desktop"}};
  EXPECT_EQ(errorOf(bad), at + "leap: applies to \"source\": \"leap\" only");

  const fs::path dir = fs::temp_directory_path() / "grip_tracking_test";
  std::ofstream(dir / "t.json") << "{\"format\": ";
  json scene = json::parse(R"({"grip_scene": 1, "duration": 0.1, "bodies": [],
                               "hands": [{"tracking": "t.json"}]})");
  try {
    parseScene(scene, dir.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(at + "invalid JSON"), std::string::npos) << e.what();
  }
  scene["hands"][0]["tracking"] = "none.json";
  try {
    parseScene(scene, dir.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "hands[0].tracking: " + (dir / "none.json").string() + ": no such tracking file");
  }
  scene["hands"][0]["keyframes"] = json::array();
  try {
    parseScene(scene, dir.string());
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "hands[0].tracking: give either keyframes or tracking, not both");
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace grip::scene
