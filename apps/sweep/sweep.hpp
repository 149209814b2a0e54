// Work-precision sweeps (docs/accuracy.md): reference scenes with analytic or converged
// answers, each run over a grid of time step, substeps and solver iterations, timed, and
// written as CSV and an SVG chart of error against run time.
//
// The scenes are written once against a small engine-neutral interface (Sim), so grip, Bullet
// and ODE run exactly the same scene code. grip's Sim lives here; the peers' live in bench/
// (built only with GRIP_WITH_BULLET / GRIP_WITH_ODE), so the runtime never links them.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace grip::sweep {

// One solid of a reference scene. Every scene uses a single friction coefficient (static =
// dynamic), because Bullet and ODE have only one. A touching pair gets the product of the two
// solids' friction and restitution, the ground counting as 1 (each engine's Sim arranges this
// through its own combine rule), so a body on the ground gets exactly its own values.
struct SolidDef {
  bool sphere = false;
  Vec3 halfExtents = Vec3::Constant(0.05);  // box
  double radius = 0.05;                     // sphere
  double mass = 1.0;
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Vec3 linearVelocity = Vec3::Zero();
  Vec3 angularVelocity = Vec3::Zero();
  double friction = 0.5;
  double restitution = 0.0;
  bool collides = true;  // false: makes no contacts at all (a chain's links: the joints alone)
};

struct SceneDef {
  Vec3 gravity = Vec3(0, -9.81, 0);
  bool ground = true;  // a static plane y = 0
  // Each engine's own sleeping at its defaults; false keeps every body awake, so that a
  // resting scene measures the solver's work (ODE does not sleep bodies by default anyway).
  bool sleep = true;
};

// The knobs every engine has: step, substeps per step, and solver iterations (grip: relax
// passes per substep; Bullet: sequential-impulse iterations; ODE: quickstep iterations, 0 =
// dWorldStep's direct solver).
struct Settings {
  double dt = 1.0 / 60.0;
  int substeps = 1;
  int iterations = 10;
};

// A world of one engine. Bodies are numbered in creation order from 0 (the ground is not one).
class Sim {
 public:
  virtual ~Sim() = default;
  virtual int add(const SolidDef& s) = 0;
  virtual void addForce(int body, const Vec3& f) = 0;  // at the centre, for the next step only
  // A ball joint between bodies a and b (a = -1: the static world) at a world point, as they
  // are now.
  virtual void joinBall(int a, int b, const Vec3& anchor) = 0;
  virtual void step() = 0;  // one step of Settings::dt
  virtual Vec3 position(int body) const = 0;
  virtual Quat orientation(int body) const = 0;
  virtual Vec3 linearVelocity(int body) const = 0;
  virtual Vec3 angularVelocity(int body) const = 0;
};

// An engine: its name, its default settings, the grid it is swept over, and its worlds.
struct Engine {
  std::string name;
  Settings defaults;
  std::function<std::vector<Settings>(const std::string& scene, bool quick)> grid;
  std::function<std::unique_ptr<Sim>(const SceneDef&, const Settings&)> make;
  bool hands = false;  // grip's hand interaction: runs the `hold` scene
};

// An engine whose worlds are S(SceneDef, Settings).
template <class S>
Engine engineOf(std::string name, Settings defaults,
                std::function<std::vector<Settings>(const std::string&, bool)> grid) {
  return {std::move(name), defaults, std::move(grid),
          [](const SceneDef& sc, const Settings& s) -> std::unique_ptr<Sim> {
            return std::make_unique<S>(sc, s);
          },
          false};
}

Engine gripEngine();
// grip with WorldDef::workerThreads = 2; swept on the pile only (the results equal grip's).
Engine gripTwoThreadEngine();

// Every combination of step rates (Hz), substeps and iterations: an engine's grid.
std::vector<Settings> product(const std::vector<double>& ratesHz, const std::vector<int>& substeps,
                              const std::vector<int>& iterations);

// The step rates every engine's pile is swept at (Hz): one list, so that no engine's grid
// reaches lower or higher than another's.
inline const std::vector<double> kPileRatesHz = {10, 12, 15, 20, 30, 60, 120};

// One sample: a scene at one setting. seconds: wall time of the steps alone per simulated
// second (the fastest of the repeats). error2 is NaN for scenes with a single metric.
struct Sample {
  std::string engine, scene;
  Settings settings;
  bool isDefault = false;
  double seconds = 0;
  double error = 0;
  std::string errorName;
  double error2 = 0;
  std::string error2Name;
};

// The scenes, in the order the chart shows them.
const std::vector<std::string>& sceneNames();

// One scene at one setting, timed `repeats` times in a row, the fastest kept (tests call it for
// a single setting; run() interleaves the repeats instead). Throws grip::Error for an unknown
// scene.
Sample measure(const Engine& e, const std::string& scene, const Settings& s, bool quick,
               int repeats = 1);

struct Options {
  std::vector<std::string> scenes;  // empty: all
  bool quick = false;               // a small grid, short pile (tests, CI)
  int repeats = 3;                  // timing rounds per sample (the fastest is kept)
};

// Throws grip::Error for an unknown scene name or a non-positive repeat count.
void validate(const Options& o);
// Runs every engine over every chosen scene: per scene, `repeats` rounds over every engine's
// settings, the fastest run of each setting kept. Throws grip::Error for an unknown scene name
// or a non-positive repeat count. progress (may be empty) is told of each sample as it is done.
std::vector<Sample> run(const std::vector<Engine>& engines, const Options& o,
                        const std::function<void(const Sample&)>& progress = {});

// sweep.csv: a header and one row per sample.
std::string csv(const std::vector<Sample>& samples);
// sweep.svg: one panel per scene (and one for the rotation's energy), log-log error against
// seconds, a colour per engine, each engine's Pareto front as a line and its default setting
// ringed.
std::string svg(const std::vector<Sample>& samples);
// Creates DIR (a run checks this before it starts); throws grip::Error naming it.
void makeOutputDir(const std::string& dir);
// Writes DIR/sweep.csv and DIR/sweep.svg (creating DIR); throws grip::Error naming the path.
void write(const std::vector<Sample>& samples, const std::string& dir);

// The command line shared by `grip sweep` and bench/peers_sweep: --out DIR, --scene NAME
// (repeatable), --quick, --repeats N.
struct CommandLine {
  Options options;
  std::string out = "sweep_out";
};
void addOptions(CLI::App& app, CommandLine& c);
// Runs, prints one line per sample on stdout, writes the files. Errors throw grip::Error.
int runCommand(const std::vector<Engine>& engines, const CommandLine& c);

}  // namespace grip::sweep
