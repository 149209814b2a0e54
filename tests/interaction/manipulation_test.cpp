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

// A handle (a cylinder of radius 12 mm, 14 cm long, 0.1 kg) across the palm below it, wrapped by
// a power grasp: the palm on top, the fingers closed around it with closeHandOn (each joint
// stops where its bone has sunk 3 mm into the handle, the joints beyond it keep closing). The
// hand carries it 30 cm and turns it 90 degrees about the vertical in 1.5 s; the handle stays
// within a few millimetres of its pose relative to the palm. Before the friction cone was put
// inside the implicit solve, the slipping samples of the first steps threw it out of this grasp.
TEST(Manipulation, APowerGraspCarriesAndTurnsAnObject) {
  World w;
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  Transform palm;
  palm.p = Vec3(0.0, 0.5, 0.0);
  const double radius = 0.012;
  const Quat alongX = Quat::FromTwoVectors(Vec3::UnitZ(), Vec3::UnitX());
  const BodyId handle =
      addCylinder(w, radius, 0.07, 0.1,
                  palm.apply(Vec3(0.0, -hd.palmHalfExtents.y() - radius - 0.0005, -0.05)), alongX);
  HandShape fist = handShape(GraspPose::Power);
  for (int f = 1; f < 5; ++f) fist[f].flex = {1.6, 1.8, 1.4};
  fist[0].flex = {1.2, 1.2, 1.2};
  const HandShape grasp = closeHandOn(w, handle, hd, palm, handShape(GraspPose::Open), fist, 0.003);
  for (int f = 1; f < 5; ++f) {  // every finger stopped on the handle before closing fully
    EXPECT_LT(grasp[f].flex[0], fist[f].flex[0]) << f;
  }
  auto poseAt = [&](double s) {  // s in [0, 1] along the path
    const double e = s * s * (3.0 - 2.0 * s);
    Transform p = palm;
    p.p += Vec3(0.3 * e, 0.0, 0.0);
    p.q = Quat(Eigen::AngleAxisd(0.5 * kPi * e, Vec3::UnitY())) * palm.q;
    ix.setHandPose(h, poseHand(hd, p, grasp));
    return p;
  };
  for (int i = 0; i < 30; ++i) {  // settle in the grasp
    poseAt(0.0);
    ix.step(w, kDt);
  }
  const Transform relStart = palm.inverse() * w.pose(handle);
  EXPECT_GE(ix.stats().pressingContacts, 8);
  // It hangs in the fingers where it was placed (within the 3 mm squeeze).
  EXPECT_LT((relStart.p - Vec3(0.0, -0.0255, -0.05)).norm(), 0.004);
  Transform end;
  double worst = 0.0;
  for (int i = 1; i <= 120; ++i) {  // 1.5 s along the path, then 0.5 s holding still
    end = poseAt(std::min(1.0, i / 90.0));
    ix.step(w, kDt);
    worst = std::max(worst, ((end.inverse() * w.pose(handle)).p - relStart.p).norm());
  }
  const Transform relEnd = end.inverse() * w.pose(handle);
  EXPECT_LT(worst, 0.003);
  EXPECT_LT((relEnd.p - relStart.p).norm(), 0.003);
  EXPECT_LT(relEnd.q.angularDistance(relStart.q), 0.02);
  // It went along: 30 cm across and turned a quarter turn with the hand.
  EXPECT_GT((w.pose(handle).p - palm.apply(relStart.p)).norm(), 0.25);
  const Vec3 axis = w.pose(handle).rotate(Vec3::UnitZ());
  EXPECT_LT(std::abs(axis.x()), 0.05);
  EXPECT_GT(std::abs(axis.z()), 0.99);
  EXPECT_LT(w.linearVelocity(handle).norm(), 0.01);
}

// A fingertip pushes the middle block of the third layer of a Jenga-like tower (see
// scenarios::addTower) 4.5 cm out along its length. The other blocks must move less than 5 mm,
// and the same tower left alone must hold still.
std::vector<Vec3> runTower(bool withHand, double& targetMoved, int relaxIterations = 1) {
  WorldDef def;
  def.relaxIterations = relaxIterations;
  World w(def);
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

// More relax passes must not make it worse. The middle block of a layer shares the load above
// with the two beside it in a split the rigid contacts leave open; when a loaded support could
// close a micrometre gap, each pass handed load to whichever block stood higher, the target
// came to carry up to 76 % (even: 33 %) and its sliding friction took layer 3 along (2-12
// passes failed).
TEST(Manipulation, TheJengaPushDoesNotDependOnTheRelaxCount) {
  for (int passes : {2, 4, 8, 12}) {
    double pushed = 0.0;
    const std::vector<Vec3> with = runTower(true, pushed, passes);
    EXPECT_GT(pushed, 0.035) << passes << " relax passes";
    for (size_t i = 0; i < with.size(); ++i) {
      if (i != 7) {
        EXPECT_LT(with[i].norm(), 0.005) << "block " << i << ", " << passes << " passes";
      }
    }
  }
}

}  // namespace
}  // namespace grip

namespace grip {
namespace {

using namespace scenarios;

// Thumb and index pinch a cylinder (a 32-sided prism, axis along z) across its curved side, in
// zero gravity, each fingertip sunk delta = 3 mm. The index fingertip then moves dy along +y
// while the thumb stays: the cylinder rolls between the two sticking fingertips about its own
// axis by the rigid turn that puts both contact points back in line with the fingers' targets,
// atan(dy / (2 (R - delta))), its centre following by dy / 2. (Measured 5-6 % less: the patch
// samples lie on tangent planes, not on the curved surface.)
struct RollRun {
  Vec3 rotation;  // rotation vector of the cylinder over the move
  double centreDy = 0.0;
  int pressing = 0;
};

// A cylinder (radius R, axis z, half length 3 cm, 50 g) in zero gravity, pinched by the thumb
// and index fingertips 3 mm deep: thumb on `thumbFace` (a surface point relative to the centre,
// outward normal `thumbNormal`), index on the opposite side; the fingertip capsules lie along
// `boneAxis`. The index moves dy along +y in 1 s while the thumb stays, then both hold 0.5 s.
RollRun pinchAndMove(double radius, const Vec3& thumbFace, const Vec3& thumbNormal,
                     const Vec3& indexFace, const Vec3& boneAxis, double dy) {
  World w;
  w.setGravity(Vec3::Zero());
  const BodyId cyl = addCylinder(w, radius, 0.03, 0.05, Vec3(0.0, 0.5, 0.0));
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  const Vec3 c = w.centerOfMass(cyl);
  const double depth = 0.003;
  auto pinch = [&](double y) {
    HandPose p = parkedHand(hd);
    pressBone(p, hd, boneIndex(Finger::Thumb, 2), c + thumbFace, thumbNormal, boneAxis, depth);
    pressBone(p, hd, boneIndex(Finger::Index, 2), c + indexFace + Vec3(0, y, 0), -thumbNormal,
              boneAxis, depth);
    ix.setHandPose(h, p);
  };
  for (int i = 0; i < 20; ++i) {
    pinch(0.0);
    ix.step(w, kDt);
  }
  const Quat q0 = w.pose(cyl).q;
  const Vec3 p0 = w.centerOfMass(cyl);
  for (int i = 1; i <= 60; ++i) {
    pinch(dy * i / 60.0);
    ix.step(w, kDt);
  }
  for (int i = 0; i < 30; ++i) {
    pinch(dy);
    ix.step(w, kDt);
  }
  const Eigen::AngleAxisd turn(w.pose(cyl).q * q0.conjugate());
  return {turn.angle() * turn.axis(), w.centerOfMass(cyl).y() - p0.y(),
          ix.stats().pressingContacts};
}

TEST(Manipulation, OneFingerMovingTangentiallySpinsAPinchedCylinder) {
  // The angle follows the finger travel over the diameter: twice the travel, or half the
  // radius, turns it about twice as far.
  for (const auto& [radius, dy] :
       {std::pair{0.02, 0.005}, std::pair{0.02, 0.01}, std::pair{0.015, 0.01}}) {
    const RollRun r = pinchAndMove(radius, -radius * Vec3::UnitX(), -Vec3::UnitX(),
                                   radius * Vec3::UnitX(), Vec3::UnitZ(), dy);
    const double expected = std::atan(dy / (2.0 * (radius - 0.003)));
    EXPECT_NEAR(r.rotation.z(), expected, 0.08 * expected) << radius << " " << dy;  // +z: +y at +x
    EXPECT_LT(std::hypot(r.rotation.x(), r.rotation.y()), 0.02);
    EXPECT_NEAR(r.centreDy, 0.5 * dy, 0.1 * dy);
    EXPECT_EQ(r.pressing, 2);
  }
}

// The same pinch on the cylinder's two flat ends (its axis, z, is the pinch axis; length
// L = 6 cm), the thumb's pad on the axis, the index's 12 mm off it. When the index moves dy
// along y, its friction force has a lever of 12 mm about the pinch axis but of L about the
// thumb's contact: the cylinder does not spin about the pinch axis, it tilts about the thumb
// (about x), by the turn that keeps the index's contact under the finger, atan(dy / (L - 2
// delta)) (measured 5-6 % less, as above), and hardly spins about z.
TEST(Manipulation, OneFingerMovingOnAnEndFaceTiltsThePinchedCylinderAboutTheThumb) {
  const double half = 0.03, offset = 0.012, depth = 0.003;
  for (const double dy : {0.004, 0.008}) {
    const RollRun r = pinchAndMove(0.02, -half * Vec3::UnitZ(), -Vec3::UnitZ(),
                                   Vec3(offset, 0.0, half), Vec3::UnitX(), dy);
    const Vec3& rot = r.rotation;
    const double expected = std::atan(dy / (2.0 * half - 2.0 * depth));
    EXPECT_NEAR(-rot.x(), expected, 0.08 * expected) << dy;  // -x: +y at +z
    EXPECT_LT(std::abs(rot.z()), 0.15 * expected) << dy;
    EXPECT_LT(std::abs(rot.y()), 0.01) << dy;
    // Its centre follows halfway, as a body turning about the thumb's end.
    EXPECT_NEAR(r.centreDy, 0.5 * dy, 0.1 * dy) << dy;
    EXPECT_EQ(r.pressing, 2);
  }
}

}  // namespace
}  // namespace grip
