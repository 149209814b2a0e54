// Hands against the engine's limits: a finger at 5 m/s against a 5 mm plate, and random and
// adversarial tracking frames (NaN, inf, huge coordinates, teleporting bones, degenerate
// quaternions, zero-length bones) -- no NaN or inf may ever reach a body.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "interaction/interaction.hpp"
#include "interaction/scenarios.hpp"
#include "interaction/tracking.hpp"
#include "stress_util.hpp"

using namespace grip;
using namespace grip::stress;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPlateHalf = 0.0025;  // a 5 mm plate
const int kIndexTip = boneIndex(Finger::Index, 2);

// ---- a fast finger against a thin plate -----------------------------------------------------

struct PlateRun {
  bool contactFound = false;
  double plateSpeed = 0.0;   // along +x at the end (m/s)
  double plateTravel = 0.0;  // along +x (m)
  bool tunnelled = false;    // the fingertip ended beyond the plate while the plate stayed put
  bool finite = true;
};

// A free 50 g plate (10 x 10 cm, 5 mm thick, normal along x) floating without gravity; the
// index fingertip, axis along z, moves along +x at `speed` through where the plate is, starting
// `phase` (0..1) of one frame's travel farther back, with the hand updated at `hz`; its axis
// `height` above the plate's centre.
PlateRun fingerAtPlate(double speed, double hz, double phase, double height) {
  WorldDef wd;
  wd.gravity = Vec3::Zero();
  World w(wd);
  Interaction ix;
  const BodyId plate = addBody(w, Shape::box(Vec3(kPlateHalf, 0.05, 0.05)), Vec3::Zero(), 0.05);
  HandDef hd;
  const HandId h = ix.addHand(hd);
  const double dt = 1.0 / hz;
  const double radius = hd.fingers[1].radius[2];
  const double x0 = -0.1 - phase * speed * dt;
  PlateRun r;
  const int steps = static_cast<int>(0.1 * hz);  // 0.1 s: 0.5 m at 5 m/s
  for (int i = 0; i <= steps; ++i) {
    HandPose pose = scenarios::parkedHand(hd);
    const double x = x0 + speed * i * dt;  // the fingertip axis
    pose.bones[kIndexTip].p = Vec3(x, height, 0.0);
    pose.bones[kIndexTip].q = Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));  // +Y -> +z
    pose.tracked = true;
    ix.setHandPose(h, pose);
    ix.step(w, dt);
    for (const HandContactEvent& e : ix.contactBeginEvents()) r.contactFound |= e.body == plate;
    r.finite = r.finite && allFinite(w);
    if (!r.finite) break;
  }
  const double plateX = w.centerOfMass(plate).x();
  const double tipX = x0 + speed * steps * dt;
  r.plateSpeed = w.linearVelocity(plate).x();
  r.plateTravel = plateX;
  r.tunnelled = tipX - radius > plateX + kPlateHalf && r.plateSpeed < 0.5 * speed;
  return r;
}

void expectPushed(double speed, double hz) {
  // Every phase of the frame sampling: a test that happens to land a frame on the plate
  // proves nothing.
  for (double phase : {0.0, 0.2, 0.4, 0.6, 0.8}) {
    const PlateRun r = fingerAtPlate(speed, hz, phase, 0.0);
    const std::string at = std::to_string(speed) + " m/s at " + std::to_string(hz) + " Hz, phase " +
                           std::to_string(phase);
    ASSERT_TRUE(r.finite) << at;
    EXPECT_TRUE(r.contactFound) << at << ": the fingertip never touched the plate";
    EXPECT_FALSE(r.tunnelled) << at << ": the fingertip passed the plate, which moves at "
                              << r.plateSpeed << " m/s";
    EXPECT_GT(r.plateSpeed, 0.5) << at << ": the plate was not pushed";
    EXPECT_GT(r.plateTravel, 0.01) << at;
  }
}

}  // namespace

TEST(FastHand, FingerAtFiveMetresPerSecondPushesAFiveMillimetrePlateAt480Hz) {
  // 10.4 mm of travel per update: less than the 15 mm window between first coming within the
  // 5 mm contact offset and the 10 mm resume depth beyond which a new contact stays passive.
  expectPushed(5.0, 480.0);
}

TEST(FastHand, FingerAtTwoMetresPerSecondPushesAFiveMillimetrePlateAt240Hz) {
  expectPushed(2.0, 240.0);  // 8.3 mm per update
}

// FAILS (interaction/ contact finding, Interaction::update). At 60 Hz a fingertip at 5 m/s
// moves 83 mm per update (240 Hz: 21 mm), more than the 15 mm window between coming within the
// 5 mm contact offset of the plate and the 10 mm resumeDepth, and update() tests only this
// frame's bone pose (no sweep from the last accepted pose). Measured (5 phases each): at
// 60 Hz 4 of 5 phases find no contact and the plate stays at rest (speed 0) while the finger
// passes it; the 5th finds it too deep (passive). At 120 and 240 Hz 2-3 of 5 phases tunnel,
// and where the first contact is past the plate's mid plane the closest point is on the far
// face, so the plate is pushed *backward* (-0.07 to -0.32 m/s). 480 Hz and above: every phase
// pushes the plate (9.2 m/s). A swept bone test from the previous pose would fix it.
TEST(FastHand, FingerAtFiveMetresPerSecondPushesAFiveMillimetrePlateAt60Hz) {
  expectPushed(5.0, 60.0);
  expectPushed(5.0, 240.0);
}

// The fingertip's axis passes just above the plate's top edge, so that only the side of the
// finger meets the plate: a ray along the axis (the sweep before shape casts) missed it, and at
// 60 Hz the finger passed the plate untouched in every phase. Now it meets and pushes the
// plate (which tips away, and the finger may then pass over its edge).
TEST(FastHand, AFingerWhoseSideMeetsThePlatesEdgePushesItAt60Hz) {
  const double radius = HandDef{}.fingers[1].radius[2];
  for (double phase : {0.0, 0.2, 0.4, 0.6, 0.8}) {
    const PlateRun r = fingerAtPlate(5.0, 60.0, phase, 0.05 + 0.5 * radius);
    ASSERT_TRUE(r.finite) << phase;
    EXPECT_TRUE(r.contactFound) << phase;
    EXPECT_GT(r.plateSpeed, 0.5) << phase;
    EXPECT_GT(r.plateTravel, 0.01) << phase;
  }
}

// ---- random and adversarial tracking frames -------------------------------------------------

namespace {

// A hand somewhere around the scene in a random grasp pose.
HandPose randomPose(const HandDef& def, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Transform palm;
  palm.p = Vec3(0.15 * u(rng), 0.08 + 0.08 * u(rng), 0.15 * u(rng));
  palm.q = Quat(u(rng), u(rng), u(rng), u(rng) + 1e-3).normalized();
  const auto grasp = static_cast<GraspPose>(rng() % 5);
  HandPose p = poseHand(def, palm, handShape(grasp));
  p.tracked = rng() % 20 != 0;
  return p;
}

// Damages a frame in one of many ways (or not at all).
void damage(HandPose& p, std::mt19937_64& rng) {
  static const double huge[] = {1e6,     -1e9, 1e30, -1e300, std::numeric_limits<double>::max(),
                                4.9e-324};
  Transform& b = p.bones[rng() % kBonesPerHand];
  const int c = static_cast<int>(rng() % 3);
  switch (rng() % 12) {
    case 0:
      b.p[c] = kNaN;
      break;
    case 1:
      b.p[c] = rng() % 2 ? kInf : -kInf;
      break;
    case 2:
      b.p[c] = huge[rng() % 6];
      break;
    case 3:
      b.q.coeffs()[c] = kNaN;
      break;
    case 4:                  // (a zero quaternion has its own, disabled, test below)
      b.q.coeffs() *= 1e-6;  // finite, far from unit (below 1e-9: the disabled test)
      break;
    case 5:
      b.q.coeffs() *= 1e100;  // finite, far from unit (1e200: the disabled test)
      break;
    case 6:
      b.p += Vec3(1.0, 0.0, 0.0);  // one bone teleports a metre
      break;
    case 7:
      for (Transform& t : p.bones) t.p += Vec3(0.0, 0.0, 0.5);  // the whole hand teleports
      break;
    case 8:
      for (Transform& t : p.bones) t.p = p.bones[0].p;  // every bone at one point
      break;
    default:
      break;  // an ordinary frame
  }
}

// Joints for OpenXR with every joint at the same point: bones of zero length, no direction.
OpenXRHandFrame collapsedOpenXRFrame(const Vec3& at) {
  OpenXRHandFrame f;
  f.isActive = true;
  for (int j = 0; j < kXrJointCount; ++j) {
    f.joints[j].p = at;
    f.valid[j] = true;
  }
  return f;
}

}  // namespace

TEST(AdversarialHands, RandomAndDamagedFramesNeverPutNaNIntoABody) {
  World w;
  InteractionDef idef;
  Interaction ix(idef);
  scenarios::addFloor(w);
  std::vector<BodyId> bodies;
  bodies.push_back(scenarios::addBox(w, Vec3::Constant(0.03), 0.2, Vec3(0.0, 0.03, 0.0)));
  bodies.push_back(scenarios::addBox(w, Vec3::Constant(0.01), 0.01, Vec3(0.06, 0.01, 0.0)));
  bodies.push_back(
      scenarios::addBox(w, Vec3(0.05, kPlateHalf, 0.05), 0.05, Vec3(-0.08, kPlateHalf, 0.0)));
  bodies.push_back(addBody(w, Shape::sphere(0.02), Vec3(0.0, 0.02, 0.08), 0.05));
  bodies.push_back(addBody(w, Shape::capsule(0.01, 0.03), Vec3(0.0, 0.1, -0.08), 0.02));
  // Two ordinary hands and one whose fingers are (almost) zero-length capsules.
  HandDef tiny;
  for (FingerSize& f : tiny.fingers) {  // the radius may be at most 3/4 of the length
    f.length = {1e-9, 1e-12, 1e-300};
    f.radius = {0.7e-9, 0.7e-12, 0.7e-300};
  }
  const std::vector<HandDef> defs = {HandDef{}, HandDef{}, tiny};
  std::vector<HandId> hands;
  for (const HandDef& d : defs) hands.push_back(ix.addHand(d));

  std::mt19937_64 rng(7);
  const double dt = 1.0 / 60.0;
  int rejected = 0, teleported = 0;
  for (int step = 0; step < 3000; ++step) {
    for (size_t k = 0; k < hands.size(); ++k) {
      HandPose p = step % 97 == 0 && k == 0 ? fromOpenXR(collapsedOpenXRFrame(Vec3(0.0, 0.03, 0.0)))
                                            : randomPose(defs[k], rng);
      if (k != 0 || step % 3 == 0) damage(p, rng);
      const FrameStatus s = ix.setHandPose(hands[k], p);
      rejected += s == FrameStatus::RejectedNonFinite;
      teleported += s == FrameStatus::Teleported;
    }
    ix.update(w, dt);
    w.step(dt);
    std::string bad;
    ASSERT_TRUE(allFinite(w, &bad)) << "step " << step << ": " << bad << " is not finite";
    for (BodyId b : bodies)
      ASSERT_LT(w.centerOfMass(b).norm(), 100.0) << "step " << step << ": body " << b.index
                                                 << " was flung to " << w.centerOfMass(b).norm();
  }
  // The damage did reach the interaction (the test is not vacuous).
  EXPECT_GT(rejected, 100);
  EXPECT_GT(teleported, 100);
  EXPECT_GT(ix.stats().droppedFrames, 100);
}

TEST(AdversarialHands, ZeroLengthFingerCapsulesAreRefusedNamingTheField) {
  Interaction ix;
  HandDef d;
  d.fingers[2].length[1] = 0.0;
  try {
    ix.addHand(d);
    FAIL() << "a zero-length finger bone was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("length"), std::string::npos) << e.what();
  }
}

TEST(AdversarialHands, ACollapsedOpenXRFrameGivesAFinitePoseOrNone) {
  const HandPose p = fromOpenXR(collapsedOpenXRFrame(Vec3(0.1, 0.2, 0.3)));
  EXPECT_TRUE(!p.tracked || isFinite(p));
}

// FAILS (interaction/: Interaction::setHandPose accepts the frame, Interaction::update throws).
// A tracking frame whose bone orientation is finite but not normalisable -- the zero
// quaternion, one of norm below 1e-9, or one scaled by 1e200 (its norm overflows to inf, so
// normalising gives zero) -- passes isFinite(pose) and setHandPose returns Accepted; the next
// update passes the bone transform to the World's overlap query, which throws grip::Error
// "overlap.transform.orientation: must be a non-zero quaternion" out of update(). setHandPose
// should reject such a frame like a non-finite one (FrameStatus::RejectedNonFinite, a dropout)
// so that update never throws on tracking data.
TEST(AdversarialHands, AnUnnormalisableQuaternionFrameIsRejectedNotThrownFromUpdate) {
  for (const double scale : {0.0, 1e-300, 1e200}) {
    SCOPED_TRACE("quaternion (1, 0, 0, 0) * " + std::to_string(scale));
    World w;
    Interaction ix;
    scenarios::addFloor(w);
    const BodyId box = scenarios::addBox(w, Vec3::Constant(0.03), 0.2, Vec3(0.0, 0.03, 0.0));
    HandDef hd;
    const HandId h = ix.addHand(hd);
    HandPose p = scenarios::parkedHand(hd);
    p.tracked = true;
    p.bones[kIndexTip].p = Vec3(0.0, 0.07, 0.0);
    p.bones[kIndexTip].q = Quat(scale, 0.0, 0.0, 0.0);
    EXPECT_EQ(ix.setHandPose(h, p), FrameStatus::RejectedNonFinite);
    EXPECT_NO_THROW(ix.update(w, 1.0 / 60.0));
    w.step(1.0 / 60.0);
    EXPECT_TRUE(allFinite(w));
    EXPECT_LT(w.linearVelocity(box).norm(), 0.1);
  }
}
