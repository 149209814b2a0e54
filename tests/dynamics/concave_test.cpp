// Concave objects at run time: the committed voxel assets (assets/concave/, made by `grip prep`)
// load without CGAL or OpenVDB, rest on the ground, hold a ball, and answer closest-point
// queries from their signed-distance field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "collision/asset.hpp"
#include "collision/sdf.hpp"
#include "dynamics/world.hpp"

using namespace grip;

namespace {

std::string assetPath(const std::string& name) {
  if (const char* s = std::getenv("GRIP_SOURCE_DIR"))
    return std::string(s) + "/assets/concave/" + name;
  return (std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "assets" /
          "concave" / name)
      .string();
}

// The mug (voxel/detail/procedural.cpp): cup of outer radius 42 mm, inner 34 mm, 95 mm tall
// with an 8 mm floor, standing on y = 0; the handle points along +x.
constexpr double kInner = 0.034, kOuter = 0.042, kHeight = 0.095, kFloor = 0.008;

struct MugScene {
  World world;
  BodyId mug;
  explicit MugScene(const char* lod = "high") {
    BodyDef g;
    g.type = BodyType::Static;
    g.shape = Shape::plane(Vec3::UnitY(), 0.0);
    world.createBody(g);
    const LoadedAsset a = loadAsset(assetPath(std::string("mug_") + lod + ".grip"));
    BodyDef d;
    d.shape = a.shape;
    d.mass = a.mass.mass;
    d.position = Vec3(0.0, 0.005, 0.0);  // dropped from 5 mm
    d.name = "mug";
    mug = world.createBody(d);
  }
  double tiltDegrees() const {
    const Vec3 up = world.pose(mug).q * Vec3::UnitY();
    return std::acos(std::clamp(up.y(), -1.0, 1.0)) * 180.0 / kPi;
  }
};

TEST(ConcaveAsset, LoadsAsACompoundWithExactMass) {
  const LoadedAsset a = loadAsset(assetPath("mug_high.grip"));
  ASSERT_EQ(a.shape->type(), ShapeType::Compound);
  ASSERT_NE(a.shape->sdf(), nullptr);
  EXPECT_GT(a.shape->children().size(), 50u);
  // The boxes' own mass at the same density is within the voxel volume error (3 %).
  const MassProperties boxes = a.shape->massProperties(1000.0);
  EXPECT_NEAR(boxes.mass / a.mass.mass, 1.0, 0.03);
  EXPECT_LT((boxes.com - a.mass.com).norm(), 0.002);
}

TEST(ConcaveAsset, MugRestsStablyOnAPlane) {
  for (const char* lod : {"medium", "high"}) {
    MugScene s(lod);
    for (int i = 0; i < 180; ++i) s.world.step(1.0 / 60.0);
    const Transform p = s.world.pose(s.mug);
    EXPECT_LT(s.tiltDegrees(), 1.0) << lod;
    EXPECT_NEAR(p.p.y(), 0.0, 0.004) << lod;  // the voxel floor sits within a voxel of y = 0
    EXPECT_LT(Vec3(p.p.x(), 0, p.p.z()).norm(), 0.002) << lod;  // no drift
    EXPECT_LT(s.world.linearVelocity(s.mug).norm(), 0.01) << lod;
  }
}

TEST(ConcaveAsset, BallDroppedIntoTheMugStaysInside) {
  // Straight in, and thrown in at an angle so that it hits the inner wall first.
  const Vec3 starts[] = {Vec3(0.0, 0.15, 0.0), Vec3(-0.02, 0.13, 0.01)};
  const Vec3 velocities[] = {Vec3::Zero(), Vec3(0.4, 0.0, -0.1)};
  for (int k = 0; k < 2; ++k) {
    MugScene s;
    const double r = 0.012;
    BodyDef b;
    b.shape = Shape::sphere(r);
    b.position = starts[k];
    b.linearVelocity = velocities[k];
    b.material.density = 1000.0;
    const BodyId ball = s.world.createBody(b);
    for (int i = 0; i < 240; ++i) s.world.step(1.0 / 60.0);
    // In the mug's frame: within the cavity, resting on the floor.
    const Vec3 c = s.world.pose(s.mug).applyInverse(s.world.pose(ball).p);
    EXPECT_LT(std::hypot(c.x(), c.z()), kInner - r + 0.003) << "case " << k;
    EXPECT_GT(c.y(), kFloor) << "case " << k;
    EXPECT_LT(c.y(), kHeight) << "case " << k;
    EXPECT_NEAR(c.y(), kFloor + r, 0.004) << "case " << k;
    EXPECT_LT(s.tiltDegrees(), 2.0) << "case " << k;
  }
}

TEST(ConcaveAsset, ClosestPointComesFromTheDistanceField) {
  MugScene s;
  const Transform t = s.world.pose(s.mug);
  const double h = s.world.shape(s.mug).sdf()->spacing();
  // Beside the outer wall (away from the handle), inside the cavity, above the floor.
  struct Probe {
    Vec3 local;
    double distance;
    Vec3 normal;
  };
  const Probe probes[] = {
      {Vec3(-kOuter - 0.004, 0.05, 0.0), 0.004, -Vec3::UnitX()},
      {Vec3(0.0, 0.05, -kOuter + 0.002), -0.002, -Vec3::UnitZ()},
      {Vec3(0.0, 0.05, kInner - 0.005), 0.005, -Vec3::UnitZ()},
      {Vec3(0.005, kFloor + 0.006, 0.0), 0.006, Vec3::UnitY()},
  };
  for (const Probe& p : probes) {
    const SurfacePoint sp = s.world.closestPoint(s.mug, t.apply(p.local));
    EXPECT_NEAR(sp.distance, p.distance, 0.25 * h) << p.local.transpose();
    EXPECT_NEAR((sp.point - t.apply(p.local)).norm(), std::abs(p.distance), 0.25 * h);
    EXPECT_GT(sp.normal.dot(t.rotate(p.normal)), std::cos(3.0 * kPi / 180.0))
        << p.local.transpose();
  }
}

TEST(ConcaveAsset, CorruptedAssetIsRefusedOnLoad) {
  const std::string copy =
      (std::filesystem::temp_directory_path() / "grip_corrupt_mug.grip").string();
  std::filesystem::copy_file(assetPath("mug_low.grip"), copy,
                             std::filesystem::copy_options::overwrite_existing);
  {
    std::fstream f(copy, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(200);
    f.put('\x7f');
  }
  try {
    loadAsset(copy);
    FAIL() << "a corrupted asset loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("checksum mismatch"), std::string::npos) << e.what();
  }
}

}  // namespace
