// "Skip what a scene doesn't need": a step costs what its awake work costs. A settled
// 1000-box pile asleep against the same pile awake; an empty world; a world with one body.
// The counters come from World::stats(), so the output shows the work each step did.
#include <benchmark/benchmark.h>

#include "dynamics/scenes.hpp"

using namespace grip;

namespace {

void addStats(benchmark::State& state, const World& w) {
  const StepStats& s = w.stats();
  state.counters["awake"] = s.awakeBodies;
  state.counters["pairs"] = s.candidatePairs;
  state.counters["manifolds"] = s.manifolds;
  state.counters["points"] = s.contactPoints;
  state.counters["islands"] = s.islands;
}

// A 1000-box pile settled for 10 s. Asleep (the default) or kept awake (sleeping off).
void BM_Pile1000(benchmark::State& state) {
  const bool asleep = state.range(0) != 0;
  WorldDef def;
  def.enableSleep = asleep;
  World w(def);
  scenes::addGround(w);
  scenes::addBoxPile(w, 1000);
  for (int i = 0; i < 600; ++i) w.step(1.0 / 60.0);
  for (auto _ : state) w.step(1.0 / 60.0);
  state.SetLabel(asleep ? "asleep" : "awake");
  addStats(state, w);
}
BENCHMARK(BM_Pile1000)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);

// Nothing to do at all.
void BM_EmptyWorld(benchmark::State& state) {
  World w;
  for (auto _ : state) w.step(1.0 / 60.0);
  addStats(state, w);
}
BENCHMARK(BM_EmptyWorld)->Unit(benchmark::kNanosecond);

// One body: falling freely (awake, no contacts), or resting on the ground (0: awake, 1: asleep).
void BM_OneBody(benchmark::State& state) {
  WorldDef def;
  def.gravity = state.range(0) == 0 ? Vec3::Zero() : def.gravity;
  World w(def);
  BodyDef d;
  d.shape = Shape::box(Vec3::Constant(0.1));
  d.position = Vec3(0, 0.1, 0);
  d.allowSleep = state.range(0) == 2;
  if (state.range(0) != 0) scenes::addGround(w);
  w.createBody(d);
  if (state.range(0) == 2)
    for (int i = 0; i < 120; ++i) w.step(1.0 / 60.0);  // falls asleep
  for (auto _ : state) w.step(1.0 / 60.0);
  const char* labels[] = {"floating", "resting awake", "resting asleep"};
  state.SetLabel(labels[state.range(0)]);
  addStats(state, w);
}
BENCHMARK(BM_OneBody)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kNanosecond);

}  // namespace
