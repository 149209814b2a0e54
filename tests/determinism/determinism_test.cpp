// Determinism: the same scene run twice gives the same hash, worlds do not disturb each
// other, and golden hashes catch any change in behaviour.
#include <gtest/gtest.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <functional>
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
    {"pile200", "80b91b5f06019e9c"},
    {"stack20", "b71d93580db55b78"},
    {"ball_into_stack", "af72823330f3f9e5"},
    {"incline", "f6bdb08aca5733a9"},
    {"mixed", "5ea25e772fe94fb0"},
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

// Two worlds that hash alike step alike: the hash sees what each setter changes, not only the
// motion, and the contacts' warm-start memory. A resting box hinged to a static post and a
// free one (kept from sleep, so that the wake every setter does changes nothing else), hashed after
// each change to a copy: every change differs from the original, and the same change made to
// two copies hashes alike.
TEST(Determinism, HashSeesWhatTheSettersChange) {
  World w;
  const BodyId ground = scenes::addGround(w);
  BodyDef d;
  d.shape = Shape::box(Vec3::Constant(0.1));
  d.position = Vec3(0, 0.1, 0);
  d.allowSleep = false;
  const BodyId box = w.createBody(d);
  d.position = Vec3(-1.0, 0.1, 0);
  const BodyId free = w.createBody(d);  // (the hinged box may not stop being dynamic)
  d.type = BodyType::Static;
  d.position = Vec3(0.3, 0.1, 0);
  const BodyId post = w.createBody(d);
  JointDef j;
  j.type = JointType::Hinge;
  j.a = post, j.b = box, j.anchor = Vec3(0.2, 0.1, 0), j.axis = Vec3::UnitZ();
  const JointId hinge = w.createJoint(j);
  for (int i = 0; i < 30; ++i) w.step(1.0 / 60.0);
  const uint64_t before = w.stateHash();
  const std::vector<std::pair<const char*, std::function<void(World&)>>> changes = {
      {"setMaterial",
       [&](World& x) {
         x.setMaterial(box, MaterialDef{0.9, 0.8, 0.1, 1000.0});
       }},
      {"setBodyType", [&](World& x) { x.setBodyType(free, BodyType::Kinematic); }},
      {"setMass", [&](World& x) { x.setMass(box, 2.0); }},
      {"setGravityScale", [&](World& x) { x.setGravityScale(box, 0.5); }},
      {"setDamping", [&](World& x) { x.setDamping(box, 0.1, 0.0); }},
      {"setAllowSleep", [&](World& x) { x.setAllowSleep(box, true); }},
      {"setCollisionFilter",
       [&](World& x) {
         x.setCollisionFilter(box, {2, ~uint64_t{0}, 0});
       }},
      {"setGravity", [&](World& x) { x.setGravity(Vec3(0, -9.0, 0)); }},
      {"setJointLimits", [&](World& x) { x.setJointLimits(hinge, true, -0.5, 0.5); }},
      {"setJointMotor", [&](World& x) { x.setJointMotor(hinge, true, 0.0, 1.0); }},
      {"setJointSpring", [&](World& x) { x.setJointSpring(hinge, true, 2.0, 1.0, 0.0); }},
      {"a contact's impulse",
       [&](World& x) {  // the contacts are all that differs: from a world stepped with less g
         World other(x);
         other.setGravity(Vec3(0, -5.0, 0));
         other.step(1.0 / 60.0);
         x.step(1.0 / 60.0);
         ASSERT_EQ(other.pose(box).p, x.pose(box).p);  // resting: the same motion
         ASSERT_EQ(other.pose(box).q.coeffs(), x.pose(box).q.coeffs());
         ASSERT_EQ(other.linearVelocity(box), x.linearVelocity(box));
         ASSERT_EQ(other.angularVelocity(box), x.angularVelocity(box));
         ASSERT_NE(other.contactForce(ground, box), x.contactForce(ground, box));
         other.setGravity(x.gravity());
         x = other;
       }},
  };
  for (const auto& [name, change] : changes) {
    World one(w), two(w);
    change(one), change(two);
    EXPECT_NE(one.stateHash(), before) << name;
    EXPECT_EQ(one.stateHash(), two.stateHash()) << name;
  }
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
