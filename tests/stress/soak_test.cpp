// A resting scene soaked for 200k steps (almost an hour at 60 Hz) with sleeping off: nothing
// drifts, energy never grows, the contact count and the heap stay flat.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "stress_util.hpp"

using namespace grip;
using namespace grip::stress;

namespace {

// Bytes of heap in use (glibc); 0 where unknown.
size_t heapInUse() {
#if defined(__GLIBC__) && (__GLIBC__ > 2 || __GLIBC_MINOR__ >= 33)
  return mallinfo2().uordblks;
#else
  return 0;
#endif
}

}  // namespace

TEST(Soak, RestingSceneTwoHundredThousandSteps) {
  WorldDef def;
  def.enableSleep = false;
  World w(def);
  scenes::addGround(w);
  std::vector<BodyId> bodies = scenes::addBoxStack(w, 3, 0.1, 1.0, Vec3(0.5, 0, 0));
  bodies.push_back(addBody(w, Shape::sphere(0.05), Vec3(-0.5, 0.05, 0)));
  BodyDef capsule;
  capsule.shape = Shape::capsule(0.03, 0.1);  // lying along X
  capsule.position = Vec3(0, 0.03, 0.5);
  capsule.orientation = Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
  bodies.push_back(w.createBody(capsule));
  bodies.push_back(addBody(w, Shape::box(Vec3(0.2, 0.05, 0.1)), Vec3(0, 0.05, -0.5), 5.0));

  const double dt = 1.0 / 60.0;
  for (int i = 0; i < 120; ++i) w.step(dt);  // settle for 2 s
  ASSERT_TRUE(allFinite(w));
  std::vector<Transform> settled;
  for (BodyId b : bodies) settled.push_back(w.pose(b));
  const double e0 = totalEnergy(w);
  const int manifolds0 = w.stats().manifolds, points0 = w.stats().contactPoints;
  const size_t heap0 = heapInUse();

  const int steps = 200000;
  double drift = 0.0, turn = 0.0, energyGain = 0.0;
  int maxManifolds = 0, maxPoints = 0;
  bool finite = true;
  for (int i = 0; i < steps; ++i) {
    w.step(dt);
    if (i % 100 != 0 && i != steps - 1) continue;
    for (size_t k = 0; k < bodies.size(); ++k) {
      const Transform t = w.pose(bodies[k]);
      drift = std::max(drift, (t.p - settled[k].p).norm());
      turn = std::max(turn, t.q.angularDistance(settled[k].q));
    }
    energyGain = std::max(energyGain, totalEnergy(w) - e0);
    maxManifolds = std::max(maxManifolds, w.stats().manifolds);
    maxPoints = std::max(maxPoints, w.stats().contactPoints);
    finite = finite && allFinite(w);
  }
  const size_t heap1 = heapInUse();
  std::printf(
      "soak: drift %.3g mm, turn %.3g rad, energy gain %.3g J, manifolds %d -> %d, "
      "points %d -> %d, heap %zu -> %zu bytes\n",
      drift * 1e3, turn, energyGain, manifolds0, maxManifolds, points0, maxPoints, heap0, heap1);
  ASSERT_TRUE(finite);
  EXPECT_LT(drift, 1e-3) << "a resting body moved " << drift * 1e3 << " mm";
  EXPECT_LT(turn, 1e-2) << "a resting body turned " << turn << " rad";
  EXPECT_LT(energyGain, 1e-6) << "energy grew by " << energyGain << " J";
  EXPECT_LE(maxManifolds, manifolds0) << "contact manifolds grew";
  EXPECT_LE(maxPoints, points0) << "contact points grew";
  EXPECT_LE(heap1, heap0 + 4096) << "the heap grew while nothing changed";
}
