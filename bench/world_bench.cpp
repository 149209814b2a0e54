// World step cost: resting stacks, resting piles, a pile being dropped; what a snapshot costs;
// what queries cost in a world at rest and in a landing pile.
#include <benchmark/benchmark.h>

#include <chrono>
#include <vector>

#include "dynamics/scenes.hpp"

using namespace grip;

namespace {

// Builds a pile and lets it settle first, so each timed step is a resting pile.
World restingPile(int count) {
  WorldDef def;
  def.enableSleep = false;  // measure the solver at rest, not sleeping
  World w(def);
  scenes::addGround(w);
  scenes::addBoxPile(w, count);
  for (int i = 0; i < 240; ++i) w.step(1.0 / 60.0);
  return w;
}

void BM_World_RestingPile(benchmark::State& state) {
  World w = restingPile(static_cast<int>(state.range(0)));
  for (auto _ : state) w.step(1.0 / 60.0);
  state.counters["contacts"] = w.stats().contactPoints;
}
BENCHMARK(BM_World_RestingPile)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);

// The same pile asleep: what a settled scene costs with sleeping on (the default).
void BM_World_SleepingPile(benchmark::State& state) {
  World w;
  scenes::addGround(w);
  scenes::addBoxPile(w, static_cast<int>(state.range(0)));
  for (int i = 0; i < 600; ++i) w.step(1.0 / 60.0);
  for (auto _ : state) w.step(1.0 / 60.0);
  state.counters["awake"] = w.stats().awakeBodies;
}
BENCHMARK(BM_World_SleepingPile)->Arg(1000)->Unit(benchmark::kMicrosecond);

// The same pile asleep while a kinematic box (an object in a hand) moves beside it: what the
// sleeping bodies cost a scene where something moves.
void BM_World_SleepingPileOneMoving(benchmark::State& state) {
  World w;
  scenes::addGround(w);
  scenes::addBoxPile(w, static_cast<int>(state.range(0)));
  for (int i = 0; i < 600; ++i) w.step(1.0 / 60.0);
  BodyDef held;
  held.type = BodyType::Kinematic;
  held.shape = Shape::box(Vec3::Constant(0.05));
  held.position = Vec3(4.0, 0.5, 0.0);
  held.linearVelocity = Vec3(0.0, 0.0, 0.1);
  w.createBody(held);
  for (auto _ : state) w.step(1.0 / 60.0);
  state.counters["awake"] = w.stats().awakeBodies;
}
BENCHMARK(BM_World_SleepingPileOneMoving)->Arg(1000)->Unit(benchmark::kMicrosecond);

// N cubes asleep on the floor in a grid, each with its floor contact, while one ball rolls
// among them: a room of sleeping objects should cost a step what its moving ones do.
void BM_World_SleepingGridOneMoving(benchmark::State& state) {
  World w;
  scenes::addGround(w);
  const int n = static_cast<int>(state.range(0));
  int side = 1;
  while (side * side < n) ++side;
  BodyDef cube;
  cube.shape = Shape::box(Vec3::Constant(0.05));
  for (int i = 0; i < n; ++i) {
    cube.position = Vec3(0.3 * (i % side), 0.05, 0.3 * (i / side));
    w.createBody(cube);
  }
  for (int i = 0; i < 60; ++i) w.step(1.0 / 60.0);
  BodyDef ball;
  ball.shape = Shape::sphere(0.1);
  ball.position = Vec3(-1.0, 0.1, 0.0);
  ball.linearVelocity = Vec3(0.0, 0.0, 1.0);
  w.createBody(ball);
  for (auto _ : state) w.step(1.0 / 60.0);
  state.counters["awake"] = w.stats().awakeBodies;
}
BENCHMARK(BM_World_SleepingGridOneMoving)
    ->Arg(1000)
    ->Arg(10000)
    ->Arg(50000)
    ->Unit(benchmark::kMicrosecond);

void BM_World_Stack(benchmark::State& state) {
  WorldDef def;
  def.enableSleep = false;
  World w(def);
  scenes::addGround(w);
  scenes::addBoxStack(w, static_cast<int>(state.range(0)));
  for (int i = 0; i < 60; ++i) w.step(1.0 / 60.0);
  for (auto _ : state) w.step(1.0 / 60.0);
}
BENCHMARK(BM_World_Stack)->Arg(10)->Arg(20)->Unit(benchmark::kMicrosecond);

// A chain of N thin links (ball joints, no contacts between them) swinging from a fixed point,
// and, for the joints' own cost, the same links without joints (falling freely).
void chain(benchmark::State& state, bool joined) {
  WorldDef def;
  def.enableSleep = false;
  World w(def);
  scenes::addChain(w, static_cast<int>(state.range(0)), Vec3(0.0, 50.0, 0.0), 0.1, 0.1, joined);
  for (int i = 0; i < 30; ++i) w.step(1.0 / 60.0);
  for (auto _ : state) w.step(1.0 / 60.0);
  state.counters["joints"] = w.jointCount();
}
void BM_World_Chain(benchmark::State& state) {
  chain(state, true);
}
BENCHMARK(BM_World_Chain)->Arg(10)->Arg(100)->Unit(benchmark::kMicrosecond);
void BM_World_ChainLinksUnjoined(benchmark::State& state) {
  chain(state, false);
}
BENCHMARK(BM_World_ChainLinksUnjoined)->Arg(10)->Arg(100)->Unit(benchmark::kMicrosecond);

// Dropping a pile: 3 s from release (falling, impacts, settling); ms_per_step is the mean.
void BM_World_PileDrop(benchmark::State& state) {
  const int steps = 180;
  double stepMs = 0;
  int runs = 0;
  for (auto _ : state) {
    World w;
    scenes::addGround(w);
    scenes::addBoxPile(w, static_cast<int>(state.range(0)));
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < steps; ++i) w.step(1.0 / 60.0);
    stepMs +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ++runs;
  }
  state.counters["ms_per_step"] = stepMs / (runs * steps);
}
BENCHMARK(BM_World_PileDrop)->Arg(1000)->Unit(benchmark::kMillisecond)->Iterations(3);

// A snapshot: copying a world with a resting pile (bodies, contacts, warm-start impulses) and
// assigning it back, as a rollback would. Against one step of the same pile above.
void BM_World_Snapshot(benchmark::State& state) {
  const World w = restingPile(static_cast<int>(state.range(0)));
  World saved(w);
  for (auto _ : state) {
    saved = w;
    benchmark::DoNotOptimize(saved);
  }
  state.counters["contacts"] = w.stats().contactPoints;
}
BENCHMARK(BM_World_Snapshot)->Arg(100)->Arg(1000)->Unit(benchmark::kMicrosecond);

}  // namespace

// `count` cubes of 0.1 m on a grid 0.3 m apart (none touching), asleep on the ground.
World restingGrid(int count) {
  World w;
  scenes::addGround(w);
  int side = 1;
  while (side * side < count) ++side;
  const ShapePtr cube = Shape::box(Vec3::Constant(0.05));
  for (int i = 0; i < count; ++i) {
    BodyDef d;
    d.shape = cube;
    d.position = Vec3((i % side) * 0.3, 0.05, (i / side) * 0.3);
    w.createBody(d);
  }
  for (int i = 0; i < 120; ++i) w.step(1.0 / 60.0);
  return w;
}

// One overlap of a finger bone (a capsule of 1 cm radius, 4 cm long) between the cubes and one
// ray down onto them, in a world of `count` cubes at rest: what a hand's contact search pays
// per bone among that many objects.
void BM_World_QueryAtRest(benchmark::State& state) {
  const World w = restingGrid(static_cast<int>(state.range(0)));
  const ShapePtr bone = Shape::capsule(0.01, 0.02);
  std::vector<OverlapHit> hits;
  int k = 0;
  for (auto _ : state) {
    const double x = 0.15 + (k++ % 10) * 0.3;
    w.overlap(*bone, Transform{Vec3(x, 0.2, 0.15), Quat::Identity()}, 0.01, hits);
    benchmark::DoNotOptimize(w.rayCast(Vec3(x - 0.15, 1.0, 0.0), Vec3(0.0, -1.0, 0.0), 2.0));
  }
  state.counters["bodies"] = w.bodyCount();
}
BENCHMARK(BM_World_QueryAtRest)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);

// The 1000-box pile landing (every box moving): a step, then `range(0)` overlaps and rays
// among the boxes; the time is the queries' (the step's paused out), per step.
void BM_World_QueryLandingPile(benchmark::State& state) {
  World w;
  scenes::addGround(w);
  scenes::addBoxPile(w, 1000);
  for (int i = 0; i < 30; ++i) w.step(1.0 / 60.0);
  const ShapePtr bone = Shape::capsule(0.01, 0.02);
  std::vector<OverlapHit> hits;
  const int queries = static_cast<int>(state.range(0));
  for (auto _ : state) {
    state.PauseTiming();
    w.step(1.0 / 60.0);
    state.ResumeTiming();
    for (int q = 0; q < queries; ++q) {
      const double x = -0.5 + 0.05 * (q % 20);
      w.overlap(*bone, Transform{Vec3(x, 0.3, 0.1), Quat::Identity()}, 0.01, hits);
      benchmark::DoNotOptimize(w.rayCast(Vec3(x, 3.0, 0.0), Vec3(0.0, -1.0, 0.0), 5.0));
    }
  }
}
BENCHMARK(BM_World_QueryLandingPile)
    ->Arg(1)
    ->Arg(16)
    ->Arg(64)
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(120);
