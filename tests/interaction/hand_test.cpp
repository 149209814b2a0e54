// Hand skeleton, input adapters and scripted hands (no World needed).
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "interaction/hand.hpp"
#include "interaction/scripted.hpp"
#include "interaction/tracking.hpp"

namespace grip {
namespace {

TEST(HandModel, SixteenBonesBoxPalmAndCapsuleFingers) {
  HandDef def;
  const HandShapes s = makeHandShapes(def);
  EXPECT_EQ(s.bones[kPalmBone]->type(), ShapeType::Box);
  for (int b = 1; b < kBonesPerHand; ++b) {
    ASSERT_EQ(s.bones[b]->type(), ShapeType::Capsule) << boneName(b);
    const int f = (b - 1) / 3, seg = (b - 1) % 3;
    EXPECT_DOUBLE_EQ(s.bones[b]->radius(), def.fingers[f].radius[seg]);
  }
  def.scale = 1.2;
  const HandShapes big = makeHandShapes(def);
  EXPECT_NEAR(big.bones[kPalmBone]->halfExtents().x(), 1.2 * 0.042, 1e-15);
  EXPECT_NEAR(big.bones[boneIndex(Finger::Index, 2)]->radius(), 1.2 * 0.0082, 1e-15);
}

TEST(HandModel, RejectsBadSizesNamingTheField) {
  HandDef def;
  def.scale = 0.0;
  try {
    makeHandShapes(def);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "HandDef.scale");
  }
  def = HandDef{};
  def.fingers[2].length[1] = std::nan("");
  EXPECT_THROW(makeHandShapes(def), Error);
}

TEST(HandModel, LeftHandMirrorsTheRightHand) {
  HandDef right, left;
  left.side = Handedness::Left;
  for (GraspPose p :
       {GraspPose::Open, GraspPose::Pinch, GraspPose::Power, GraspPose::Flat, GraspPose::Point}) {
    const HandPose r = poseHand(right, Transform{}, handShape(p));
    const HandPose l = poseHand(left, Transform{}, handShape(p));
    for (int f = 0; f < 5; ++f) {
      const Vec3 tr = fingertip(right, r, Finger(f)), tl = fingertip(left, l, Finger(f));
      EXPECT_NEAR(tr.x(), -tl.x(), 1e-12);
      EXPECT_NEAR(tr.y(), tl.y(), 1e-12);
      EXPECT_NEAR(tr.z(), tl.z(), 1e-12);
    }
  }
}

TEST(HandModel, FingersCurlTowardThePalmSide) {
  // Palm side is -Y of the palm frame: a power grasp puts the fingertips below the flat ones.
  HandDef def;
  const HandPose flat = poseHand(def, Transform{}, handShape(GraspPose::Flat));
  const HandPose power = poseHand(def, Transform{}, handShape(GraspPose::Power));
  for (Finger f : {Finger::Index, Finger::Middle, Finger::Ring, Finger::Pinky}) {
    EXPECT_LT(fingertip(def, power, f).y(), fingertip(def, flat, f).y() - 0.03);
    EXPECT_NEAR(fingertip(def, flat, f).y(), 0.0, 1e-12);  // a flat finger stays in the plane
  }
}

// Joints as OpenXR reports them, built from a pose: each joint's -Z along its bone, +Y dorsal.
OpenXRHandFrame openXRFrom(const HandDef& def, const HandPose& pose) {
  OpenXRHandFrame fr;
  fr.isActive = true;
  fr.valid.fill(true);
  const Quat boneToJoint(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitX()));
  fr.joints[0] = pose.bones[kPalmBone];
  fr.joints[1] = pose.bones[kPalmBone];
  const int chains[5][4] = {
      {2, 3, 4, 5}, {7, 8, 9, 10}, {12, 13, 14, 15}, {17, 18, 19, 20}, {22, 23, 24, 25}};
  for (int f = 0; f < 5; ++f) {
    fr.joints[chains[f][0] - (f == 0 ? 0 : 1)] = pose.bones[kPalmBone];  // metacarpals
    for (int seg = 0; seg < 3; ++seg) {
      const Transform& b = pose.bones[boneIndex(Finger(f), seg)];
      const double half = 0.5 * def.fingers[f].length[seg];
      fr.joints[chains[f][seg]] = {b.apply(Vec3(0, -half, 0)), b.q * boneToJoint};
      if (seg == 2) fr.joints[chains[f][3]] = {b.apply(Vec3(0, half, 0)), b.q * boneToJoint};
    }
  }
  return fr;
}

TEST(OpenXRAdapter, BonesSpanConsecutiveJoints) {
  HandDef def;
  Transform palm;
  palm.p = Vec3(0.1, 1.2, -0.3);
  palm.q = Quat(Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()));
  const HandPose pose = poseHand(def, palm, handShape(GraspPose::Pinch));
  const HandPose back = fromOpenXR(openXRFrom(def, pose));
  ASSERT_TRUE(back.tracked);
  for (int b = 0; b < kBonesPerHand; ++b) {
    EXPECT_LT((back.bones[b].p - pose.bones[b].p).norm(), 1e-12) << boneName(b);
    EXPECT_LT(back.bones[b].q.angularDistance(pose.bones[b].q), 1e-9) << boneName(b);
  }
}

TEST(OpenXRAdapter, InactiveOrInvalidJointsMeanNoTracking) {
  HandDef def;
  OpenXRHandFrame fr = openXRFrom(def, poseHand(def, Transform{}, handShape(GraspPose::Open)));
  fr.valid[9] = false;
  EXPECT_FALSE(fromOpenXR(fr).tracked);
  fr.valid[9] = true;
  fr.joints[4].p.x() = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(fromOpenXR(fr).tracked);
  fr = openXRFrom(def, poseHand(def, Transform{}, handShape(GraspPose::Open)));
  fr.isActive = false;
  EXPECT_FALSE(fromOpenXR(fr).tracked);
}

TEST(LeapAdapter, DesktopToHmdIsTheThesisMatrixInMetres) {
  // Desktop mode: only mm -> m.
  EXPECT_LT(
      (leapPointToWorld(LeapConversion::desktop(), Vec3(10, 200, -30)) - Vec3(0.01, 0.2, -0.03))
          .norm(),
      1e-15);
  // Head mounted: x -> -x, y (away from the device, forward) -> -z, z -> -y; then the mount.
  LeapConversion hmd;
  EXPECT_LT((leapPointToWorld(hmd, Vec3(1000, 0, 0)) - Vec3(-1, 0, 0)).norm(), 1e-15);
  EXPECT_LT((leapPointToWorld(hmd, Vec3(0, 1000, 0)) - Vec3(0, 0, -1)).norm(), 1e-15);
  EXPECT_LT((leapPointToWorld(hmd, Vec3(0, 0, 1000)) - Vec3(0, -1, 0)).norm(), 1e-15);
  const LeapConversion rift = LeapConversion::riftDK2();
  EXPECT_LT((leapPointToWorld(rift, Vec3::Zero()) - Vec3(0, 0, -0.08)).norm(), 1e-15);
  const LeapConversion holo = LeapConversion::holoLens();
  EXPECT_LT((leapPointToWorld(holo, Vec3::Zero()) - Vec3(0, 0.07, -0.05)).norm(), 1e-15);
  // A mount tilted 90 degrees about z turns the device's x into y.
  LeapConversion tilted = LeapConversion::desktop();
  tilted.mountTilt = Vec3(0, 0, 0.5 * kPi);
  EXPECT_LT((leapPointToWorld(tilted, Vec3(1000, 0, 0)) - Vec3(0, 1, 0)).norm(), 1e-12);
  // The headset pose carries everything.
  hmd.hmdPose.p = Vec3(0, 1.6, 0);
  EXPECT_LT((leapPointToWorld(hmd, Vec3::Zero()) - Vec3(0, 1.6, 0)).norm(), 1e-15);
}

TEST(LeapAdapter, BonesFromJointsSkippingTheMetacarpal) {
  HandDef def;
  const HandPose pose = poseHand(def, Transform{}, handShape(GraspPose::Power));
  LeapHandFrame fr;
  fr.isTracked = true;
  fr.palmPosition = 1000.0 * pose.bones[kPalmBone].p;
  fr.palmNormal = -(pose.bones[kPalmBone].q * Vec3::UnitY());
  fr.palmDirection = -(pose.bones[kPalmBone].q * Vec3::UnitZ());
  for (int f = 0; f < 5; ++f) {
    for (int seg = 0; seg < 3; ++seg) {
      const Transform& b = pose.bones[boneIndex(Finger(f), seg)];
      const double half = 0.5 * def.fingers[f].length[seg];
      fr.digits[f][seg + 1] = {1000.0 * b.apply(Vec3(0, -half, 0)),
                               1000.0 * b.apply(Vec3(0, half, 0))};
    }
  }
  const HandPose back = fromLeap(fr, LeapConversion::desktop());
  ASSERT_TRUE(back.tracked);
  for (int b = 0; b < kBonesPerHand; ++b) {
    EXPECT_LT((back.bones[b].p - pose.bones[b].p).norm(), 1e-12) << boneName(b);
    EXPECT_LT((back.bones[b].q * Vec3::UnitY() - pose.bones[b].q * Vec3::UnitY()).norm(), 1e-9);
  }
  fr.isTracked = false;
  EXPECT_FALSE(fromLeap(fr, LeapConversion::desktop()).tracked);
}

ScriptedHandDef twoKeyScript() {
  ScriptedHandDef d;
  Transform a, b;
  a.p = Vec3(0, 1, 0);
  b.p = Vec3(0.3, 1, 0);
  b.q = Quat(Eigen::AngleAxisd(0.5 * kPi, Vec3::UnitY()));
  d.keys = {{0.0, a, GraspPose::Open, {}}, {1.0, b, GraspPose::Power, {}}};
  return d;
}

TEST(ScriptedHand, InterpolatesPathAndPoseAndHoldsAtTheEnds) {
  const ScriptedHand s(twoKeyScript());
  const HandPose mid = s.sample(0.5);
  ASSERT_TRUE(mid.tracked);
  EXPECT_LT((mid.bones[kPalmBone].p - Vec3(0.15, 1, 0)).norm(), 1e-15);
  EXPECT_NEAR(mid.bones[kPalmBone].q.angularDistance(Quat::Identity()), 0.25 * kPi, 1e-12);
  const HandPose blended =
      poseHand(HandDef{}, mid.bones[kPalmBone],
               blend(handShape(GraspPose::Open), handShape(GraspPose::Power), 0.5));
  EXPECT_LT((mid.bones[5].p - blended.bones[5].p).norm(), 1e-15);
  EXPECT_LT((s.sample(-1.0).bones[kPalmBone].p - Vec3(0, 1, 0)).norm(), 1e-15);
  EXPECT_LT((s.sample(7.0).bones[kPalmBone].p - Vec3(0.3, 1, 0)).norm(), 1e-15);
}

TEST(ScriptedHand, NoiseIsSeededAndTrackingLossIsUntracked) {
  ScriptedHandDef d = twoKeyScript();
  d.positionNoise = 0.002;
  d.seed = 7;
  d.trackingLoss = {{0.4, 0.6}};
  const ScriptedHand a(d), b(d);
  const HandPose pa = a.sample(0.25), pb = b.sample(0.25);
  const HandPose clean = ScriptedHand(twoKeyScript()).sample(0.25);
  double rms = 0.0;
  for (int i = 0; i < kBonesPerHand; ++i) {
    EXPECT_EQ(pa.bones[i].p, pb.bones[i].p);  // same seed, same bits
    rms += (pa.bones[i].p - clean.bones[i].p).squaredNorm();
  }
  rms = std::sqrt(rms / (3 * kBonesPerHand));
  EXPECT_GT(rms, 0.0005);
  EXPECT_LT(rms, 0.006);
  d.seed = 8;
  EXPECT_NE(ScriptedHand(d).sample(0.25).bones[3].p, pa.bones[3].p);
  EXPECT_FALSE(a.sample(0.5).tracked);
  EXPECT_TRUE(a.sample(0.61).tracked);
}

TEST(ScriptedHand, RejectsBadScripts) {
  ScriptedHandDef d = twoKeyScript();
  d.keys[1].time = 0.0;
  EXPECT_THROW(ScriptedHand{d}, Error);
  d = twoKeyScript();
  d.keys.clear();
  EXPECT_THROW(ScriptedHand{d}, Error);
  d = twoKeyScript();
  d.positionNoise = -1.0;
  EXPECT_THROW(ScriptedHand{d}, Error);
}

}  // namespace
}  // namespace grip
