// Determinism: the same scene run twice gives the same hash, worlds do not disturb each
// other, and golden hashes catch any change in behaviour.
#include <gtest/gtest.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <map>
#include <thread>
#include <vector>

#include "scenes.hpp"

using namespace grip;
using namespace grip::determinism;

namespace {

std::string hex(uint64_t h) {
  char s[17];
  std::snprintf(s, sizeof s, "%016" PRIx64, h);
  return s;
}

// The hashes of hash_scenes at the last deliberate change of behaviour (g++ and clang++,
// Release, x86-64; see docs/determinism.md).
// One scene a line (a script rewrites this table).
// clang-format off
const std::map<std::string, std::string> kGolden = {
    {"pile200", "9bf1c41792bfacf7"},
    {"stack20", "a37773b4306f5d1f"},
    {"ball_into_stack", "2488dc3f58156031"},
    {"incline", "d0bc94462eb0f6f4"},
    {"mixed", "0f9763709662d931"},
};
// clang-format on

}  // namespace

TEST(Determinism, EverySceneTwiceGivesTheSameHash) {
  for (const HashScene& s : hashScenes()) EXPECT_EQ(s.run(), s.run()) << s.name;
}

TEST(Determinism, GoldenHashes) {
  std::string update;
  for (const HashScene& s : hashScenes()) {
    const std::string got = hex(s.run());
    const auto it = kGolden.find(s.name);
    ASSERT_NE(it, kGolden.end()) << "no golden hash for scene " << s.name;
    if (got != it->second) update += "    {\"" + s.name + "\", \"" + got + "\"},\n";
    EXPECT_EQ(got, it->second) << "scene " << s.name << " changed behaviour";
  }
  if (!update.empty())
    ADD_FAILURE() << "The simulation no longer reproduces the golden runs. If the change in "
                     "behaviour is deliberate (a solver or collision change), explain it in "
                     "the commit message and update kGolden in "
                     "tests/determinism/determinism_test.cpp with these lines (also printed by "
                     "build/tests/hash_scenes):\n"
                  << update;
}

TEST(Determinism, WorldsSteppedInTurnDoNotDisturbEachOther) {
  // Scratch memory shared between worlds (thread_local buffers) must not leak state.
  auto build = [](World& w) {
    scenes::addGround(w);
    scenes::addBoxPile(w, 60);
  };
  World alone;
  build(alone);
  for (int i = 0; i < 120; ++i) alone.step(1.0 / 60.0);
  World a, b;
  build(a);
  build(b);
  scenes::addBoxStack(b, 5, 0.1, 1.0, Vec3(3, 0, 3));  // b differs: more bodies, more contacts
  for (int i = 0; i < 120; ++i) a.step(1.0 / 60.0), b.step(1.0 / 60.0);
  EXPECT_EQ(a.stateHash(), alone.stateHash());
}

TEST(Determinism, HashSeesTheSmallestChange) {
  // One ulp in one coordinate of one body gives a different run: the golden test is sharp.
  auto run = [](double nudge) {
    World w;
    scenes::addGround(w);
    const std::vector<BodyId> boxes = scenes::addBoxPile(w, 30);
    const Vec3 p = w.pose(boxes[7]).p;
    w.setPose(boxes[7], Vec3(std::nextafter(p.x(), p.x() + nudge), p.y(), p.z()),
              w.pose(boxes[7]).q);
    return runHash(w, 60);
  };
  EXPECT_NE(run(0.0), run(1.0));
}

// With 256 moving bodies or more, the narrowphase and the solve run in two regions, one per
// thread, each writing only its own output, with the manifolds across the cut after both: the
// run must be the same bit for bit with any number of threads. A 400-box pile (two regions
// while it falls and settles) with a sensor in it (sensor pairs go through the regions too).
TEST(Determinism, AnyNumberOfThreadsGivesTheSameRun) {
  auto run = [](int threads) {
    WorldDef def;
    def.workerThreads = threads;
    World w(def);
    scenes::addGround(w);
    scenes::addBoxPile(w, 400);
    BodyDef sensor;
    sensor.type = BodyType::Static;
    sensor.isSensor = true;
    sensor.shape = Shape::box(Vec3(0.5, 0.3, 0.5));
    sensor.position = Vec3(0, 0.3, 0);
    w.createBody(sensor);
    StateHash h;
    int sensorEvents = 0, contactEvents = 0, splitSteps = 0;
    for (int i = 0; i < 150; ++i) {
      w.step(1.0 / 60.0);
      h.add(w.stateHash());
      splitSteps += w.stats().solveRegions == 2;
      sensorEvents += static_cast<int>(w.sensorBeginEvents().size() + w.sensorEndEvents().size());
      contactEvents += static_cast<int>(w.contactBeginEvents().size());
      for (const SensorEvent& e : w.sensorBeginEvents()) h.add(uint64_t{e.visitor.index});
    }
    EXPECT_GT(sensorEvents, 10) << "the sensor saw nothing: the test does not test it";
    EXPECT_GT(contactEvents, 1000);
    EXPECT_EQ(splitSteps, 150) << "the solve did not run in two regions";
    return h.value();
  };
  const uint64_t one = run(1);
  EXPECT_EQ(run(2), one);
  EXPECT_EQ(run(3), one);
}

// Queries are const and may run on several threads at once between steps (as Jolt's and
// Box2D's): two threads asking at once, while their first queries build the query tree, get
// what one thread gets asking alone in a copy of the world.
TEST(Determinism, AnyNumberOfThreadsMayQueryAtOnce) {
  World w;
  scenes::addGround(w);
  scenes::addBoxPile(w, 300);
  for (int i = 0; i < 60; ++i) w.step(1.0 / 60.0);
  auto ask = [](const World& view, std::vector<uint32_t>& out) {
    const ShapePtr ball = Shape::sphere(0.3);
    std::vector<OverlapHit> hits;
    for (int q = 0; q < 200; ++q) {
      const double x = -1.5 + 0.015 * q;
      view.overlap(*ball, Transform{Vec3(x, 0.3, 0.0), Quat::Identity()}, 0.0, hits);
      for (const OverlapHit& h : hits) out.push_back(h.body.index);
      const auto ray = view.rayCast(Vec3(x, 3.0, 0.2), Vec3(0, -1, 0), 5.0);
      out.push_back(ray ? ray->body.index : ~0u);
    }
  };
  const World alone(w);
  std::vector<uint32_t> one, two, single;
  std::thread other([&] { ask(w, two); });
  ask(w, one);
  other.join();
  ask(alone, single);
  EXPECT_GT(one.size(), 400u);
  EXPECT_EQ(one, single);
  EXPECT_EQ(two, single);
}
