// A dropped pile of 1000 boxes comes to rest and falls asleep. Its boxes tremble about their
// poses (measured: about a hundred at any instant turning faster than the 0.05 rad/s sleep
// speed), so sleep reads each body's mean velocity over its calm time; with the instant's
// velocity alone the pile's one island of 920 boxes was still awake after 30 s.
#include <gtest/gtest.h>

#include "stress_util.hpp"

using namespace grip;

TEST(Sleep, ADroppedThousandBoxPileFallsAsleepWithinTwentySeconds) {
  World w;
  scenes::addGround(w);
  const std::vector<BodyId> boxes = scenes::addBoxPile(w, 1000);
  int steps = 0;
  while (steps < 20 * 60 && (steps == 0 || w.stats().awakeBodies > 0)) {
    w.step(1.0 / 60.0);
    ++steps;
  }
  ASSERT_EQ(w.stats().awakeBodies, 0) << "still awake after " << steps / 60.0 << " s";
  std::vector<Transform> poses;
  for (BodyId b : boxes) {
    EXPECT_FALSE(w.isAwake(b));
    EXPECT_GT(w.centerOfMass(b).y(), 0.0);
    poses.push_back(w.pose(b));
  }
  // Asleep means at rest: another second moves nothing and costs no contact solving.
  for (int i = 0; i < 60; ++i) w.step(1.0 / 60.0);
  EXPECT_EQ(w.contactConstraintCount(), 0);
  for (size_t i = 0; i < boxes.size(); ++i) {
    EXPECT_EQ(w.pose(boxes[i]).p, poses[i].p);
    EXPECT_EQ(w.pose(boxes[i]).q.coeffs(), poses[i].q.coeffs());
  }
}
