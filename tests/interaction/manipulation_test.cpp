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

// A tower of 6 layers of 3 blocks (7.5 x 1.5 x 2.5 cm, 14 g, wood on wood mu 0.4), layers
// crossed. A fingertip pushes the middle block of the third layer 4.5 cm out along its length.
TEST(Manipulation, OneJengaBlockIsPushedOutWhileTheTowerStands) {
  World w;
  addFloor(w, 0.6, 0.5);
  const double len = 0.075, height = 0.015, width = 0.025, mass = 0.014;
  std::vector<BodyId> blocks;
  BodyId target;
  for (int layer = 0; layer < 6; ++layer) {
    const double y = 0.5 * height + layer * height;
    for (int k = -1; k <= 1; ++k) {
      const bool alongX = layer % 2 == 0;
      const Vec3 half = alongX ? Vec3(0.5 * len, 0.5 * height, 0.5 * width)
                               : Vec3(0.5 * width, 0.5 * height, 0.5 * len);
      const Vec3 at = alongX ? Vec3(0.0, y, k * width) : Vec3(k * width, y, 0.0);
      const BodyId b = addBox(w, half, mass, at, Quat::Identity(), 0.4, 0.35);
      blocks.push_back(b);
      if (layer == 2 && k == 0) target = b;
    }
  }
  for (int i = 0; i < 60; ++i) w.step(kDt);  // settle
  std::vector<Vec3> start;
  for (BodyId b : blocks) start.push_back(w.centerOfMass(b));

  Interaction ix;
  HandDef hd;
  hd.scale = 0.8;  // a slim finger for a 15 mm slot
  const HandId h = ix.addHand(hd);
  const int tip = boneIndex(Finger::Index, 2);
  const Vec3 face(0.5 * len, w.centerOfMass(target).y(), 0.0);
  auto finger = [&](double depth) {
    HandPose p = parkedHand(hd);
    // Fingertip pointing -x into the end face of the block.
    const double r = hd.scale * hd.fingers[1].radius[2];
    const double axisHalf = 0.5 * hd.scale * hd.fingers[1].length[2] - 0.5 * r;
    p.bones[tip].q = Quat::FromTwoVectors(Vec3::UnitY(), -Vec3::UnitX());
    p.bones[tip].p = face + Vec3(axisHalf + r - depth, 0.0, 0.0);
    ix.setHandPose(h, p);
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
  const double moved = start[7].x() - w.centerOfMass(target).x();
  EXPECT_GT(moved, 0.035);
  for (size_t i = 0; i < blocks.size(); ++i) {
    if (blocks[i] == target) continue;
    EXPECT_LT((w.centerOfMass(blocks[i]) - start[i]).norm(), 0.005) << "block " << i;
  }
}

}  // namespace
}  // namespace grip
