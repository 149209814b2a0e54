// The reference scenes of the sweep and their error metrics (docs/accuracy.md). Each scene
// builds its solids through Sim, steps, and compares with an analytic answer; only the steps
// are timed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "dynamics/scenes.hpp"
#include "sweep/detail.hpp"

namespace grip::sweep {

namespace {

constexpr double kG = 9.81;
constexpr double kMu = 0.5;  // friction of every scene with contact

using detail::Outcome;

// A Sim whose steps are timed and counted.
class Clock {
 public:
  Clock(Sim& sim, double dt) : sim_(sim), dt_(dt) {}
  void step() {
    const auto t0 = std::chrono::steady_clock::now();
    sim_.step();
    wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++steps_;
  }
  double time() const { return steps_ * dt_; }
  Outcome outcome(double error, double error2 = std::numeric_limits<double>::quiet_NaN()) const {
    return {error, error2, time(), wall_};
  }

 private:
  Sim& sim_;
  double dt_;
  double wall_ = 0;
  long steps_ = 0;
};

long stepsFor(double seconds, const Settings& s) {
  return std::max(1L, std::lround(seconds / s.dt));
}

SolidDef cube(double edge, double mass, const Vec3& p) {
  SolidDef b;
  b.halfExtents = Vec3::Constant(edge / 2);
  b.mass = mass;
  b.position = p;
  return b;
}

// A cube on a slope of `degrees`, as a cube on flat ground under tilted gravity (the same
// physics in the slope's frame; no engine has to rotate its ground). Returns the distance slid
// down the slope after 2 s.
Outcome incline(const Engine& e, const Settings& s, double degrees, double& expected) {
  const double th = degrees * kPi / 180.0;
  SceneDef sc;
  sc.gravity = Vec3(kG * std::sin(th), -kG * std::cos(th), 0);
  auto sim = e.make(sc, s);
  SolidDef b = cube(0.1, 1.0, Vec3(0, 0.05, 0));
  b.friction = kMu;
  const int id = sim->add(b);
  Clock c(*sim, s.dt);
  for (long i = stepsFor(2.0, s); i > 0; --i) c.step();
  const double a = std::max(0.0, kG * (std::sin(th) - kMu * std::cos(th)));
  expected = 0.5 * a * c.time() * c.time();
  return c.outcome(sim->position(id).x());
}

Outcome inclineSlide(const Engine& e, const Settings& s, bool) {
  double expected = 0;
  Outcome o = incline(e, s, 35.0, expected);  // above the stick angle atan(0.5) = 26.6°
  o.error = std::abs(o.error - expected) / expected;
  return o;
}

Outcome inclineStick(const Engine& e, const Settings& s, bool) {
  double expected = 0;
  Outcome o = incline(e, s, 20.0, expected);  // below it: the cube must not move
  o.error = std::abs(o.error);
  return o;
}

// Ten 0.1 m, 1 kg cubes on the ground for 10 s. error: the largest movement of the top cube
// from where it was after the first second (settling excluded); error2: that settling.
Outcome stack(const Engine& e, const Settings& s, bool) {
  auto sim = e.make(SceneDef{}, s);
  int top = 0;
  for (int i = 0; i < 10; ++i) {
    SolidDef b = cube(0.1, 1.0, Vec3(0, 0.05 + 0.1 * i, 0));
    b.friction = kMu;
    top = sim->add(b);
  }
  const Vec3 start = sim->position(top);
  Clock c(*sim, s.dt);
  const long settle = stepsFor(1.0, s);
  for (long i = 0; i < settle; ++i) c.step();
  const Vec3 settled = sim->position(top);
  double drift = 0;
  for (long i = stepsFor(10.0, s) - settle; i > 0; --i) {
    c.step();
    drift = std::max(drift, (sim->position(top) - settled).norm());
  }
  return c.outcome(drift, (settled - start).norm());
}

// A ball of restitution 0.5 dropped from 1 m (its lowest point): the first bounce should rise
// to e² h = 0.25 m. The apex is taken ballistically, y + v²/2g, from the first state that moves
// up clear of the ground (a sampled maximum would add an error of order g dt²).
Outcome bounce(const Engine& e, const Settings& s, bool) {
  constexpr double r = 0.05, h = 1.0, rest = 0.5;
  auto sim = e.make(SceneDef{}, s);
  SolidDef b;
  b.sphere = true;
  b.radius = r;
  b.position = Vec3(0, r + h, 0);
  b.restitution = rest;
  b.friction = kMu;
  const int id = sim->add(b);
  Clock c(*sim, s.dt);
  double apex = 0;  // stays 0 (error 1) if the ball never comes back up
  bool fell = false;
  while (c.time() < 3.0) {
    c.step();
    const double y = sim->position(id).y() - r, vy = sim->linearVelocity(id).y();
    if (vy < -0.5) fell = true;
    if (fell && vy > 0 && y > 0.01) {
      apex = y + vy * vy / (2 * kG);
      break;
    }
  }
  const double expected = rest * rest * h;
  return c.outcome(std::abs(apex - expected) / expected);
}

// A free box of half extents 0.05 x 0.1 x 0.2 m spun near its intermediate axis (the hardest
// case: the spin flips over). error: |L(10 s) − L0| / |L0| in the world frame; error2: the
// relative change of the kinetic energy.
Outcome rotation(const Engine& e, const Settings& s, bool) {
  SceneDef sc;
  sc.gravity = Vec3::Zero();
  sc.ground = false;
  auto sim = e.make(sc, s);
  SolidDef b;
  b.halfExtents = Vec3(0.05, 0.1, 0.2);
  b.mass = 1.0;
  b.position = Vec3(0, 1, 0);
  b.angularVelocity = Vec3(0.1, 5.0, 0.1);
  const int id = sim->add(b);
  const Vec3 h2 = b.halfExtents.cwiseProduct(b.halfExtents);
  const Vec3 inertia = b.mass / 3.0 * Vec3(h2.y() + h2.z(), h2.x() + h2.z(), h2.x() + h2.y());
  auto momentum = [&](Vec3& L, double& energy) {
    const Quat q = sim->orientation(id);
    const Vec3 wBody = q.conjugate() * sim->angularVelocity(id);
    const Vec3 lBody = inertia.cwiseProduct(wBody);
    L = q * lBody;
    energy = 0.5 * wBody.dot(lBody);
  };
  Vec3 L0, L1;
  double e0 = 0, e1 = 0;
  momentum(L0, e0);
  Clock c(*sim, s.dt);
  for (long i = stepsFor(10.0, s); i > 0; --i) c.step();
  momentum(L1, e1);
  return c.outcome((L1 - L0).norm() / L0.norm(), std::abs(e1 - e0) / e0);
}

// A 0.2 m, 1 kg box pushed by 8 N at its centre over a floor with μ = 0.5 for 2 s: it travels
// (F/m − μ g) t²/2 (the push is too low to tip it).
Outcome push(const Engine& e, const Settings& s, bool) {
  constexpr double force = 8.0;
  auto sim = e.make(SceneDef{}, s);
  SolidDef b = cube(0.2, 1.0, Vec3(0, 0.1, 0));
  b.friction = kMu;
  const int id = sim->add(b);
  Clock c(*sim, s.dt);
  for (long i = stepsFor(2.0, s); i > 0; --i) {
    sim->addForce(id, Vec3(force, 0, 0));
    c.step();
  }
  const double expected = 0.5 * (force / b.mass - kMu * kG) * c.time() * c.time();
  return c.outcome(std::abs(sim->position(id).x() - expected) / expected);
}

// grip's 1000-box pile (dynamics/scenes.hpp: 0.2 m cubes in ten staggered layers), 3 s
// (quick: 200 boxes, 1 s). error: the deepest any box corner went into the ground over the
// run; error2: the boxes whose centre went below the ground.
Outcome pile(const Engine& e, const Settings& s, bool quick) {
  std::vector<Transform> layout;
  {
    World w;
    for (BodyId id : scenes::addBoxPile(w, quick ? 200 : 1000)) layout.push_back(w.pose(id));
  }
  auto sim = e.make(SceneDef{}, s);
  std::vector<int> ids;
  for (const Transform& t : layout) {
    SolidDef b = cube(0.2, 1.0, t.p);
    b.orientation = t.q;
    b.friction = kMu;
    ids.push_back(sim->add(b));
  }
  std::vector<uint8_t> below(ids.size(), 0);
  double deepest = 0;
  Clock c(*sim, s.dt);
  for (long i = stepsFor(quick ? 1.0 : 3.0, s); i > 0; --i) {
    c.step();
    for (size_t k = 0; k < ids.size(); ++k) {
      const Vec3 p = sim->position(ids[k]);
      const Mat3 r = sim->orientation(ids[k]).toRotationMatrix();
      // The lowest corner of a cube: its centre minus the half edge times |row y of R| summed.
      const double low = p.y() - 0.1 * r.row(1).cwiseAbs().sum();
      deepest = std::max(deepest, -low);
      below[k] |= p.y() < 0.0;
    }
  }
  return c.outcome(deepest, static_cast<double>(std::count(below.begin(), below.end(), 1)));
}

Outcome hold(const Engine&, const Settings& s, bool) {
  return detail::hold(s);
}

struct SceneSpec {
  const char* name;
  const char* errorName;
  const char* error2Name;
  Outcome (*run)(const Engine&, const Settings&, bool quick);
  bool needsHands = false;  // only engines with grip's hand interaction run it
};

const std::vector<SceneSpec>& specs() {
  static const std::vector<SceneSpec> all = {
      {"incline", "slide_rel_error", "", inclineSlide, false},
      {"incline_stick", "slid_m", "", inclineStick, false},
      {"stack", "top_drift_m", "settle_m", stack, false},
      {"bounce", "apex_rel_error", "", bounce, false},
      {"rotation", "momentum_rel_error", "energy_rel_error", rotation, false},
      {"push", "travel_rel_error", "", push, false},
      {"pile", "deepest_m", "below_ground", pile, false},
      {"hold", "threshold_rel_error", "threshold_signed", hold, true},
  };
  return all;
}

const SceneSpec& spec(const std::string& name) {
  for (const SceneSpec& s : specs())
    if (name == s.name) return s;
  std::string known;
  for (const SceneSpec& s : specs()) known += std::string(known.empty() ? "" : ", ") + s.name;
  throw Error("--scene", "unknown scene '" + name + "' (one of " + known + ")");
}

}  // namespace

const std::vector<std::string>& sceneNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const SceneSpec& s : specs()) n.push_back(s.name);
    return n;
  }();
  return names;
}

namespace {

// One timing run: the scene repeated until its steps have taken 50 ms (a one-box scene takes
// tens of microseconds; the timer's and the machine's jitter would decide it otherwise).
// Returns the wall time per simulated second; `o` is the last run's outcome.
double timingRun(const SceneSpec& sp, const Engine& e, const Settings& s, bool quick, Outcome& o) {
  constexpr double kMinWall = 0.05;
  double wall = 0, simulated = 0;
  do {
    o = sp.run(e, s, quick);
    wall += o.wall, simulated += o.simulated;
  } while (wall < kMinWall && o.wall > 0.0);
  return wall / simulated;
}

Sample sampleOf(const Engine& e, const SceneSpec& sp, const Settings& s, const Outcome& o,
                double seconds) {
  Sample out;
  out.engine = e.name;
  out.scene = sp.name;
  out.settings = s;
  out.isDefault = s.dt == e.defaults.dt && s.substeps == e.defaults.substeps &&
                  s.iterations == e.defaults.iterations;
  out.seconds = seconds;
  out.error = o.error;
  out.errorName = sp.errorName;
  out.error2 = o.error2;
  out.error2Name = sp.error2Name;
  return out;
}

}  // namespace

Sample measure(const Engine& e, const std::string& scene, const Settings& s, bool quick,
               int repeats) {
  const SceneSpec& sp = spec(scene);
  if (repeats < 1)
    throw Error("--repeats", "must be positive (got " + std::to_string(repeats) + ")");
  Outcome o;
  double fastest = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r) fastest = std::min(fastest, timingRun(sp, e, s, quick, o));
  return sampleOf(e, sp, s, o, fastest);
}

void validate(const Options& o) {
  for (const std::string& name : o.scenes) spec(name);
  if (o.repeats < 1)
    throw Error("--repeats", "must be positive (got " + std::to_string(o.repeats) + ")");
}

std::vector<Sample> run(const std::vector<Engine>& engines, const Options& o,
                        const std::function<void(const Sample&)>& progress) {
  validate(o);  // every name checked before any run
  const std::vector<std::string>& chosen = o.scenes.empty() ? sceneNames() : o.scenes;
  std::vector<Sample> out;
  for (const std::string& name : chosen) {
    const SceneSpec& sp = spec(name);
    // Every engine's settings for this scene; each is timed once per round, the rounds one
    // after another, and the fastest run is kept: a slow spell of a shared machine then falls
    // on every engine alike instead of on whichever was being timed.
    struct Job {
      const Engine* engine;
      Settings settings;
      Outcome outcome;
      double fastest = std::numeric_limits<double>::infinity();
    };
    std::vector<Job> jobs;
    for (const Engine& e : engines) {
      if (sp.needsHands && !e.hands) continue;
      std::vector<Settings> grid = e.grid(name, o.quick);
      if (grid.empty()) continue;  // an engine that is not swept on this scene
      const bool hasDefault = std::any_of(grid.begin(), grid.end(), [&](const Settings& s) {
        return s.dt == e.defaults.dt && s.substeps == e.defaults.substeps &&
               s.iterations == e.defaults.iterations;
      });
      if (!hasDefault) grid.push_back(e.defaults);
      for (const Settings& s : grid) jobs.push_back({&e, s, Outcome{}});
    }
    for (int round = 0; round < o.repeats; ++round)
      for (Job& j : jobs)
        j.fastest = std::min(j.fastest, timingRun(sp, *j.engine, j.settings, o.quick, j.outcome));
    for (const Job& j : jobs) {
      out.push_back(sampleOf(*j.engine, sp, j.settings, j.outcome, j.fastest));
      if (progress) progress(out.back());
    }
  }
  return out;
}

}  // namespace grip::sweep
