// grip beside Bullet (Debian's libbullet-dev) and ODE (libode-dev), each at its default
// settings, same scenes, same process. Build with -DGRIP_WITH_BULLET=ON and/or
// -DGRIP_WITH_ODE=ON; run build/bench/peers_bench. The engines are the sweep's
// (bench/peers/, apps/sweep/): grip 60 Hz 4 substeps; Bullet 60 Hz 10 iterations; ODE 60 Hz
// quickstep 20 iterations.
// Scenes: Pile1000 and Pile100 drop the boxes in staggered layers (the pile lands within the
// run); PileRest1000 starts every engine from the same resting pile (grip's, settled for 10 s),
// at each engine's defaults, and PileRest1000Awake the same with sleeping off in every engine
// (the cost of holding a pile up).
// Chain10, Chain30 and Chain10Heavy hang chains of thin boxes on ball joints (runChain).
// Counters: ms_per_step (wall time per step), below (bodies whose centre went below the ground
// at any step); for the resting piles moved (bodies more than 5 mm from their start at the
// end); for the stacks settle_mm (the top's movement in the first second) and drift_mm
// (its largest movement from there over the next 10 s: issue 2's bar, as tests/dynamics
// measures it). For medians on a noisy host, run with --benchmark_repetitions=7
// --benchmark_enable_random_interleaving=true (docs/performance.md).
#include <benchmark/benchmark.h>

#include <chrono>

#include "dynamics/scenes.hpp"
#include "peers/peers.hpp"

using namespace grip;

namespace {

// Initial poses come from grip's scene builders, so every engine starts identically.
std::vector<sweep::SolidDef> layout(bool pile, int count) {
  World w;
  const std::vector<BodyId> ids =
      pile ? scenes::addBoxPile(w, count) : scenes::addBoxStack(w, count, 0.1, 1.0);
  std::vector<sweep::SolidDef> out;
  for (BodyId id : ids) {
    sweep::SolidDef b;
    b.halfExtents = w.shape(id).halfExtents();
    b.position = w.pose(id).p;
    b.orientation = w.pose(id).q;
    b.friction = 0.6;
    out.push_back(b);
  }
  return out;
}

const sweep::Engine& engine(const std::string& name) {
  static const std::vector<sweep::Engine> all = peers::allEngines();
  for (const sweep::Engine& e : all)
    if (e.name == name) return e;
  throw Error("engine", "not in this build: " + name);
}

// The 1000-box pile dropped and settled by grip for 10 s with every body awake (the fastest
// box then moves about 5 mm/s): the start of the resting-pile scenes. Made on first use.
const std::vector<sweep::SolidDef>& restingPile() {
  static const std::vector<sweep::SolidDef> solids = [] {
    std::vector<sweep::SolidDef> out = layout(true, 1000);
    sweep::SceneDef awake;
    awake.sleep = false;
    const sweep::Engine& e = engine("grip");
    auto sim = e.make(awake, e.defaults);
    for (const sweep::SolidDef& s : out) sim->add(s);
    for (int s = 0; s < 600; ++s) sim->step();
    for (size_t i = 0; i < out.size(); ++i) {
      out[i].position = sim->position(static_cast<int>(i));
      out[i].orientation = sim->orientation(static_cast<int>(i));
    }
    return out;
  }();
  return solids;
}

// One iteration = build the scene, then `steps` steps. The stacks' top is read after
// kSettleSteps (a stack built exactly resting still settles into its contacts' slop).
constexpr int kSettleSteps = 60;

enum class Kind { Drop, Rest, Stack };

void runScene(benchmark::State& state, const std::string& name,
              const std::vector<sweep::SolidDef>& solids, int steps, Kind kind, bool sleep) {
  const sweep::Engine& e = engine(name);
  double below = 0, moved = 0, settle = 0, drift = 0, stepMs = 0;
  int runs = 0;
  sweep::SceneDef scene;
  scene.sleep = sleep;
  for (auto _ : state) {
    auto sim = e.make(scene, e.defaults);
    for (const sweep::SolidDef& s : solids) sim->add(s);
    const int top = static_cast<int>(solids.size()) - 1;
    const Vec3 start = sim->position(top);
    Vec3 settled = start;
    std::vector<uint8_t> wentBelow(solids.size(), 0);
    drift = 0;
    for (int s = 0; s < steps; ++s) {
      const auto t0 = std::chrono::steady_clock::now();
      sim->step();
      stepMs +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      for (int i = 0; i <= top; ++i) wentBelow[i] |= sim->position(i).y() < 0.0;
      if (s + 1 == kSettleSteps) settled = sim->position(top);
      if (s + 1 > kSettleSteps) drift = std::max(drift, (sim->position(top) - settled).norm());
    }
    settle = (settled - start).norm();
    below = 0;
    for (uint8_t b : wentBelow) below += b;
    moved = 0;
    for (int i = 0; i <= top; ++i) moved += (sim->position(i) - solids[i].position).norm() > 0.005;
    ++runs;
  }
  state.counters["ms_per_step"] = stepMs / (runs * steps);
  state.counters["below"] = below;
  if (kind == Kind::Rest) state.counters["moved"] = moved;
  if (kind == Kind::Stack) {
    state.counters["settle_mm"] = settle * 1e3;
    state.counters["drift_mm"] = drift * 1e3;
  }
}

// A chain of `links` thin boxes (10 x 2 x 2 cm, 0.1 kg; the last `endMass`) hanging from a fixed
// point by ball joints at their shared ends, released level, 600 steps at 60 Hz, everything
// awake, the links touching nothing. Counters: gap_mm (the widest any joint opened over the
// run), gap_end_mm (the widest at the end), gain_mJ (the most the energy rose above its start;
// a chain swinging without friction should not gain any), lost_mJ (what it lost by the end:
// the joints' softness and the solver's passes damp the swing).
void runChain(benchmark::State& state, const std::string& name, int links, double endMass) {
  const sweep::Engine& e = engine(name);
  sweep::SceneDef scene;
  scene.sleep = false;
  const Vec3 top(0.0, 5.0, 0.0), half(0.05, 0.01, 0.01), g = scene.gravity;
  const int steps = 600;
  double widest = 0, atEnd = 0, gain = 0, lost = 0, stepMs = 0;
  int runs = 0;
  for (auto _ : state) {
    auto sim = e.make(scene, e.defaults);
    std::vector<double> mass;
    for (int k = 0; k < links; ++k) {
      sweep::SolidDef d;
      d.halfExtents = half;
      d.mass = k + 1 == links ? endMass : 0.1;
      d.position = top + Vec3(0.1 * k + 0.05, 0.0, 0.0);
      d.collides = false;
      mass.push_back(d.mass);
      sim->add(d);
      sim->joinBall(k - 1, k, top + Vec3(0.1 * k, 0.0, 0.0));
    }
    auto gap = [&] {
      double most = (sim->position(0) + sim->orientation(0) * Vec3(-0.05, 0, 0) - top).norm();
      for (int k = 1; k < links; ++k) {
        const Vec3 end = sim->position(k - 1) + sim->orientation(k - 1) * Vec3(0.05, 0, 0);
        const Vec3 start = sim->position(k) + sim->orientation(k) * Vec3(-0.05, 0, 0);
        most = std::max(most, (end - start).norm());
      }
      return most;
    };
    auto energy = [&] {
      double E = 0;
      for (int k = 0; k < links; ++k) {
        const double m = mass[k];
        const Vec3 I = m / 3.0 *
                       Vec3(half.y() * half.y() + half.z() * half.z(),
                            half.x() * half.x() + half.z() * half.z(),
                            half.x() * half.x() + half.y() * half.y());
        const Vec3 w = sim->orientation(k).conjugate() * sim->angularVelocity(k);
        E += 0.5 * m * sim->linearVelocity(k).squaredNorm() + 0.5 * w.dot(I.cwiseProduct(w)) -
             m * g.dot(sim->position(k));
      }
      return E;
    };
    const double start = energy();
    widest = 0, gain = 0;
    for (int s = 0; s < steps; ++s) {
      const auto t0 = std::chrono::steady_clock::now();
      sim->step();
      stepMs +=
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      widest = std::max(widest, gap());
      gain = std::max(gain, energy() - start);
    }
    atEnd = gap();
    lost = start - energy();
    ++runs;
  }
  state.counters["ms_per_step"] = stepMs / (runs * steps);
  state.counters["gap_mm"] = widest * 1e3;
  state.counters["gap_end_mm"] = atEnd * 1e3;
  state.counters["gain_mJ"] = gain * 1e3;
  state.counters["lost_mJ"] = lost * 1e3;
}

void registerAll() {
  struct Case {
    const char* name;
    Kind kind;
    bool sleep;
    int count, steps, iterations;
    benchmark::TimeUnit unit;
  };
  const Case cases[] = {
      {"Pile1000", Kind::Drop, true, 1000, 180, 3, benchmark::kSecond},
      {"PileRest1000", Kind::Rest, true, 1000, 180, 3, benchmark::kSecond},
      {"PileRest1000Awake", Kind::Rest, false, 1000, 180, 3, benchmark::kSecond},
      {"Pile100", Kind::Drop, true, 100, 180, 5, benchmark::kMillisecond},
      {"Stack20", Kind::Stack, true, 20, kSettleSteps + 600, 3, benchmark::kMillisecond},
      {"Stack10", Kind::Stack, true, 10, kSettleSteps + 600, 3, benchmark::kMillisecond}};
  for (const Case& c : cases) {
    const std::vector<sweep::SolidDef> built = c.kind == Kind::Rest
                                                   ? std::vector<sweep::SolidDef>{}
                                                   : layout(c.kind == Kind::Drop, c.count);
    for (const sweep::Engine& e : peers::allEngines()) {
      const std::string name = "BM_Peer_" + std::string(c.name) + "_" + e.name;
      benchmark::RegisterBenchmark(name.c_str(),
                                   [built, c, n = e.name](benchmark::State& s) {
                                     const std::vector<sweep::SolidDef>& solids =
                                         c.kind == Kind::Rest ? restingPile() : built;
                                     runScene(s, n, solids, c.steps, c.kind, c.sleep);
                                   })
          ->Unit(c.unit)
          ->Iterations(c.iterations);
    }
  }
}

void registerChains() {
  struct Chain {
    const char* name;
    int links;
    double endMass;
  };
  for (const Chain& c :
       {Chain{"Chain10", 10, 0.1}, Chain{"Chain30", 30, 0.1}, Chain{"Chain10Heavy", 10, 10.0}})
    for (const sweep::Engine& e : peers::allEngines()) {
      const std::string name = "BM_Peer_" + std::string(c.name) + "_" + e.name;
      benchmark::RegisterBenchmark(
          name.c_str(),
          [c, n = e.name](benchmark::State& s) { runChain(s, n, c.links, c.endMass); })
          ->Unit(benchmark::kMillisecond)
          ->Iterations(3);
    }
}

const int registered = (registerAll(), registerChains(), 0);

}  // namespace
