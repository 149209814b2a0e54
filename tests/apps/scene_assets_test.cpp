// Concave bodies in scene files: prepared assets load with their exact mass, relative paths are
// taken from the scene file's folder, and missing, corrupted or truncated assets (and meshes
// without the voxel module) are refused with the JSON path and the problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scene/scene.hpp"

namespace grip::scene {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

json axeScene(const std::string& path) {
  json doc = json::parse(R"({"grip_scene": 1, "duration": 1.5, "bodies": [
    {"name": "floor", "type": "static", "shape": {"type": "plane"}},
    {"name": "axe", "shape": {"type": "asset"}, "position": [0, 0.05, 0],
     "orientation": {"axis": [1, 0, 0], "degrees": 90}}]})");
  doc["bodies"][1]["shape"]["path"] = path;
  return doc;
}

std::string errorOf(const json& doc, const std::string& base = builtinBaseDir()) {
  try {
    parseScene(doc, base);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("grip_scene_assets_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const char* kAxe = "assets/concave/axe_high.grip";

TEST(SceneAssets, AnAssetBodyHasTheExactMassOfItsMesh) {
  const Scene s = parseScene(axeScene(kAxe));
  const BodySpec& b = s.bodies[1];
  ASSERT_EQ(b.def.shape->type(), ShapeType::Compound);
  EXPECT_NE(b.def.shape->sdf(), nullptr);
  const LoadedAsset a = loadAsset(builtinBaseDir() + "/" + kAxe);
  EXPECT_DOUBLE_EQ(b.def.mass, a.mass.mass);
  EXPECT_EQ(b.asset, fs::path(builtinBaseDir() + "/" + kAxe).lexically_normal().string());
  // A density scales the exact volume; a mass is taken as given.
  json doc = axeScene(kAxe);
  doc["bodies"][1]["density"] = 700;
  EXPECT_DOUBLE_EQ(parseScene(doc).bodies[1].def.mass, a.mass.volume * 700.0);
  doc["bodies"][1].erase("density");
  doc["bodies"][1]["mass"] = 0.9;
  EXPECT_DOUBLE_EQ(parseScene(doc).bodies[1].def.mass, 0.9);
}

TEST(SceneAssets, TheAxeFallsFlatAndRestsOnTheFloor) {
  const Scene s = parseScene(axeScene(kAxe));
  const RunResult r = run(s);
  const json& axe = r.metrics["bodies"][1];
  // Lying on its side: the head (4 cm thick at the back) on the floor.
  EXPECT_LT(axe["position"][1].get<double>(), 0.03);
  EXPECT_GT(axe["position"][1].get<double>(), 0.0);
  const Vec3 v(axe["linearVelocity"][0].get<double>(), axe["linearVelocity"][1].get<double>(),
               axe["linearVelocity"][2].get<double>());
  EXPECT_LT(v.norm(), 0.01);
}

TEST(SceneAssets, RelativePathsAreTakenFromTheSceneFilesFolder) {
  const fs::path dir = scratch("rel");
  fs::create_directories(dir / "objects");
  fs::copy_file(builtinBaseDir() + "/" + kAxe, dir / "objects" / "axe.grip");
  { std::ofstream(dir / "scene.json") << axeScene("objects/axe.grip").dump(); }
  const Scene s = parseScene(readSceneFile((dir / "scene.json").string()), dir.string());
  EXPECT_EQ(s.bodies[1].asset, (dir / "objects" / "axe.grip").string());
  EXPECT_EQ(errorOf(axeScene("objects/axe.grip")).find("no such asset file") != std::string::npos,
            true);
  fs::remove_all(dir);
}

TEST(SceneAssets, BadAssetsAreRefusedWithThePathAndTheProblem) {
  const fs::path dir = scratch("bad");
  std::ifstream in(builtinBaseDir() + "/" + kAxe, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string corrupt = bytes;
  corrupt[bytes.size() / 2] = static_cast<char>(corrupt[bytes.size() / 2] ^ 0x5a);
  { std::ofstream(dir / "corrupt.grip", std::ios::binary) << corrupt; }
  { std::ofstream(dir / "short.grip", std::ios::binary) << bytes.substr(0, bytes.size() - 100); }
  { std::ofstream(dir / "text.grip") << "not an asset"; }
  const std::string base = dir.string();
  EXPECT_EQ(errorOf(axeScene("missing.grip"), base),
            "bodies[1].shape.path: " + base + "/missing.grip: no such asset file");
  EXPECT_NE(errorOf(axeScene("corrupt.grip"), base).find("bodies[1].shape.path: "),
            std::string::npos);
  EXPECT_NE(errorOf(axeScene("corrupt.grip"), base).find("checksum"), std::string::npos)
      << errorOf(axeScene("corrupt.grip"), base);
  EXPECT_NE(errorOf(axeScene("short.grip"), base).find("truncated"), std::string::npos)
      << errorOf(axeScene("short.grip"), base);
  EXPECT_NE(errorOf(axeScene("text.grip"), base).find("bodies[1].shape.path: "), std::string::npos);
  EXPECT_EQ(errorOf(axeScene("."), base),
            "bodies[1].shape.path: " + base + ": is a directory, not an asset file");
  json doc = axeScene(kAxe);
  doc["bodies"][1]["shape"]["lod"] = "high";
  EXPECT_EQ(errorOf(doc), "bodies[1].shape.lod: unknown field");
  doc["bodies"][1]["shape"].erase("lod");
  doc["bodies"][1]["shape"].erase("path");
  EXPECT_EQ(errorOf(doc), "bodies[1].shape.path: is required");
  fs::remove_all(dir);
}

TEST(SceneAssets, AMeshShapeNeedsTheVoxelModule) {
  json doc = axeScene("assets/concave/axe.off");
  doc["bodies"][1]["shape"]["type"] = "mesh";
  doc["bodies"][1]["shape"]["lod"] = "low";
  if (haveVoxelModule()) {
    // Prepared on demand into a fresh cache, then found there.
    const fs::path cache = scratch("cache");
    setenv("GRIP_CACHE_DIR", cache.c_str(), 1);
    const Scene a = parseScene(doc);
    ASSERT_TRUE(fs::exists(a.bodies[1].asset)) << a.bodies[1].asset;
    EXPECT_EQ(fs::path(a.bodies[1].asset).parent_path(), cache);
    const auto written = fs::last_write_time(a.bodies[1].asset);
    const Scene b = parseScene(doc);
    EXPECT_EQ(b.bodies[1].asset, a.bodies[1].asset);
    EXPECT_EQ(fs::last_write_time(b.bodies[1].asset), written);  // a cache hit
    // The same mesh as the committed low asset (axe.off keeps 9 digits of its vertices).
    const double committed = loadAsset(builtinBaseDir() + "/assets/concave/axe_low.grip").mass.mass;
    EXPECT_NEAR(a.bodies[1].def.mass / committed, 1.0, 1e-6);
    doc["bodies"][1]["shape"]["lod"] = "ultra";
    EXPECT_EQ(errorOf(doc),
              "bodies[1].shape.lod: must be one of low, medium, high, very-high (got \"ultra\")");
    doc["bodies"][1]["shape"]["lod"] = "low";
    doc["bodies"][1]["shape"]["path"] = "assets/concave/none.off";
    EXPECT_EQ(errorOf(doc), "bodies[1].shape.path: " + builtinBaseDir() +
                                "/assets/concave/none.off: no such file");
    unsetenv("GRIP_CACHE_DIR");
    fs::remove_all(cache);
  } else {
    EXPECT_NE(errorOf(doc).find("bodies[1].shape.path: "), std::string::npos) << errorOf(doc);
    EXPECT_NE(errorOf(doc).find("needs grip built with the voxel module"), std::string::npos)
        << errorOf(doc);
  }
}

}  // namespace
}  // namespace grip::scene
