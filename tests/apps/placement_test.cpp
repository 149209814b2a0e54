// `grip eval placement` (thesis 5.2): the table has both methods, the Coulomb method places the
// cube more accurately than the kinematic baseline, and the same seed gives the same numbers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

#include "scene/placement.hpp"

namespace grip::scene {
namespace {

PlacementDef small(uint64_t seed) {
  PlacementDef d;
  d.trials = 4;
  d.seed = seed;
  return d;
}

TEST(Placement, TheTableHasBothMethodsAndCoulombIsMoreAccurate) {
  const PlacementDef d = small(1);
  const std::vector<PlacementMethod> r = evaluatePlacement(d);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].method, "coulomb");
  EXPECT_EQ(r[1].method, "kinematic");
  for (const PlacementMethod& m : r) {
    ASSERT_EQ(m.trials.size(), 4u);
    for (const PlacementTrial& t : m.trials) {
      EXPECT_GT((t.target - t.start).norm(), 0.04);  // different squares
      EXPECT_GE(t.grasps, 1);                        // the first move is a grasp-and-place
      EXPECT_LT(t.error, 0.02) << m.method;          // it got there (within 2 cm)
      EXPECT_GT(t.time, 1.0);
      EXPECT_LE(t.time, d.timeLimit + 5.0);
    }
    const auto [lo, hi] = std::minmax_element(
        m.trials.begin(), m.trials.end(),
        [](const PlacementTrial& a, const PlacementTrial& b) { return a.error < b.error; });
    EXPECT_GE(m.error.median, lo->error);
    EXPECT_LE(m.error.median, hi->error);
  }
  // Same layouts for both methods.
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(r[0].trials[i].target, r[1].trials[i].target);
  EXPECT_LT(r[0].error.mean, r[1].error.mean);

  const std::string table = placementTable(d, r);
  EXPECT_NE(table.find("positioning error / mm"), std::string::npos) << table;
  EXPECT_NE(table.find("\ncoulomb "), std::string::npos) << table;
  EXPECT_NE(table.find("\nkinematic "), std::string::npos) << table;
  EXPECT_NE(table.find(" ± "), std::string::npos) << table;
}

TEST(Placement, TheSameSeedGivesTheSameNumbers) {
  const auto a = evaluatePlacement(small(5)), b = evaluatePlacement(small(5)),
             c = evaluatePlacement(small(6));
  for (size_t m = 0; m < 2; ++m) {
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(a[m].trials[i].error, b[m].trials[i].error);  // bit for bit
      EXPECT_EQ(a[m].trials[i].time, b[m].trials[i].time);
    }
  }
  EXPECT_NE(a[0].error.mean, c[0].error.mean);
  EXPECT_NE(a[0].trials[0].target, c[0].trials[0].target);
}

TEST(Placement, WithoutNoiseThePinchStillLandsWithinAMillimetre) {
  PlacementDef d = small(2);
  d.noise = 0.0;
  const auto r = evaluatePlacement(d);
  EXPECT_LT(r[0].error.mean, 0.001);
}

TEST(Placement, SummaryIsMeanSampleSdAndMedian) {
  const Summary s = summarize({1.0, 2.0, 3.0, 10.0});
  EXPECT_DOUBLE_EQ(s.mean, 4.0);
  EXPECT_DOUBLE_EQ(s.sd, std::sqrt((9.0 + 4.0 + 1.0 + 36.0) / 3.0));
  EXPECT_DOUBLE_EQ(s.median, 2.5);
}

TEST(Placement, BadSettingsAreRefusedByName) {
  PlacementDef d;
  d.trials = 0;
  try {
    evaluatePlacement(d);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "trials: must be positive (got 0)");
  }
  d = PlacementDef{};
  d.noise = std::nan("");
  EXPECT_THROW(evaluatePlacement(d), Error);
}

}  // namespace
}  // namespace grip::scene
