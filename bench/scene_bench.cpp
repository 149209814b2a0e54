// Built-in scenes stretched to one simulated minute at 240 Hz (issue bar: at least 50x real
// time). Each run is one whole scene; the counter x_realtime is simulated seconds per wall
// second (UseRealTime; the CPU column shows the same run's CPU time, lower on a shared machine).
// The scenes hold still after their last keyframe, so most of the minute is a hand holding (or a
// tower standing), which is what a long recorded session mostly is.
//   BM_Scene/<i>/<substeps>  built-in scene i with 4 substeps per step (the scenes' own setting,
//                            a 960 Hz solver) or 1 (a 240 Hz solver, as fast as the 60 Hz
//                            scenes' 4 substeps), no output files
//   BM_SceneRecorded/<i>/4   the same, writing recording.jsonl and metrics.json to a temp folder
#include <benchmark/benchmark.h>

#include <filesystem>

#include "scene/scene.hpp"

namespace {

constexpr double kMinute = 60.0;

grip::scene::Scene minuteAt240Hz(int i, int substeps) {
  nlohmann::json doc = grip::scene::builtinScenes()[static_cast<size_t>(i)].make();
  grip::scene::applyOverride(doc, "duration=60");
  grip::scene::applyOverride(doc, "world.hz=240");
  grip::scene::applyOverride(doc, "world.substeps=" + std::to_string(substeps));
  return grip::scene::parseScene(doc);
}

void runScene(benchmark::State& state, bool record) {
  const int i = static_cast<int>(state.range(0));
  const grip::scene::Scene s = minuteAt240Hz(i, static_cast<int>(state.range(1)));
  grip::scene::RunOptions opt;
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "grip_scene_bench";
  if (record) opt.outDir = dir.string();
  for (auto _ : state) {
    const grip::scene::RunResult r = grip::scene::run(s, opt);
    benchmark::DoNotOptimize(r.stateHash);
  }
  state.SetLabel(s.name);
  state.counters["x_realtime"] =
      benchmark::Counter(kMinute, benchmark::Counter::kIsIterationInvariantRate);
  if (record) std::filesystem::remove_all(dir);
}

void BM_Scene(benchmark::State& state) {
  runScene(state, false);
}
void BM_SceneRecorded(benchmark::State& state) {
  runScene(state, true);
}

void allScenes(benchmark::internal::Benchmark* b) {
  for (int substeps : {4, 1})
    for (size_t i = 0; i < grip::scene::builtinScenes().size(); ++i)
      b->Args({static_cast<int>(i), substeps});
  b->Unit(benchmark::kMillisecond)->Iterations(1)->Repetitions(3)->ReportAggregatesOnly(true);
  b->UseRealTime();
}

BENCHMARK(BM_Scene)->Apply(allScenes);
BENCHMARK(BM_SceneRecorded)
    ->Args({0, 4})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace
