#include "interaction/force_law.hpp"

#include <Eigen/Cholesky>
#include <cmath>

#include "core/error.hpp"

namespace grip {

const char* slipLawName(SlipLaw s) {
  return s == SlipLaw::KineticCoulomb ? "kinetic_coulomb" : "thesis_literal";
}

ConeResult frictionCone(const Vec3& f, const Vec3& n, double muStatic, double muDynamic,
                        SlipLaw law) {
  ConeResult r;
  const double fn = -f.dot(n);  // compressive magnitude
  if (!(fn > 0.0)) return r;    // tensile or zero: no adhesion
  r.compressive = true;
  r.normalForce = fn;
  const Vec3 normalPart = -fn * n;         // eq. 3.5, pointing into the body
  const Vec3 tangential = f - normalPart;  // eq. 3.6
  const double ft2 = tangential.squaredNorm();
  const double limit = muStatic * fn;
  if (ft2 <= limit * limit) {  // eq. 3.7: inside the cone, stick (no square root needed)
    r.force = f;
    return r;
  }
  const double ft = std::sqrt(ft2);
  r.slipping = true;
  if (law == SlipLaw::ThesisLiteral) {
    r.force = normalPart + muDynamic * tangential;  // eq. 3.8 as written
  } else {
    r.force = normalPart + (muDynamic * fn / ft) * tangential;
  }
  return r;
}

Vec3 slipShift(const Vec3& stretch, const Vec3& n, double muDynamic) {
  const double depth = -stretch.dot(n);
  if (!(depth > 0.0)) return Vec3::Zero();
  const Vec3 et = stretch + depth * n;
  const double len = et.norm();
  const double allowed = muDynamic * depth;
  if (len <= allowed) return Vec3::Zero();
  return (1.0 - allowed / len) * et;
}

double autoTuneGamma(double mass, double gravity, double mu, double diameter) {
  requirePositive(mass, "mass");
  requirePositive(gravity, "gravity");
  requirePositive(mu, "mu");
  requirePositive(diameter, "diameter");
  return mass * gravity / (mu * 0.2 * diameter);
}

SkinFriction skinFriction(SkinContactMaterial m) {
  double mu = 0.46;
  switch (m) {
    case SkinContactMaterial::Average:
      mu = 0.46;
      break;
    case SkinContactMaterial::Silicone:
      mu = 0.61;
      break;
    case SkinContactMaterial::Nylon:
      mu = 0.37;
      break;
    case SkinContactMaterial::PalmSkinAverage:
      mu = 0.62;
      break;
  }
  return {mu, kDynamicOverStatic * mu};
}

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

// J maps the twist to the velocity of the point: v + w x r = v - [r]x w.
Vec3 pointVelocity(const Twist& V, const Vec3& r) {
  return V.head<3>() + V.tail<3>().cross(r);
}

}  // namespace

Twist implicitVelocity(const RigidBodyState& body, std::span<const SpringPoint> springs, double h) {
  // K = sum k J^T J with J = [I, -[r]x] is [[sum k I, -[sum k r]x], [[sum k r]x, sum k (|r|^2 I
  // - r r^T)]]: three moment sums instead of a 6x6 per spring.
  double k0 = 0.0;
  Vec3 k1 = Vec3::Zero();
  Mat3 k2 = Mat3::Zero();
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  for (const SpringPoint& s : springs) {
    const Vec3 r = s.anchor - body.com;
    const double k = s.stiffness;
    k0 += k;
    k1 += k * r;
    k2 += k * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
    const Vec3 f = k * (s.target - s.anchor);
    force += f;
    torque += r.cross(f);
  }
  const double h2 = h * h;
  const Mat3 R = skew(k1);
  Mat6 A;
  A.topLeftCorner<3, 3>() = (body.mass + h2 * k0) * Mat3::Identity();
  A.topRightCorner<3, 3>() = -h2 * R;
  A.bottomLeftCorner<3, 3>() = h2 * R;
  A.bottomRightCorner<3, 3>() = body.inertiaWorld + h2 * k2;
  Twist rhs;
  rhs.head<3>() = body.mass * body.linearVelocity + h * (body.externalForce + force);
  rhs.tail<3>() = body.inertiaWorld * body.angularVelocity + h * (body.externalTorque + torque);
  return A.ldlt().solve(rhs);
}

Vec3 implicitSpringForce(const RigidBodyState& body, const SpringPoint& s, const Twist& vNext,
                         double h) {
  const Vec3 r = s.anchor - body.com;
  return s.stiffness * (s.target - s.anchor - h * pointVelocity(vNext, r));
}

}  // namespace grip
