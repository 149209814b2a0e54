// The two-finger hold threshold (grip only: the peers have no hand interaction). Two fingertips
// pinch a 0.1 kg, 6 cm cube in mid-air at depth δ while its weight comes in over a second (an
// upward force cancels gravity at first); the cube is held when 2 μs γ δ ≥ m g (thesis 3.5).
// The sweep finds the smallest depth that holds by bisection and compares it with
// m g / (2 μs γ). The load is quasi-static on purpose: the law is a static one. Lifting the cube
// off a floor adds the lift's own transient (the fingers start at 5 cm/s), and once the cube
// slips the kinetic μd = 0.8 μs cannot stop it: that threshold is higher (docs/accuracy.md).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "interaction/interaction.hpp"
#include "interaction/scenarios.hpp"
#include "sweep/detail.hpp"

namespace grip::sweep::detail {

namespace {

constexpr double kMass = 0.1, kHalf = 0.03;

// Squeeze 0.25 s, weight in over 1 s, hold 1 s; true when the cube stayed with the fingers.
bool holds(const Settings& s, double depth, double& wall, double& simulated) {
  WorldDef wd;
  wd.substeps = s.substeps;
  wd.maxSubstep = std::max(wd.maxSubstep, s.dt / s.substeps);  // the setting swept, as it is
  wd.relaxIterations = s.iterations;
  World w(wd);
  Interaction ix;
  const Vec3 c(0.0, 0.5, 0.0);
  const BodyId cube = scenarios::addBox(w, Vec3::Constant(kHalf), kMass, c);
  const HandDef hd;
  const HandId h = ix.addHand(hd);
  const long squeeze = std::lround(0.25 / s.dt), ramp = std::lround(1.0 / s.dt);
  const long steps = squeeze + 2 * ramp;
  const double g = -wd.gravity.y();
  for (long i = 0; i < steps; ++i) {
    const double weight = std::clamp(double(i - squeeze) / double(ramp), 0.0, 1.0);
    w.addForce(cube, Vec3(0.0, (1.0 - weight) * kMass * g, 0.0));
    ix.setHandPose(h, scenarios::pinchCube(hd, c, kHalf, depth));
    const auto t0 = std::chrono::steady_clock::now();
    ix.step(w, s.dt);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  simulated += steps * s.dt;
  return c.y() - w.centerOfMass(cube).y() < 0.01;  // within 1 cm of the fingers
}

}  // namespace

Outcome hold(const Settings& s) {
  const InteractionDef def;
  const double expected = kMass * 9.81 / (2.0 * def.skin.staticFriction * def.gamma);
  Outcome o;
  o.simulated = o.wall = 0;
  // The threshold within ±50 % of the analytic one, to 1/1024 of it by bisection; a threshold
  // outside the bracket reports the bracket's edge (error 0.5).
  double lo = 0.5 * expected, hi = 1.5 * expected;
  if (holds(s, lo, o.wall, o.simulated)) {
    hi = lo;
  } else if (!holds(s, hi, o.wall, o.simulated)) {
    lo = hi;
  }
  for (int i = 0; i < 10 && hi > lo; ++i) {
    const double mid = 0.5 * (lo + hi);
    (holds(s, mid, o.wall, o.simulated) ? hi : lo) = mid;
  }
  o.error2 = (0.5 * (lo + hi) - expected) / expected;  // signed: < 0 holds below the answer
  o.error = std::abs(o.error2);
  return o;
}

}  // namespace grip::sweep::detail
