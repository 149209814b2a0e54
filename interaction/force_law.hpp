// The thesis's contact force law (3.5.5, eqs. 3.4-3.11) as pure functions, with the signs made
// explicit, and the linearly implicit spring that keeps it stable on light objects.
//
// Signs: C is the contact point on the body surface, n the OUTWARD surface normal at C, p the
// tracked point on the bone. The thesis's f = gamma (C - p) (eq. 3.4) is the force on the bone;
// everything here works with the force ON THE OBJECT, f = gamma (p - C). The bone presses into
// the body when that force points into it: f . (-n) > 0.
#pragma once

#include <cstdint>
#include <span>

#include <Eigen/Core>

#include "core/math.hpp"

namespace grip {

// What a contact outside the static friction cone transmits tangentially (eq. 3.8).
enum class SlipLaw : uint8_t {
  // Coulomb's kinetic law: tangential magnitude mu_d |f_n| along f_t. The default: it is the one
  // with a hold threshold (2 mu gamma delta = m g) that the tests can find on both sides.
  KineticCoulomb,
  // The thesis as written: tangential = mu_d * f_t (no cap). Kept to reproduce the thesis.
  ThesisLiteral,
};
const char* slipLawName(SlipLaw s);

struct ConeResult {
  Vec3 force = Vec3::Zero();          // on the object, after the cone
  double normalForce = 0.0;           // compressive magnitude f . (-n) (0 when tensile)
  bool compressive = false;           // false: the bone pulls; no adhesion, so no force at all
  bool slipping = false;              // outside the static cone (eq. 3.7)
  Vec3 slipDirection = Vec3::Zero();  // implicitConeForces: unit tangential direction of a slip
};

// Eqs. 3.5-3.8 on one force f (on the object) at a point with outward normal n. A tensile force
// (f . n >= 0) transmits nothing: skin does not stick to objects.
ConeResult frictionCone(const Vec3& f, const Vec3& n, double muStatic, double muDynamic,
                        SlipLaw law);

// Surface update for a slipping contact (3.5.3, as DESIGN.md reads it): the tangential shift of
// the contact point that puts the elastic stretch e = p - C back on the kinetic cone,
// |e_t| = mu_d * depth. Zero when the stretch is inside that cone or tensile.
Vec3 slipShift(const Vec3& stretch, const Vec3& n, double muDynamic);

// Eq. 3.11: the smallest gamma that can hold a body of mass m with friction mu when the bones
// sink at most 20 % of the bounding-sphere diameter d into it.
double autoTuneGamma(double mass, double gravity, double mu, double diameter);

// Skin friction from Zhang & Mak 1999 ("In vivo friction properties of human skin", Prosthetics
// and Orthotics International 23(2)): measured means over ten subjects and six sites. Their
// measurement gives one coefficient per material; we use it as the static coefficient and take
// the dynamic one as kDynamicOverStatic of it (an assumption, stated in docs/interaction.md).
struct SkinFriction {
  double staticFriction = 0.46;  // all materials and sites, 0.46 +- 0.15
  double dynamicFriction = 0.46 * 0.8;
};
inline constexpr double kDynamicOverStatic = 0.8;
enum class SkinContactMaterial : uint8_t { Average, Silicone, Nylon, PalmSkinAverage };
SkinFriction skinFriction(SkinContactMaterial m);

// ---- The linearly implicit spring (see docs/interaction.md, "Stability") --------------------

// One body at the start of the step, in world coordinates.
struct RigidBodyState {
  double mass = 1.0;
  Mat3 inertiaWorld = Mat3::Identity();  // about the centre of mass
  Vec3 com = Vec3::Zero();
  Vec3 linearVelocity = Vec3::Zero();
  Vec3 angularVelocity = Vec3::Zero();
  Vec3 externalForce = Vec3::Zero();   // gravity and other known forces for this step
  Vec3 externalTorque = Vec3::Zero();  // about the centre of mass
};

// One spring from a point C fixed on the body (anchor) to a tracked target p, stiffness k.
struct SpringPoint {
  Vec3 anchor = Vec3::Zero();
  Vec3 target = Vec3::Zero();
  double stiffness = 0.0;
  Vec3 normal = Vec3::UnitY();  // outward surface normal at the anchor (for the cone)
};

using Twist = Eigen::Matrix<double, 6, 1>;  // (v, w) of the centre of mass

// The velocity twist at the end of a step of length h under the springs evaluated at the end of
// the step: (M + h^2 K) V+ = M V + h (b + F_ext), K = sum k J^T J, b = sum J^T k (p - C).
Twist implicitVelocity(const RigidBodyState& body, std::span<const SpringPoint> springs, double h);
// The spring force on the object at the end of the step: k (p - C - h J V+).
Vec3 implicitSpringForce(const RigidBodyState& body, const SpringPoint& s, const Twist& vNext,
                         double h);

// The implicit spring with the friction cone inside the solve. Every spring is in one of three
// states, each a linear force law in V+ (with e = p - C - h J V+):
//   stick:  f = k e                               (inside the static cone)
//   slip:   f = k (n - mu_d t) n^T e              (KineticCoulomb: the normal spring, and
//           mu_d times that normal force along the tangential direction t; ThesisLiteral:
//           f = k (n n^T + mu_d (I - n n^T)) e)
//   free:   f = 0                                 (tensile: no adhesion)
// The states are found by iterating solve -> classify with eq. 3.7 on the stick force at the
// solved V+ until nothing changes (a few iterations; after kFreeIterations states only move
// toward slip or free, so the loop ends). The forces returned are the ones that produce V+
// through the integrator exactly, so sticking samples never brace against a velocity that the
// slipping ones do not deliver (the launch of heavy slipping with a stick-only solve).
struct ConeSolveResult {
  Twist velocity = Twist::Zero();  // V+
  int iterations = 0;
  bool converged = true;  // false: the cap was hit; the forces are then clipped to the cone
};
ConeSolveResult implicitConeForces(const RigidBodyState& body, std::span<const SpringPoint> springs,
                                   double muStatic, double muDynamic, SlipLaw law, double h,
                                   std::span<ConeResult> out);

}  // namespace grip
