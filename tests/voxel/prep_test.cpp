// Preparation of the committed concave objects: volume accuracy per level of detail, boxes that
// tile the interior voxels exactly, bit-identical regeneration of the committed assets.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "collision/asset.hpp"
#include "voxel_test_util.hpp"

namespace grip::voxel::test {
namespace {

std::vector<uint8_t> readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

class Builtin : public ::testing::TestWithParam<std::string> {};

TEST_P(Builtin, VolumeWithinThreePercentAtHigh) {
  const AssetData a = readAssetFile(assetPath("concave/" + GetParam() + "_high.grip"));
  const double error = (a.boxVolume() - a.mass.volume) / a.mass.volume;
  EXPECT_LT(std::abs(error), 0.03) << GetParam() << ": " << 100.0 * error << " %";
}

TEST_P(Builtin, ErrorShrinksWithDetail) {
  // Not monotone step by step (voxel alignment), but very-high beats low.
  auto error = [&](const char* lod) {
    const AssetData a = readAssetFile(assetPath("concave/" + GetParam() + "_" + lod + ".grip"));
    return std::abs(a.boxVolume() - a.mass.volume) / a.mass.volume;
  };
  EXPECT_LT(error("very-high"), std::max(error("low"), 0.02));
  EXPECT_LT(error("very-high"), 0.03);
}

TEST_P(Builtin, CommittedMeshMatchesTheGenerator) {
  // The committed .off is the generator's output; loading it back gives the same volume.
  const Mesh fromFile = loadMesh(assetPath("concave/" + GetParam() + ".off"));
  const Mesh generated = repairMesh(builtinMesh(GetParam()));
  const double v1 = meshMass(fromFile.vertices, fromFile.triangles, 1.0).volume;
  const double v2 = meshMass(generated.vertices, generated.triangles, 1.0).volume;
  EXPECT_NEAR(v1, v2, 1e-6 * v2);
}

TEST_P(Builtin, RegeneratesTheCommittedAssetsBitForBit) {
  const Mesh mesh = repairMesh(builtinMesh(GetParam()));
  for (Lod lod : {Lod::Low, Lod::High}) {
    PrepOptions opt;
    opt.lod = lod;
    const auto bytes = encodeAsset(prepare(mesh, opt));
    const auto committed =
        readBytes(assetPath("concave/" + GetParam() + "_" + lodName(lod) + ".grip"));
    EXPECT_TRUE(bytes == committed) << GetParam() << " " << lodName(lod)
                                    << ": run scripts/make_assets.sh after changing the tool";
  }
}

TEST_P(Builtin, BoxesTileTheInteriorVoxelsWithoutOverlap) {
  const Mesh mesh = repairMesh(builtinMesh(GetParam()));
  PrepOptions opt;
  opt.lod = Lod::Medium;
  const AssetData a = prepare(mesh, opt);
  const DenseGrid g = signedDistanceGrid(
      mesh, a.voxelSize, opt.bandVoxels,
      static_cast<int>(std::ceil(opt.bandVoxels)) + 1 + SignedDistanceField::kBrick);
  std::vector<int> cover(g.values.size(), 0);
  for (const auto& b : a.boxes)
    for (int k = b.lo[2]; k < b.hi[2]; ++k)
      for (int j = b.lo[1]; j < b.hi[1]; ++j)
        for (int i = b.lo[0]; i < b.hi[0]; ++i)
          ++cover[static_cast<size_t>(i + g.size[0] * (j + g.size[1] * k))];
  for (size_t i = 0; i < g.values.size(); ++i)
    ASSERT_EQ(cover[i], g.values[i] < 0.0f ? 1 : 0) << "voxel " << i;
  // Merging pays: far fewer boxes than voxels.
  size_t voxels = 0;
  for (float v : g.values) voxels += v < 0.0f;
  EXPECT_LT(a.boxes.size() * 5, voxels);
}

INSTANTIATE_TEST_SUITE_P(Concave, Builtin,
                         ::testing::Values("mug", "axe", "torus", "l-block", "figurine"),
                         [](const auto& param) {
                           std::string s = param.param;
                           for (char& c : s)
                             if (c == '-') c = '_';
                           return s;
                         });

TEST(Prep, MassPropertiesAreExact) {
  // A torus: V = 2 pi^2 R r^2 (the tessellated mesh is slightly smaller, within 0.1 %).
  Torus t;
  const Mesh mesh = repairMesh(t.mesh(256, 128));
  PrepOptions opt;
  opt.lod = Lod::Low;
  opt.density = 500.0;
  const AssetData a = prepare(mesh, opt);
  const double v = 2.0 * kPi * kPi * t.R * t.r * t.r;
  EXPECT_NEAR(a.mass.volume, v, 1e-3 * v);
  EXPECT_NEAR(a.mass.mass, 500.0 * a.mass.volume, 1e-12);
  EXPECT_LT(a.mass.com.norm(), 1e-9);
  // Inertia about Y: m (R^2 + 3/4 r^2); about X and Z: m (R^2/2 + 5/8 r^2).
  const double m = a.mass.mass;
  EXPECT_NEAR(a.mass.inertia(1, 1), m * (t.R * t.R + 0.75 * t.r * t.r),
              2e-3 * a.mass.inertia(1, 1));
  EXPECT_NEAR(a.mass.inertia(0, 0), m * (0.5 * t.R * t.R + 0.625 * t.r * t.r),
              2e-3 * a.mass.inertia(0, 0));
}

TEST(Prep, CgalDemoMeshesAtEveryLod) {
  if (!haveCgalData()) GTEST_SKIP() << "libcgal-demo not installed";
  for (const char* name : {"elephant.off", "knot.off", "anchor.off", "bunny00.off", "dino.off",
                           "homer.off", "sphere.stl", "sphere.ply"}) {
    const std::string path = cgalMesh(name);
    ASSERT_FALSE(path.empty()) << name;
    const Mesh mesh = loadMesh(path);
    for (Lod lod : {Lod::Low, Lod::Medium, Lod::High, Lod::VeryHigh}) {
      PrepStats st;
      PrepOptions opt;
      opt.lod = lod;
      const AssetData a = prepare(mesh, opt, &st);
      EXPECT_NO_THROW(decodeAsset(encodeAsset(a)));
      if (lod == Lod::High || lod == Lod::VeryHigh) {
        EXPECT_LT(std::abs(st.volumeError()), 0.03) << name << " " << lodName(lod);
      }
    }
  }
}

}  // namespace
}  // namespace grip::voxel::test
