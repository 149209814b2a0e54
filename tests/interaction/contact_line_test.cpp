// A fingertip lying flat along a face touches it along a line. The narrowphase sometimes reports
// such a capsule-box pair with a single point (GJK's closest pair, an arbitrary point of the
// line, often its end on the face's edge); the contact must still be anchored in the middle of
// the line, or the two patches of a pinch sit on opposite edges and roll the body (issue 5:
// jenga_two_hands threw the pulled block).
#include <gtest/gtest.h>

#include <cmath>

#include "interaction/interaction.hpp"
#include "interaction/scenarios.hpp"

namespace grip {
namespace {

using namespace scenarios;

// A Jenga block (75 x 15 x 25 mm, 14 g): its z faces are 15 mm tall, narrower than an adult
// thumb's distal capsule (20.5 mm axis + 9.5 mm radius).
const Vec3 kBlockHalf(0.0375, 0.0075, 0.0125);
constexpr double kBlockMass = 0.014;

Quat tilt(double aboutXDeg, double aboutYDeg) {
  return Quat(Eigen::AngleAxisd(aboutXDeg * kPi / 180.0, Vec3::UnitX()) *
              Eigen::AngleAxisd(aboutYDeg * kPi / 180.0, Vec3::UnitY()));
}

// Where along the block's height (its local y, from the face centre) the thumb's patch is
// anchored, the thumb upright on the -z face 2 cm from the block's centre.
double anchorHeight(const Quat& q) {
  World w;
  w.setGravity(Vec3::Zero());
  const Vec3 c(0.0, 0.5, 0.0);
  const BodyId block = addBox(w, kBlockHalf, kBlockMass, c, q);
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  HandPose p = parkedHand(hd);
  const Vec3 face = c + q * Vec3(-0.02, 0.0, -kBlockHalf.z());
  pressBone(p, hd, boneIndex(Finger::Thumb, 2), face, -Vec3::UnitZ(), Vec3::UnitY(), 0.003);
  ix.setHandPose(h, p);
  ix.update(w, 1.0 / 60.0);
  const std::vector<HandContactInfo> cs = ix.contacts();
  EXPECT_EQ(cs.size(), 1u);
  if (cs.size() != 1 || !cs[0].pressing) return kBlockHalf.y();
  return (w.pose(block).rotateInverse(cs[0].point - w.pose(block).p)).y();
}

TEST(ContactLine, AFingertipAlongANarrowFaceIsAnchoredAtTheMiddleOfTheLine) {
  // Tilts of a few tenths of a degree, as a block pushed out of a tower has: the line of contact
  // spans the whole 15 mm face; its middle is the face's mid-height (an edge is 7.5 mm away).
  for (double ax : {-0.4, -0.2, 0.0, 0.2, 0.4}) {
    for (double ay : {-0.3, 0.0, 0.3}) {
      EXPECT_LT(std::abs(anchorHeight(tilt(ax, ay))), 0.3e-3) << "tilt " << ax << ", " << ay;
    }
  }
}

TEST(ContactLine, ATiltedFingertipTouchingWithItsEndKeepsTheEnd) {
  // A capsule at 30 degrees to the face touches it with its end cap: the contact stays there
  // (the middle of the line is only for a bone lying along the face).
  World w;
  w.setGravity(Vec3::Zero());
  const BodyId cube = addBox(w, Vec3::Constant(0.05), 0.2, Vec3(0, 0.5, 0));
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  HandPose p = parkedHand(hd);
  const int thumb = boneIndex(Finger::Thumb, 2);
  const Vec3 axis = Vec3(0.0, std::sin(kPi / 6.0), std::cos(kPi / 6.0));
  pressBone(p, hd, thumb, Vec3(0, 0.55, 0), Vec3::UnitY(), axis, 0.002);
  // pressBone centres the capsule on the point; move it so that its lower end cap touches.
  const double hh = makeHandShapes(hd).bones[thumb]->halfHeight();
  p.bones[thumb].p += hh * axis;
  ix.setHandPose(h, p);
  ix.update(w, 1.0 / 60.0);
  const std::vector<HandContactInfo> cs = ix.contacts();
  ASSERT_EQ(cs.size(), 1u);
  EXPECT_EQ(cs[0].body, cube);
  // The end cap's lowest point: the capsule's lower axis end, one radius down (within 1 mm).
  const Vec3 end = p.bones[thumb].p - hh * axis;
  EXPECT_LT((cs[0].point - Vec3(end.x(), 0.55, end.z())).norm(), 1e-3);
}

TEST(ContactLine, APinchedJengaBlockHangsWithoutRolling) {
  // Thumb and index (adult size, upright) pinch a free block 5 mm deep near one end, as the
  // left hand of jenga_two_hands does once the block is out of the tower; the block starts
  // tilted 0.3 degrees about its long axis. The pinch holds it: it tips about the pinch axis
  // under its own weight (torsional friction of the patches), but must not roll about its long
  // axis, which the line through two centred contacts cannot drive.
  World w;
  const Vec3 c(0.0, 0.5, 0.0);
  const BodyId block = addBox(w, kBlockHalf, kBlockMass, c, tilt(0.3, 0.0));
  Interaction ix;
  HandDef hd;
  const HandId h = ix.addHand(hd);
  HandPose p = parkedHand(hd);
  const Vec3 at = c + Vec3(-0.025, 0.0, 0.0);
  pressBone(p, hd, boneIndex(Finger::Thumb, 2), at - kBlockHalf.z() * Vec3::UnitZ(), -Vec3::UnitZ(),
            Vec3::UnitY(), 0.005);
  pressBone(p, hd, boneIndex(Finger::Index, 2), at + kBlockHalf.z() * Vec3::UnitZ(), Vec3::UnitZ(),
            Vec3::UnitY(), 0.005);
  double maxRoll = 0.0;
  for (int i = 0; i < 120; ++i) {
    ix.setHandPose(h, p);
    ix.step(w, 1.0 / 60.0);
    // The block's long axis x stays horizontal-ish under tipping; roll is the turn of its y axis
    // about x: the angle of the local y axis out of the x-y plane.
    const Vec3 y = w.pose(block).rotate(Vec3::UnitY());
    maxRoll = std::max(maxRoll, std::abs(std::asin(std::clamp(y.z(), -1.0, 1.0))));
  }
  EXPECT_LT(maxRoll * 180.0 / kPi, 3.0);
  EXPECT_GT(w.centerOfMass(block).y(), c.y() - 0.01);  // held
  EXPECT_EQ(ix.stats().pressingContacts, 2);
}

}  // namespace
}  // namespace grip
