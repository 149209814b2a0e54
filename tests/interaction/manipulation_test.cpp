// Whole-hand manipulation with scripted hands: lifting on a flat hand, carrying in a power
// grasp, extracting a Jenga block.
#include <gtest/gtest.h>

#include <cmath>

#include "interaction/interaction.hpp"
#include "interaction/scenarios.hpp"

namespace grip {
namespace {

using namespace scenarios;

constexpr double kDt = 1.0 / 60.0;

TEST(Manipulation, AFlatHandLiftsAnObjectFromBelow) {
  World w;
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  Transform palm;
  palm.p = Vec3(0.0, 0.3, 0.0);
  palm.q = Quat(Eigen::AngleAxisd(kPi, Vec3::UnitZ()));  // palm side up
  const double top = palm.p.y() + hd.palmHalfExtents.y();
  // On the palm, clear of the thumb (which leaves the palm toward the palm side).
  const BodyId box = addBox(w, Vec3(0.025, 0.02, 0.025), 0.1, Vec3(-0.012, top + 0.0205, -0.01));
  auto pose = [&](double lift) {
    Transform p = palm;
    p.p.y() += lift;
    ix.setHandPose(h, poseHand(hd, p, handShape(GraspPose::Flat)));
  };
  for (int i = 0; i < 30; ++i) {  // the box settles onto the palm
    pose(0.0);
    ix.step(w, kDt);
  }
  const Vec3 rest = w.centerOfMass(box) - palm.p;
  EXPECT_LT(rest.y() - (top - palm.p.y() + 0.02), 0.0);  // it sank into the palm: it is carried
  for (int i = 1; i <= 90; ++i) {                        // up 20 cm in 1.5 s, accelerating smoothly
    const double s = i / 90.0;
    pose(0.2 * s * s * (3.0 - 2.0 * s));
    ix.step(w, kDt);
  }
  for (int i = 0; i < 30; ++i) {
    pose(0.2);
    ix.step(w, kDt);
  }
  const Vec3 carried = w.centerOfMass(box) - (palm.p + Vec3(0.0, 0.2, 0.0));
  EXPECT_LT((carried - rest).norm(), 0.005);
  EXPECT_LT(w.linearVelocity(box).norm(), 0.01);
}

// A bar (12 x 4 x 4 cm, 0.1 kg) across the palm, wrapped by a power grasp: palm on top,
// proximal phalanges in front, distal phalanges under it. The hand carries it 30 cm and turns
// it 90 degrees about the vertical in 1.5 s.
// DISABLED: fails today. With the forward-kinematics power pose the bones meet the bar on edges
// and oblique faces at once; the patches slip, re-anchor on other faces and the bar is thrown
// out within 0.1 s. Needs work on contact placement for edge contacts (see docs/interaction.md,
// "Open problems").
TEST(Manipulation, DISABLED_APowerGraspCarriesAndTurnsAnObject) {
  World w;
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  Transform palm;
  palm.p = Vec3(0.0, 0.5, 0.0);
  const BodyId bar = addBox(w, Vec3(0.06, 0.02, 0.02), 0.1,
                            palm.apply(Vec3(0.0, -hd.palmHalfExtents.y() - 0.02, -0.035)));
  const HandShape power = handShape(GraspPose::Power);
  auto poseAt = [&](double s) {  // s in [0, 1] along the path
    const double e = s * s * (3.0 - 2.0 * s);
    Transform p = palm;
    p.p += Vec3(0.3 * e, 0.0, 0.0);
    p.q = Quat(Eigen::AngleAxisd(0.5 * kPi * e, Vec3::UnitY())) * palm.q;
    ix.setHandPose(h, poseHand(hd, p, power));
    return p;
  };
  for (int i = 0; i < 30; ++i) {  // settle in the grasp
    poseAt(0.0);
    ix.step(w, kDt);
  }
  const Transform relStart = palm.inverse() * w.pose(bar);
  EXPECT_GE(ix.stats().pressingContacts, 5);
  Transform end;
  for (int i = 1; i <= 90; ++i) {
    end = poseAt(i / 90.0);
    ix.step(w, kDt);
  }
  for (int i = 0; i < 30; ++i) {
    end = poseAt(1.0);
    ix.step(w, kDt);
  }
  const Transform relEnd = end.inverse() * w.pose(bar);
  EXPECT_LT((relEnd.p - relStart.p).norm(), 0.005);
  EXPECT_LT(relEnd.q.angularDistance(relStart.q), 0.05);
  const Vec3 travelled = w.centerOfMass(bar) - palm.apply(relStart.p);
  EXPECT_GT(travelled.norm(), 0.25);
}

// A fingertip pushes the middle block of the third layer of a Jenga-like tower (see
// scenarios::addTower) 4.5 cm out along its length. The other blocks must move less than 5 mm,
// and the same tower left alone must hold still.
std::vector<Vec3> runTower(bool withHand, double& targetMoved) {
  World w;
  addFloor(w, 0.6, 0.5);
  const Tower tower = addTower(w, 6);
  const BodyId target = tower.blocks[7];
  for (int i = 0; i < 60; ++i) w.step(kDt);  // settle
  const Vec3 start = w.centerOfMass(target);
  std::vector<Vec3> settled;
  for (BodyId b : tower.blocks) settled.push_back(w.centerOfMass(b));
  Interaction ix;
  HandDef hd;
  hd.scale = 0.7;  // a slim finger (11 mm thick) for a 15 mm slot
  const HandId h = ix.addHand(hd);
  const int tip = boneIndex(Finger::Index, 2);
  const Vec3 face(tower.blockHalfExtents.x(), start.y(), start.z());
  auto finger = [&](double depth) {
    HandPose p = parkedHand(hd);
    // Fingertip pointing -x into the end face of the block.
    const double r = hd.scale * hd.fingers[1].radius[2];
    const double axisHalf = 0.5 * hd.scale * hd.fingers[1].length[2] - 0.5 * r;
    p.bones[tip].q = Quat::FromTwoVectors(Vec3::UnitY(), -Vec3::UnitX());
    p.bones[tip].p = face + Vec3(axisHalf + r - depth, 0.0, 0.0);
    if (withHand) ix.setHandPose(h, p);
  };
  const double travel = 0.045, speed = 0.03;
  const int steps = static_cast<int>(travel / speed / kDt);
  for (int i = 0; i < 20; ++i) {  // touch
    finger(-0.002 + 0.004 * i / 20.0);
    ix.step(w, kDt);
  }
  for (int i = 1; i <= steps; ++i) {
    finger(0.002 + travel * i / steps);
    ix.step(w, kDt);
  }
  for (int i = 0; i < 30; ++i) ix.step(w, kDt);  // hand gone (tracking lost), things settle
  targetMoved = start.x() - w.centerOfMass(target).x();
  std::vector<Vec3> moved;  // each block's displacement since the tower settled
  for (size_t i = 0; i < tower.blocks.size(); ++i)
    moved.push_back(w.centerOfMass(tower.blocks[i]) - settled[i]);
  return moved;
}

// The World used to let this 18-block tower creep by centimetres: the plane contact kept the
// thin blocks' upper corners. Now the hand-free tower holds still and the comparison is fair.
TEST(Manipulation, OneJengaBlockIsPushedOutWhileTheTowerStands) {
  double pushed = 0.0, alone = 0.0;
  const std::vector<Vec3> with = runTower(true, pushed);
  const std::vector<Vec3> without = runTower(false, alone);
  EXPECT_GT(pushed, 0.035);
  EXPECT_LT(std::abs(alone), 1e-3);
  for (size_t i = 0; i < with.size(); ++i) {
    EXPECT_LT(without[i].norm(), 1e-3) << "block " << i << " of the tower left alone";
    if (i != 7) {
      EXPECT_LT(with[i].norm(), 0.005) << "block " << i;
    }
  }
}

}  // namespace
}  // namespace grip

namespace grip {
namespace {

using namespace scenarios;

// Thumb and index pinch a cylinder (radius 2 cm, a 32-sided prism, axis along z) across its
// curved side, in zero gravity. The index fingertip then moves 1 cm along +y while the thumb
// stays: the cylinder rolls between them about its own axis by about dy / (2 R) = 0.25 rad, its
// centre following by dy / 2, as between two sticking fingertips.
TEST(Manipulation, OneFingerMovingTangentiallySpinsAPinchedCylinder) {
  World w;
  w.setGravity(Vec3::Zero());
  const double radius = 0.02, half = 0.03;
  std::vector<Vec3> pts;
  for (int i = 0; i < 32; ++i) {
    const double a = 2.0 * kPi * i / 32.0;
    for (double z : {-half, half}) pts.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
  }
  BodyDef bd;
  bd.shape = Shape::convexHull(pts);
  bd.mass = 0.05;
  bd.position = Vec3(0.0, 0.5, 0.0);
  const BodyId cyl = w.createBody(bd);
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  const Vec3 c = w.centerOfMass(cyl);
  const double depth = 0.003;
  auto pinch = [&](double dy) {
    HandPose p = parkedHand(hd);
    pressBone(p, hd, boneIndex(Finger::Thumb, 2), c - radius * Vec3::UnitX(), -Vec3::UnitX(),
              Vec3::UnitZ(), depth);
    pressBone(p, hd, boneIndex(Finger::Index, 2), c + radius * Vec3::UnitX() + Vec3(0, dy, 0),
              Vec3::UnitX(), Vec3::UnitZ(), depth);
    ix.setHandPose(h, p);
  };
  for (int i = 0; i < 20; ++i) {
    pinch(0.0);
    ix.step(w, kDt);
  }
  const Quat q0 = w.pose(cyl).q;
  const Vec3 p0 = w.centerOfMass(cyl);
  const double dy = 0.01;
  for (int i = 1; i <= 60; ++i) {
    pinch(dy * i / 60.0);
    ix.step(w, kDt);
  }
  for (int i = 0; i < 30; ++i) {
    pinch(dy);
    ix.step(w, kDt);
  }
  const Eigen::AngleAxisd turn(w.pose(cyl).q * q0.conjugate());
  const Vec3 rot = turn.angle() * turn.axis();
  EXPECT_NEAR(rot.z(), dy / (2.0 * radius), 0.08);  // rolls about its own axis (+z for +y at +x)
  EXPECT_LT(std::hypot(rot.x(), rot.y()), 0.03);
  EXPECT_NEAR(w.centerOfMass(cyl).y() - p0.y(), 0.5 * dy, 0.002);
  EXPECT_EQ(ix.stats().pressingContacts, 2);
}

}  // namespace
}  // namespace grip
