// Hand-interaction cost for 6..32 contact phalanges with 9-sample patches, in the scene of
// scenarios::buildHoldScene (a floor, ten boxes, a 0.2 kg cube held by the phalanges).
//   BM_Interaction_Update/N    the interaction update alone (contacts, patches, forces)
//   BM_Interaction_FullStep/N  interaction update plus World::step
#include <benchmark/benchmark.h>

#include "interaction/interaction.hpp"
#include "interaction/scenarios.hpp"

namespace {

constexpr double kDt = 1.0 / 60.0;

void setPoses(grip::Interaction& ix, const grip::scenarios::HoldScene& s) {
  for (size_t h = 0; h < s.hands.size(); ++h) ix.setHandPose(s.hands[h], s.poses[h]);
}

void BM_Interaction_Update(benchmark::State& state) {
  grip::World w;
  grip::Interaction ix;
  const auto s = grip::scenarios::buildHoldScene(w, ix, static_cast<int>(state.range(0)));
  for (int i = 0; i < 30; ++i) {  // settle into the hold
    setPoses(ix, s);
    ix.step(w, kDt);
  }
  for (auto _ : state) {
    setPoses(ix, s);
    ix.update(w, kDt);  // forces accumulate without a step; the work per update is the same
    benchmark::DoNotOptimize(ix.stats().samples);
  }
  state.counters["pressing"] = ix.stats().pressingContacts;
  state.counters["samples"] = ix.stats().samples;
}

void BM_Interaction_FullStep(benchmark::State& state) {
  grip::World w;
  grip::Interaction ix;
  const auto s = grip::scenarios::buildHoldScene(w, ix, static_cast<int>(state.range(0)));
  for (int i = 0; i < 30; ++i) {
    setPoses(ix, s);
    ix.step(w, kDt);
  }
  for (auto _ : state) {
    setPoses(ix, s);
    ix.step(w, kDt);
    benchmark::DoNotOptimize(w.stateHash());
  }
  state.counters["pressing"] = ix.stats().pressingContacts;
  state.counters["bodies"] = w.bodyCount();
}

}  // namespace

BENCHMARK(BM_Interaction_Update)
    ->Arg(6)
    ->Arg(8)
    ->Arg(12)
    ->Arg(16)
    ->Arg(24)
    ->Arg(32)
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Interaction_FullStep)
    ->Arg(6)
    ->Arg(8)
    ->Arg(12)
    ->Arg(16)
    ->Arg(24)
    ->Arg(32)
    ->Unit(benchmark::kMicrosecond);
