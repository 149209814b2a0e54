// A resting scene soaked for a million steps (4.6 hours at 60 Hz) with the defaults, sleeping
// included: nothing drifts, energy never grows, and the heap does not grow -- every allocation
// of this program is counted by the replaced global operator new below.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "stress_util.hpp"

namespace {
std::atomic<long long> gAllocations{0}, gFrees{0};
void countedFree(void* p) {
  if (p) gFrees.fetch_add(1, std::memory_order_relaxed);
  std::free(p);
}
}  // namespace

// Counting replacements of the global allocation functions (all sizes and alignments go
// through these two; the others forward to them by the standard's defaults).
void* operator new(std::size_t n) {
  gAllocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  countedFree(p);
}
void operator delete(void* p, std::size_t) noexcept {
  countedFree(p);
}

using namespace grip;
using namespace grip::stress;

TEST(Soak, RestingSceneAMillionStepsSleepingWithoutDriftOrAllocation) {
  World w;  // the defaults: sleeping on
  scenes::addGround(w);
  std::vector<BodyId> bodies = scenes::addBoxStack(w, 5, 0.1, 1.0, Vec3(0.5, 0, 0));
  bodies.push_back(addBody(w, Shape::sphere(0.05), Vec3(-0.5, 0.05, 0)));
  bodies.push_back(addBody(w, Shape::box(Vec3(0.2, 0.05, 0.1)), Vec3(0, 0.05, -0.5), 5.0));
  bodies.push_back(addBody(w, Shape::box(Vec3(0.05, 0.05, 0.05)), Vec3(0, 0.15, -0.5), 0.5));

  const double dt = 1.0 / 60.0;
  for (int i = 0; i < 600; ++i) w.step(dt);  // 10 s: settle and fall asleep
  ASSERT_TRUE(allFinite(w));
  std::vector<Transform> settled;
  for (BodyId b : bodies) settled.push_back(w.pose(b));
  const double e0 = totalEnergy(w);
  ASSERT_EQ(w.stats().awakeBodies, 0) << "the scene did not fall asleep in 10 s";
  const long long live0 = gAllocations - gFrees, allocs0 = gAllocations;

  const auto start = std::chrono::steady_clock::now();
  const int steps = 1'000'000;
  double drift = 0.0, energyGain = 0.0;
  long long maxLive = live0;
  int maxAwake = 0;
  long long stepAllocations = 0;  // inside World::step only (the checks below allocate)
  bool finite = true;
  for (int i = 0; i < steps; ++i) {
    const long long before = gAllocations;
    w.step(dt);
    stepAllocations += gAllocations - before;
    if (i % 1000 != 0 && i != steps - 1) continue;
    for (size_t k = 0; k < bodies.size(); ++k)
      drift = std::max(drift, (w.pose(bodies[k]).p - settled[k].p).norm());
    energyGain = std::max(energyGain, totalEnergy(w) - e0);
    maxLive = std::max(maxLive, gAllocations - gFrees);
    maxAwake = std::max(maxAwake, w.stats().awakeBodies);
    finite = finite && allFinite(w);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const long long allocs = gAllocations - allocs0;
  std::printf(
      "soak 1M: %.1f s, drift %.3g mm, energy gain %.3g J, awake bodies <= %d, %lld "
      "allocations in World::step (%lld with the checks), live blocks %lld -> max %lld\n",
      seconds, drift * 1e3, energyGain, maxAwake, stepAllocations, allocs, live0, maxLive);
  ASSERT_TRUE(finite);
  EXPECT_LT(drift, 1e-3) << "a resting body moved " << drift * 1e3 << " mm";
  EXPECT_LT(energyGain, 1e-6) << "energy grew by " << energyGain << " J";
  EXPECT_EQ(maxAwake, 0) << "the resting scene did not stay asleep";
  EXPECT_EQ(stepAllocations, 0) << "a sleeping world allocated while stepping";
  // Memory: the number of live heap blocks never grows (a leak of one block per thousand
  // steps would show as a thousand).
  EXPECT_LE(maxLive, live0) << "live heap blocks grew from " << live0 << " to " << maxLive;
}
