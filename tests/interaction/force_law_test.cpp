// The force law and the implicit spring as pure functions, checked against a hand-written
// semi-implicit Euler rigid-body integrator (the same scheme the World uses: v += h F/m, then
// x += h v).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "interaction/force_law.hpp"

namespace grip {
namespace {

TEST(FrictionCone, PressingIntoTheBodyIsCompressiveAndSticksInsideTheCone) {
  // Top face of a box, outward normal +Y; a finger above pushes down on it.
  const Vec3 n = Vec3::UnitY();
  ConeResult r = frictionCone(Vec3(0.1, -1.0, 0.0), n, 0.5, 0.4, SlipLaw::KineticCoulomb);
  EXPECT_TRUE(r.compressive);
  EXPECT_FALSE(r.slipping);
  EXPECT_DOUBLE_EQ(r.normalForce, 1.0);
  EXPECT_EQ(r.force, Vec3(0.1, -1.0, 0.0));
}

TEST(FrictionCone, PullingAwayTransmitsNothing) {
  const Vec3 n = Vec3::UnitY();
  for (SlipLaw law : {SlipLaw::KineticCoulomb, SlipLaw::ThesisLiteral}) {
    ConeResult r = frictionCone(Vec3(0.3, 1.0, 0.0), n, 0.5, 0.4, law);
    EXPECT_FALSE(r.compressive);
    EXPECT_EQ(r.force, Vec3::Zero());
  }
}

TEST(FrictionCone, SlipLawsCapOrScaleTheTangentialPart) {
  const Vec3 n = Vec3::UnitY();
  const Vec3 f(2.0, -1.0, 0.0);  // |f_t| = 2 > 0.5 * 1
  ConeResult kinetic = frictionCone(f, n, 0.5, 0.4, SlipLaw::KineticCoulomb);
  EXPECT_TRUE(kinetic.slipping);
  EXPECT_NEAR(kinetic.force.x(), 0.4 * 1.0, 1e-15);  // mu_d |f_n|
  EXPECT_DOUBLE_EQ(kinetic.force.y(), -1.0);
  ConeResult literal = frictionCone(f, n, 0.5, 0.4, SlipLaw::ThesisLiteral);
  EXPECT_TRUE(literal.slipping);
  EXPECT_NEAR(literal.force.x(), 0.4 * 2.0, 1e-15);  // mu_d f_t
  EXPECT_DOUBLE_EQ(literal.force.y(), -1.0);
}

TEST(FrictionCone, SlipShiftPutsTheStretchOnTheKineticCone) {
  const Vec3 n = Vec3::UnitY();
  const Vec3 stretch(0.01, -0.004, 0.003);  // depth 4 mm, tangential 10.4 mm
  const Vec3 shift = slipShift(stretch, n, 0.5);
  const Vec3 e = stretch - shift;  // the stretch after C moved by `shift`
  EXPECT_NEAR(shift.dot(n), 0.0, 1e-18);
  EXPECT_NEAR(std::hypot(e.x(), e.z()), 0.5 * 0.004, 1e-15);
  EXPECT_EQ(slipShift(Vec3(0.001, -0.004, 0.0), n, 0.5), Vec3::Zero());  // inside: no shift
}

TEST(AutoTuneGamma, HoldsTheBodyAtTwentyPercentDepth) {
  const double m = 0.2, g = 9.81, mu = 0.46, d = 0.1;
  const double gamma = autoTuneGamma(m, g, mu, d);
  EXPECT_NEAR(mu * gamma * 0.2 * d, m * g, 1e-12);
  EXPECT_THROW(autoTuneGamma(0.0, g, mu, d), Error);
}

// ---- Implicit spring against a hand-written integrator -----------------------------------

struct Body {
  double mass = 1.0;
  double inertia = 1.0;  // isotropic, so the world inertia never changes
  Vec3 x = Vec3::Zero();
  Quat q = Quat::Identity();
  Vec3 v = Vec3::Zero();
  Vec3 w = Vec3::Zero();
};

struct Spring {
  Vec3 local;   // anchor in body coordinates
  Vec3 target;  // world, fixed
  double k;
};

RigidBodyState stateOf(const Body& b, const Vec3& gravity) {
  RigidBodyState s;
  s.mass = b.mass;
  s.inertiaWorld = b.inertia * Mat3::Identity();
  s.com = b.x;
  s.linearVelocity = b.v;
  s.angularVelocity = b.w;
  s.externalForce = b.mass * gravity;
  return s;
}

// One step: spring forces (implicit or explicit), then semi-implicit Euler.
void stepBody(Body& b, const std::vector<Spring>& springs, const Vec3& gravity, double h,
              bool implicit) {
  const RigidBodyState s = stateOf(b, gravity);
  std::vector<SpringPoint> pts;
  for (const Spring& sp : springs) pts.push_back({b.x + b.q * sp.local, sp.target, sp.k});
  const Twist vNext = implicitVelocity(s, pts, h);
  Vec3 F = b.mass * gravity, T = Vec3::Zero();
  for (const SpringPoint& p : pts) {
    const Vec3 f =
        implicit ? implicitSpringForce(s, p, vNext, h) : p.stiffness * (p.target - p.anchor);
    F += f;
    T += (p.anchor - b.x).cross(f);
  }
  b.v += h * F / b.mass;
  b.w += h * T / b.inertia;
  b.x += h * b.v;
  b.q = integrateRotation(b.q, b.w, h);
}

double energy(const Body& b, const std::vector<Spring>& springs, const Vec3& gravity) {
  double e = 0.5 * b.mass * b.v.squaredNorm() + 0.5 * b.inertia * b.w.squaredNorm() -
             b.mass * gravity.dot(b.x);
  for (const Spring& sp : springs) {
    e += 0.5 * sp.k * (sp.target - (b.x + b.q * sp.local)).squaredNorm();
  }
  return e;
}

TEST(ImplicitSpring, ForcesThroughTheIntegratorGiveExactlyThePredictedVelocity) {
  Body b;
  b.mass = 0.3;
  b.inertia = 0.002;
  b.v = Vec3(0.1, -0.2, 0.05);
  b.w = Vec3(1.0, 0.5, -2.0);
  std::vector<Spring> springs = {{Vec3(0.05, 0.01, 0.0), Vec3(0.04, 0.0, 0.01), 400.0},
                                 {Vec3(-0.05, 0.0, 0.02), Vec3(-0.03, 0.01, 0.0), 250.0},
                                 {Vec3(0.0, 0.05, 0.0), Vec3(0.01, 0.045, 0.0), 100.0}};
  const double h = 1.0 / 60.0;
  const Vec3 g(0.0, -9.81, 0.0);
  std::vector<SpringPoint> pts;
  for (const Spring& sp : springs) pts.push_back({b.x + b.q * sp.local, sp.target, sp.k});
  const Twist predicted = implicitVelocity(stateOf(b, g), pts, h);
  stepBody(b, springs, g, h, true);
  EXPECT_LT((b.v - predicted.head<3>()).norm(), 1e-12);
  EXPECT_LT((b.w - predicted.tail<3>()).norm(), 1e-12);
}

TEST(ImplicitSpring, AtRestInEquilibriumItIsTheThesisForce) {
  // Two springs holding a body against gravity, already at rest in equilibrium: V+ = 0 and the
  // implicit force equals gamma (p - C) exactly.
  Body b;
  b.mass = 0.2;
  const double k = 400.0;
  const double sag = b.mass * 9.81 / (2.0 * k);
  std::vector<Spring> springs = {{Vec3(0.02, 0.0, 0.0), Vec3(0.02, sag, 0.0), k},
                                 {Vec3(-0.02, 0.0, 0.0), Vec3(-0.02, sag, 0.0), k}};
  std::vector<SpringPoint> pts;
  for (const Spring& sp : springs) pts.push_back({sp.local, sp.target, sp.k});
  const RigidBodyState s = stateOf(b, Vec3(0.0, -9.81, 0.0));
  const Twist vNext = implicitVelocity(s, pts, 1.0 / 60.0);
  EXPECT_LT(vNext.norm(), 1e-15);
  for (const SpringPoint& p : pts) {
    EXPECT_LT((implicitSpringForce(s, p, vNext, 1.0 / 60.0) - k * (p.target - p.anchor)).norm(),
              1e-15);
  }
}

// A pinch: two opposing springs squeezing a body, displaced and spinning. omega*dt is far
// above 2 for both cases, where explicit springs must diverge.
struct PinchCase {
  double mass, inertia, kTotal;
  int points;
};

std::vector<Spring> pinchSprings(const PinchCase& c) {
  std::vector<Spring> s;
  const double k = c.kTotal / c.points;
  for (int i = 0; i < c.points; ++i) {
    const double side = i % 2 == 0 ? 1.0 : -1.0;
    const double a = 0.3 * i;
    const Vec3 local(side * 0.02, 0.01 * std::cos(a), 0.01 * std::sin(a));
    s.push_back({local, local - side * Vec3(0.004, 0.0, 0.0), k});
  }
  return s;
}

void runPinch(const PinchCase& c, bool implicit, double& maxGrowth, double& finalEnergy) {
  Body b;
  b.mass = c.mass;
  b.inertia = c.inertia;
  b.x = Vec3(0.003, -0.002, 0.001);
  b.v = Vec3(0.05, 0.0, -0.02);
  b.w = Vec3(0.0, 2.0, 1.0);
  const std::vector<Spring> springs = pinchSprings(c);
  const Vec3 g(0.0, -9.81, 0.0);
  const double h = 1.0 / 60.0;
  double e = energy(b, springs, g);
  maxGrowth = 0.0;
  for (int i = 0; i < 120; ++i) {
    stepBody(b, springs, g, h, implicit);
    const double e2 = energy(b, springs, g);
    maxGrowth = std::max(maxGrowth, e2 - e);
    e = e2;
    if (!std::isfinite(e) || std::abs(e) > 1e6) break;
  }
  finalEnergy = e;
}

TEST(ImplicitSpring, TenGramPinchAtSixtyHertzNeverGainsEnergy) {
  const PinchCase c{0.01, 1e-6, 2 * 400.0, 18};  // k/m h^2 = 22
  double growth = 0, finalE = 0;
  runPinch(c, true, growth, finalE);
  EXPECT_LE(growth, 1e-12);
  EXPECT_TRUE(std::isfinite(finalE));
  runPinch(c, false, growth, finalE);  // the evidence: explicit springs blow up here
  EXPECT_TRUE(!std::isfinite(finalE) || std::abs(finalE) > 1e3);
}

TEST(ImplicitSpring, CubeHeldByThirtyTwoPatchesNeverGainsEnergy) {
  const PinchCase c{0.2, 0.2 * 0.1 * 0.1 / 6.0, 32 * 400.0, 32 * 9};  // k/m h^2 = 17.8
  double growth = 0, finalE = 0;
  runPinch(c, true, growth, finalE);
  EXPECT_LE(growth, 1e-12);
  EXPECT_TRUE(std::isfinite(finalE));
  runPinch(c, false, growth, finalE);
  EXPECT_TRUE(!std::isfinite(finalE) || std::abs(finalE) > 1e3);
}

// ---- The friction cone inside the implicit solve -------------------------------------------

// A 0.1 kg body pressed by `count` springs on its -y face; each target sits 2 mm into the face
// and `shear` to the side, so that with a large shear every spring is far outside the cone.
std::vector<SpringPoint> shearedPatch(int count, const Vec3& shear) {
  std::vector<SpringPoint> pts;
  for (int i = 0; i < count; ++i) {
    const Vec3 c(0.01 * (i % 3 - 1), -0.02, 0.01 * (i / 3 - 1));
    pts.push_back({c, c + Vec3(0.0, 0.002, 0.0) + shear, 400.0 / count, -Vec3::UnitY()});
  }
  return pts;
}

RigidBodyState smallBody() {
  RigidBodyState s;
  s.mass = 0.1;
  s.inertiaWorld = 2e-5 * Mat3::Identity();
  s.linearVelocity = Vec3(0.01, 0.0, -0.02);
  s.externalForce = Vec3(0.0, -0.981, 0.0);
  return s;
}

// The twist the forces give through the integrator (v += h F / m, w += h I^-1 T).
Twist integrate(const RigidBodyState& s, std::span<const SpringPoint> pts,
                std::span<const ConeResult> out, double h) {
  Vec3 F = s.externalForce, T = s.externalTorque;
  for (size_t i = 0; i < pts.size(); ++i) {
    F += out[i].force;
    T += (pts[i].anchor - s.com).cross(out[i].force);
  }
  Twist v;
  v.head<3>() = s.linearVelocity + h * F / s.mass;
  v.tail<3>() = s.angularVelocity + h * s.inertiaWorld.inverse() * T;
  return v;
}

TEST(ConeSolve, InsideTheConeItIsThePlainImplicitSpring) {
  const RigidBodyState s = smallBody();
  const std::vector<SpringPoint> pts = shearedPatch(9, Vec3(0.0002, 0.0, 0.0));
  const double h = 1.0 / 60.0;
  std::vector<ConeResult> out(pts.size());
  const ConeSolveResult r =
      implicitConeForces(s, pts, 0.46, 0.368, SlipLaw::KineticCoulomb, h, out);
  const Twist plain = implicitVelocity(s, pts, h);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_LT((r.velocity - plain).norm(), 1e-12);
  for (size_t i = 0; i < pts.size(); ++i) {
    EXPECT_FALSE(out[i].slipping);
    EXPECT_LT((out[i].force - implicitSpringForce(s, pts[i], plain, h)).norm(), 1e-12);
  }
}

// Every sample sheared far outside the cone (10 cm of tangential stretch on a 2 mm press): the
// stick-only solve predicts a velocity that drags the body 10 cm in one step, and its forces,
// clipped by the cone afterwards, no longer produce that velocity. With the cone in the solve
// the forces are on the kinetic cone, produce exactly the solved velocity through the
// integrator, and the body gets only what kinetic friction can give: mu_d times the normal
// force, over the step.
TEST(ConeSolve, HeavySlipGivesKineticFrictionAndAConsistentVelocity) {
  const RigidBodyState s = smallBody();
  const double h = 1.0 / 60.0, muS = 0.46, muD = 0.368;
  for (SlipLaw law : {SlipLaw::KineticCoulomb, SlipLaw::ThesisLiteral}) {
    const std::vector<SpringPoint> pts = shearedPatch(9, Vec3(0.1, 0.0, 0.0));
    std::vector<ConeResult> out(pts.size());
    const ConeSolveResult r = implicitConeForces(s, pts, muS, muD, law, h, out);
    EXPECT_TRUE(r.converged) << slipLawName(law);
    EXPECT_LT((integrate(s, pts, out, h) - r.velocity).norm(), 1e-12) << slipLawName(law);
    double fn = 0.0, ft = 0.0;
    for (size_t i = 0; i < pts.size(); ++i) {
      const double n = -out[i].force.dot(pts[i].normal);
      const Vec3 t = out[i].force + n * pts[i].normal;
      EXPECT_GE(n, 0.0);                     // never pulling
      if (law == SlipLaw::KineticCoulomb) {  // (the literal law's slip has no cap)
        ASSERT_TRUE(out[i].slipping);
        EXPECT_NEAR(t.norm(), muD * n, 1e-12);
      }
      fn += n;
      ft += t.x();
    }
    if (law == SlipLaw::KineticCoulomb) {
      // The body's x velocity changes by h * mu_d * sum f_n / m, not by the 10 cm of stretch.
      EXPECT_NEAR(r.velocity.x(), s.linearVelocity.x() + h * ft / s.mass, 1e-12);
      EXPECT_LT(r.velocity.x(), s.linearVelocity.x() + h * muD * fn / s.mass + 1e-12);
    }
  }
  // The stick-only solve, clipped afterwards: inconsistent (what the World would do with the
  // clipped forces differs from the velocity the sticking assumption used).
  const std::vector<SpringPoint> pts = shearedPatch(9, Vec3(0.1, 0.0, 0.0));
  const Twist stick = implicitVelocity(s, pts, h);
  std::vector<ConeResult> clipped;
  for (const SpringPoint& p : pts) {
    clipped.push_back(frictionCone(implicitSpringForce(s, p, stick, h), p.normal, muS, muD,
                                   SlipLaw::KineticCoulomb));
  }
  EXPECT_GT((integrate(s, pts, clipped, h) - stick).norm(), 0.1);
}

TEST(ConeSolve, TensileSamplesTransmitNothingAndLeaveTheSolve) {
  RigidBodyState s = smallBody();
  s.externalForce.setZero();
  std::vector<SpringPoint> pts = shearedPatch(9, Vec3::Zero());
  for (size_t i = 0; i < 4; ++i) pts[i].target = pts[i].anchor - Vec3(0.0, 0.001, 0.0);  // out
  const double h = 1.0 / 60.0;
  std::vector<ConeResult> out(pts.size());
  const ConeSolveResult r =
      implicitConeForces(s, pts, 0.46, 0.368, SlipLaw::KineticCoulomb, h, out);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_FALSE(out[i].compressive);
    EXPECT_EQ(out[i].force, Vec3::Zero());
  }
  for (size_t i = 4; i < pts.size(); ++i) EXPECT_GT(-out[i].force.dot(pts[i].normal), 0.0);
  EXPECT_LT((integrate(s, pts, out, h) - r.velocity).norm(), 1e-12);
}

}  // namespace
}  // namespace grip
