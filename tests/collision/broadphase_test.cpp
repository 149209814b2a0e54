// The broadphase against the definition: every pair of overlapping boxes with an active
// member, once, sorted, and nothing else.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <thread>

#include "collision/broadphase.hpp"

namespace grip {
namespace {

using Pairs = std::vector<std::pair<uint32_t, uint32_t>>;

Pairs bruteForce(const std::vector<Aabb>& boxes, const std::vector<uint8_t>& active) {
  Pairs pairs;
  for (uint32_t i = 0; i < boxes.size(); ++i)
    for (uint32_t j = i + 1; j < boxes.size(); ++j) {
      const Aabb &a = boxes[i], &b = boxes[j];
      bool overlap = active[i] || active[j];
      for (int k = 0; k < 3; ++k) overlap &= a.min[k] <= b.max[k] && b.min[k] <= a.max[k];
      if (overlap) pairs.emplace_back(i, j);
    }
  return pairs;
}

Aabb boxAt(const Vec3& centre, const Vec3& half) {
  return {centre - half, centre + half};
}

TEST(Broadphase, APileFindsExactlyTheOverlappingPairs) {
  // Cubes in a 12 x 12 x 8 lattice with jitter, so rows and layers touch their neighbours.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.03, 0.03);
  std::vector<Aabb> boxes;
  std::vector<uint8_t> active;
  for (int x = 0; x < 12; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 12; ++z) {
        const Vec3 c(0.21 * x + jitter(rng), 0.2 * y + jitter(rng), 0.21 * z + jitter(rng));
        boxes.push_back(boxAt(c, Vec3::Constant(0.1 + 0.02 * jitter(rng))));
        active.push_back((x + y + z) % 5 != 0);
      }
  boxes.push_back({Vec3(-1e15, -1e15, -1e15), Vec3(1e15, 0.0, 1e15)});  // the ground
  active.push_back(0);
  SweepBroadphase broadphase;
  Pairs pairs;
  broadphase.findPairs(boxes, active, pairs);
  const Pairs expected = bruteForce(boxes, active);
  EXPECT_GT(expected.size(), 2000u);
  EXPECT_EQ(pairs, expected);
  // Again and again after moves (the sweep keeps its state between calls), one box stretched
  // as a fast one is.
  for (int call = 0; call < 3; ++call) {
    for (Aabb& b : boxes) b.min.x() += 0.05, b.max.x() += 0.05;
    boxes[5] = boxAt(Vec3(1.0, 0.5, 1.0), Vec3(0.3, 0.3 + 2.0 * call, 0.3));
    broadphase.findPairs(boxes, active, pairs);
    EXPECT_EQ(pairs, bruteForce(boxes, active)) << "call " << call;
  }
}

TEST(Broadphase, TheSweepsTwoHalvesGiveTheSamePairsInEitherOrderOrAtOnce) {
  // The sweep's halves may run on two threads (World::Impl::collide): run in reverse order and
  // at once on two threads, they give the pairs of the definition, each half called once.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  std::vector<Aabb> boxes;
  std::vector<uint8_t> active;
  for (int i = 0; i < 900; ++i) {
    boxes.push_back(boxAt(Vec3(u(rng), 0.3 * u(rng), u(rng)), Vec3::Constant(0.1)));
    active.push_back(i % 7 != 0);
  }
  boxes.push_back({Vec3(-1e15, -1e15, -1e15), Vec3(1e15, 0.0, 1e15)});  // the ground
  active.push_back(0);
  const Pairs expected = bruteForce(boxes, active);
  EXPECT_GT(expected.size(), 2000u);
  int calls[2] = {0, 0};
  const SweepBroadphase::TwoParts reversed = [&](const std::function<void(int)>& part) {
    part(1), ++calls[1];
    part(0), ++calls[0];
  };
  const SweepBroadphase::TwoParts atOnce = [&](const std::function<void(int)>& part) {
    std::thread helper([&] { part(1); });
    part(0);
    helper.join();
    ++calls[0], ++calls[1];
  };
  SweepBroadphase broadphase;
  Pairs pairs;
  for (int call = 0; call < 4; ++call) {
    broadphase.findPairs(boxes, active, pairs, call % 2 ? atOnce : reversed);
    EXPECT_EQ(pairs, expected) << "call " << call;
  }
  EXPECT_EQ(calls[0], 4);
  EXPECT_EQ(calls[1], 4);
}

TEST(Broadphase, WideInfiniteAndInvalidBoxesArePairedByDefinition) {
  // A plane's box is infinite, a table spans many strips, a NaN box overlaps nothing, and far
  // bodies make the strips sparse.
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::vector<Aabb> boxes;
  std::vector<uint8_t> active;
  boxes.push_back({Vec3(-inf, -inf, -inf), Vec3(inf, 0.0, inf)});  // a ground plane
  active.push_back(0);
  boxes.push_back(boxAt(Vec3(0, 0.5, 0), Vec3(3.0, 0.05, 3.0)));  // a table
  active.push_back(0);
  boxes.push_back(boxAt(Vec3(0, 0.5, 0), Vec3(2.5, 0.05, 2.5)));  // a plank across the strips
  active.push_back(1);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  boxes.push_back({Vec3(nan, 0, 0), Vec3(1, 1, 1)});
  active.push_back(1);
  for (int i = 0; i < 300; ++i) {
    boxes.push_back(boxAt(Vec3(u(rng), u(rng) * 0.2, u(rng)), Vec3(0.1, 0.1, 0.15)));
    active.push_back(i % 3 != 0);
  }
  boxes.push_back(boxAt(Vec3(1e6, 0, 1e6), Vec3::Constant(0.1)));  // far away
  active.push_back(1);
  boxes.push_back(boxAt(Vec3(1e6, 0, 1e6 + 0.1), Vec3::Constant(0.1)));
  active.push_back(1);
  SweepBroadphase broadphase;
  Pairs pairs;
  broadphase.findPairs(boxes, active, pairs);
  const Pairs expected = bruteForce(boxes, active);
  EXPECT_EQ(pairs, expected);
  EXPECT_NE(std::find(pairs.begin(), pairs.end(), std::make_pair(1u, 2u)), pairs.end());
  const uint32_t far = static_cast<uint32_t>(boxes.size() - 2);
  EXPECT_NE(std::find(pairs.begin(), pairs.end(), std::make_pair(far, far + 1)), pairs.end());
  for (const auto& p : pairs) EXPECT_TRUE(p.first != 3u && p.second != 3u);
}

TEST(Broadphase, FewProxiesAndManyGiveTheSamePairs) {
  // Up to 16 proxies every pair is tested directly, above that the sweep runs: every count
  // around the switch gives the definition's pairs (a plane, a NaN box and inactive proxies
  // among them).
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::vector<Aabb> all;
  std::vector<uint8_t> allActive;
  all.push_back({Vec3(-inf, -inf, -inf), Vec3(inf, 0.0, inf)});
  allActive.push_back(0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  all.push_back({Vec3(nan, 0, 0), Vec3(1, 1, 1)});
  allActive.push_back(1);
  for (int i = 0; i < 40; ++i) {
    all.push_back(boxAt(Vec3(u(rng), u(rng), u(rng)), Vec3::Constant(0.15)));
    allActive.push_back(i % 4 != 0);
  }
  SweepBroadphase broadphase;
  Pairs pairs;
  for (size_t n = 0; n <= all.size(); ++n) {
    const std::vector<Aabb> boxes(all.begin(), all.begin() + static_cast<long>(n));
    const std::vector<uint8_t> active(allActive.begin(), allActive.begin() + static_cast<long>(n));
    broadphase.findPairs(boxes, active, pairs);
    EXPECT_EQ(pairs, bruteForce(boxes, active)) << n << " proxies";
  }
}

TEST(Broadphase, FewActiveProxiesAmongManyGiveTheSamePairs) {
  // A settled pile with a few awake boxes among the sleeping ones: up to 16 active proxies each
  // is tested against every proxy, above that the sweep runs. Every active count around the
  // switch, one call after another on the same broadphase (the sweep keeps its order between
  // calls), gives the definition's pairs; two active boxes that overlap pair once.
  constexpr double inf = std::numeric_limits<double>::infinity();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02);
  std::vector<Aabb> boxes;
  boxes.push_back({Vec3(-inf, -inf, -inf), Vec3(inf, 0.0, inf)});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  boxes.push_back({Vec3(nan, 0, 0), Vec3(1, 1, 1)});
  for (int x = 0; x < 10; ++x)
    for (int y = 0; y < 5; ++y)
      for (int z = 0; z < 10; ++z)
        boxes.push_back(boxAt(Vec3(0.2 * x + jitter(rng), 0.1 + 0.2 * y, 0.2 * z + jitter(rng)),
                              Vec3::Constant(0.105)));
  std::vector<uint32_t> order(boxes.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::shuffle(order.begin(), order.end(), rng);
  SweepBroadphase broadphase;
  Pairs pairs;
  for (size_t awake : {0, 1, 2, 15, 16, 17, 40, 16, 3}) {
    std::vector<uint8_t> active(boxes.size(), 0);
    for (size_t k = 0; k < awake; ++k) active[order[k]] = 1;
    broadphase.findPairs(boxes, active, pairs);
    EXPECT_EQ(pairs, bruteForce(boxes, active)) << awake << " active";
    EXPECT_EQ(pairs.empty(), awake == 0) << awake << " active";
  }
}

TEST(Broadphase, IdenticalBoxesAllPair) {
  // Zero median width along every axis: all boxes are points at one place.
  std::vector<Aabb> boxes(20, Aabb{Vec3::Zero(), Vec3::Zero()});
  std::vector<uint8_t> active(20, 1);
  SweepBroadphase broadphase;
  Pairs pairs;
  broadphase.findPairs(boxes, active, pairs);
  EXPECT_EQ(pairs.size(), 20u * 19u / 2u);
  EXPECT_EQ(pairs, bruteForce(boxes, active));
}

}  // namespace
}  // namespace grip
