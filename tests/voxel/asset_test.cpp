// The runtime asset format: round trip, determinism, and refusal of damaged files.
#include <gtest/gtest.h>

#include <fstream>

#include "collision/asset.hpp"
#include "voxel_test_util.hpp"

namespace grip::voxel::test {
namespace {

std::vector<uint8_t> smallAsset() {
  PrepOptions opt;
  opt.lod = Lod::Low;
  return encodeAsset(prepare(repairMesh(builtinMesh("l-block")), opt));
}

std::string message(const std::vector<uint8_t>& bytes) {
  try {
    decodeAsset(bytes);
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Asset, RoundTripsBitForBit) {
  const auto bytes = smallAsset();
  const AssetData a = decodeAsset(bytes);
  EXPECT_EQ(encodeAsset(a), bytes);
  EXPECT_EQ(a.boxes.size(), 3u);  // an L of two boxes, the overlap split off: three
  EXPECT_NEAR(a.mass.volume, 0.1 * 0.03 * 0.05 + 0.03 * 0.07 * 0.05, 1e-12);
}

TEST(Asset, PreparationIsDeterministic) {
  EXPECT_EQ(smallAsset(), smallAsset());
}

TEST(Asset, RefusesCorruptionTruncationAndOtherVersions) {
  const auto good = smallAsset();
  auto flipped = good;
  flipped[flipped.size() / 2] ^= 0x10;
  EXPECT_NE(message(flipped).find("checksum mismatch"), std::string::npos);

  auto truncated = good;
  truncated.resize(good.size() - 100);
  EXPECT_NE(message(truncated).find("truncated"), std::string::npos);
  EXPECT_NE(message({good.begin(), good.begin() + 20}).find("bad magic"), std::string::npos);

  auto version = good;
  version[8] = 2;  // the version field follows the 8-byte magic
  EXPECT_NE(message(version).find("version 2 is not supported"), std::string::npos);

  auto magic = good;
  magic[0] = 'X';
  EXPECT_NE(message(magic).find("not a grip asset"), std::string::npos);
  EXPECT_NE(message({}).find("not a grip asset"), std::string::npos);
}

TEST(Asset, RefusesConsistentlyChecksummedNonsense) {
  // A payload that passes the checksum but describes an impossible asset is still refused.
  AssetData a = decodeAsset(smallAsset());
  a.boxes[0].hi[0] = a.boxes[0].lo[0];
  EXPECT_NE(message(encodeAsset(a)).find("empty or inverted"), std::string::npos);
  a = decodeAsset(smallAsset());
  a.sdf.bricks[0] = 1 << 20;
  EXPECT_NE(message(encodeAsset(a)).find("invalid distance field"), std::string::npos);
  a = decodeAsset(smallAsset());
  a.mass.mass = -1.0;
  EXPECT_NE(message(encodeAsset(a)).find("must be positive"), std::string::npos);
}

TEST(Asset, FileErrorsNameTheFile) {
  try {
    readAssetFile("/nonexistent/x.grip");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.grip"), std::string::npos);
  }
}

}  // namespace
}  // namespace grip::voxel::test
