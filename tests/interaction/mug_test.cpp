// A concave object through the runtime asset loader: the prepared mug (assets/concave/, made by
// `grip prep`, a compound of boxes carrying a signed-distance field) lifted by its handle.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "collision/asset.hpp"
#include "collision/sdf.hpp"
#include "interaction/interaction.hpp"
#include "interaction/scenarios.hpp"

namespace grip {
namespace {

using namespace scenarios;

constexpr double kDt = 1.0 / 60.0;

std::string mugPath() {
  if (const char* s = std::getenv("GRIP_SOURCE_DIR")) {
    return std::string(s) + "/assets/concave/mug_high.grip";
  }
  return (std::filesystem::path(__FILE__).parent_path().parent_path().parent_path() / "assets" /
          "concave" / "mug_high.grip")
      .string();
}

// The mug (voxel/detail/procedural.cpp), in its own frame: cup of outer radius 42 mm standing on
// y = 0; the handle a 4.5 mm tube in the z = 0 plane: a top bar at y = 75 mm from the wall out
// to x = 54 mm, a half circle of radius 25 mm about (54, 50) mm, a bottom bar at y = 25 mm.
constexpr double kOuter = 0.042, kTube = 0.0045;
const Vec3 kArcCentre(0.054, 0.05, 0.0);
constexpr double kArcRadius = 0.025, kTopBar = 0.075;

// The handle's outward normal at a surface point near it (analytic, from the tube's centre line).
Vec3 handleNormal(const Vec3& local) {
  Vec3 centre;
  if (local.x() <= kArcCentre.x()) {
    centre = Vec3(local.x(), local.y() > kArcCentre.y() ? kTopBar : 0.025, 0.0);
  } else {
    Vec3 d = local - kArcCentre;
    d.z() = 0.0;
    centre = kArcCentre + kArcRadius * d.normalized();
  }
  return (local - centre).normalized();
}

struct MugGrasp {
  World world;
  Interaction ix;
  HandDef hd;
  HandId hand;
  BodyId mug;
  Transform rest;  // the mug's pose on the table
  MugGrasp() {
    addFloor(world);
    const LoadedAsset a = loadAsset(mugPath());
    BodyDef d;
    d.shape = a.shape;
    d.mass = a.mass.mass;
    d.position = Vec3(0.0, 0.002, 0.0);
    d.name = "mug";
    mug = world.createBody(d);
    for (int i = 0; i < 60; ++i) world.step(kDt);  // settle on the table
    rest = world.pose(mug);
    hand = ix.addHand(hd);
  }
  // The hook grip on the handle, in the mug's rest frame, raised by `up`: the index finger through
  // the handle, under the top bar; the thumb on top of the top bar; the middle finger through the
  // handle against the cup wall (it takes the torque of the cup hanging off the handle). Each
  // bone sunk `depth` into the surface it presses, finger axes along z (through the handle).
  HandPose pose(double depth, double up) const {
    HandPose p = parkedHand(hd);
    Transform at = rest;
    at.p.y() += up;
    auto press = [&](int bone, const Vec3& point, const Vec3& normal) {
      pressBone(p, hd, bone, at.apply(point), at.rotate(normal), at.rotate(Vec3::UnitZ()), depth);
    };
    // Inside the handle's outer half circle, 45 degrees from its top: pushes up and outward.
    const Vec3 out = Vec3(std::sin(0.25 * kPi), std::cos(0.25 * kPi), 0.0);
    press(boneIndex(Finger::Index, 1), kArcCentre + (kArcRadius - kTube) * out, -out);
    // On top of the half circle, 15 degrees out from its top (clear of the cup wall).
    const Vec3 top = Vec3(std::sin(kPi / 12.0), std::cos(kPi / 12.0), 0.0);
    press(boneIndex(Finger::Thumb, 2), kArcCentre + (kArcRadius + kTube) * top, top);
    press(boneIndex(Finger::Middle, 1), Vec3(kOuter, 0.045, 0.0), Vec3::UnitX());
    press(boneIndex(Finger::Ring, 1), Vec3(kOuter, 0.011, 0.0), Vec3::UnitX());
    return p;
  }
  // Closes the grip (each bone from 2 mm outside to `depth` inside in 20 steps) while the mug
  // stands on the table.
  void close(double depth) {
    for (int i = 0; i <= 20; ++i) {
      ix.setHandPose(hand, pose(-0.002 + (depth + 0.002) * i / 20.0, 0.0));
      ix.step(world, kDt);
    }
  }
};

// Lifting the 0.22 kg mug 10 cm by the handle. The cup's centre of mass is about 6.5 cm beside
// the index finger that carries it: the grip must hold m g * 6.5 cm = 0.14 N m, with the middle
// and ring fingers pressing the wall 2 and 5.3 cm below the index, about 1.9 N each. With
// gamma = 1000 N/m (a firm grip) and 3 mm of squeeze a bone gives 3 N, and the mug comes up
// upright and stays with the hand. With the default gamma = 400 (1.2 N per bone) it cannot:
// the cup swings down around the handle.
TEST(ConcaveGrasp, TheMugIsLiftedByItsHandle) {
  for (double gamma : {1000.0, 400.0}) {
    MugGrasp s;
    s.ix.setBodyOverrides(s.mug, {.gamma = gamma});
    const double depth = 0.003, lift = 0.1;
    s.close(depth);
    EXPECT_EQ(s.ix.stats().pressingContacts, 4) << gamma;
    const int rise = 90;
    Transform relHeld;
    double drift = 0.0;
    for (int i = 1; i <= rise + 60; ++i) {  // up 10 cm in 1.5 s, then hold for 1 s
      const double t = std::min(1.0, double(i) / rise);
      const double up = lift * t * t * (3.0 - 2.0 * t);
      s.ix.setHandPose(s.hand, s.pose(depth, up));
      s.ix.step(s.world, kDt);
      Transform hand = s.rest;  // the frame the fingers move with
      hand.p.y() += up;
      const Transform rel = hand.inverse() * s.world.pose(s.mug);
      if (i == rise) relHeld = rel;
      if (i > rise) drift = std::max(drift, (rel.p - relHeld.p).norm());
    }
    const Transform now = s.world.pose(s.mug);
    const double tilt = now.q.angularDistance(s.rest.q);
    if (gamma == 400.0) {
      EXPECT_GT(tilt, 0.5);
      continue;
    }
    EXPECT_NEAR(now.p.y() - s.rest.p.y(), lift, 0.005);  // off the table, with the hand
    EXPECT_GT(now.p.y(), 0.09);
    EXPECT_LT(tilt, 0.05);
    EXPECT_LT(drift, 0.002);
    EXPECT_LT(s.world.linearVelocity(s.mug).norm(), 0.01);
    EXPECT_EQ(s.ix.stats().pressingContacts, 4);
  }
}

// Contacts on a body with a signed-distance field take the field's closest point and normal:
// every contact's normal is the field's normal at its point, and it matches the analytic normal
// of the part it presses (the handle's tube, the cup wall) within the voxel resolution.
TEST(ConcaveGrasp, ContactNormalsOnTheHandleAreTheDistanceFieldNormals) {
  MugGrasp s;
  s.ix.setBodyOverrides(s.mug, {.gamma = 1000.0});
  s.close(0.003);
  const Transform t = s.world.pose(s.mug);
  int onHandle = 0;
  ASSERT_EQ(s.ix.contacts().size(), 4u);
  for (const HandContactInfo& c : s.ix.contacts()) {
    EXPECT_TRUE(c.pressing) << boneName(c.bone);
    const SurfacePoint sp = s.world.closestPoint(s.mug, c.point);
    EXPECT_LT(std::abs(sp.distance), 0.25 * s.world.shape(s.mug).sdf()->spacing());
    EXPECT_GT(c.normal.dot(sp.normal), std::cos(2.0 * kPi / 180.0)) << boneName(c.bone);
    const Vec3 local = t.applyInverse(c.point);
    const bool handle = local.x() > kOuter + 0.002;
    onHandle += handle;
    const Vec3 analytic =
        handle ? handleNormal(local) : Vec3(local.x(), 0.0, local.z()).normalized();
    EXPECT_GT(t.rotateInverse(c.normal).dot(analytic), std::cos(15.0 * kPi / 180.0))
        << boneName(c.bone) << " at " << local.transpose();
  }
  EXPECT_EQ(onHandle, 2);  // thumb and index on the handle, middle and ring on the wall
}

}  // namespace
}  // namespace grip
