#include "interaction/force_law.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
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

namespace {

enum class SpringState : uint8_t { Free, Stick, Slip };

// Where the cone solve keeps a spring's state between iterations: in its ConeResult's flags.
SpringState stateOf(const ConeResult& r) {
  return !r.compressive ? SpringState::Free : r.slipping ? SpringState::Slip : SpringState::Stick;
}

// The force of one spring in a given state, for e = p - C - h J V+ (see implicitConeForces).
Vec3 stateForce(SpringState st, const SpringPoint& s, const Vec3& e, const Vec3& slipDir,
                double muD, SlipLaw law) {
  if (st == SpringState::Free) return Vec3::Zero();
  if (st == SpringState::Stick) return s.stiffness * e;
  const double en = s.normal.dot(e);  // < 0 while it presses
  if (law == SlipLaw::ThesisLiteral) return s.stiffness * (muD * e + (1.0 - muD) * en * s.normal);
  return s.stiffness * en * (s.normal - muD * slipDir);
}

// Eq. 3.7 on the stick force k e: free, stick, or slip (with the tangential direction).
SpringState classify(const SpringPoint& s, const Vec3& e, double muS, Vec3& slipDir) {
  const double fn = -s.stiffness * s.normal.dot(e);
  if (!(fn > 0.0)) return SpringState::Free;
  const Vec3 ft = s.stiffness * e + fn * s.normal;
  const double ft2 = ft.squaredNorm();
  if (ft2 <= muS * fn * muS * fn) return SpringState::Stick;
  slipDir = ft / std::sqrt(ft2);
  return SpringState::Slip;
}

// 6-vector J^T u = (u, r x u): the wrench of a unit force u at r.
Twist wrench(const Vec3& u, const Vec3& r) {
  Twist w;
  w.head<3>() = u;
  w.tail<3>() = r.cross(u);
  return w;
}

}  // namespace

ConeSolveResult implicitConeForces(const RigidBodyState& body, std::span<const SpringPoint> springs,
                                   double muS, double muD, SlipLaw law, double h,
                                   std::span<ConeResult> out) {
  // Iterations that may also return springs to sticking; after them states only move toward
  // slip or free, so the loop ends.
  constexpr int kFreeIterations = 4;
  constexpr int kMaxIterations = 12;
  const size_t n = springs.size();
  for (size_t i = 0; i < n; ++i) {  // start: every pressing spring sticks
    out[i] = ConeResult{};
    out[i].compressive = springs[i].normal.dot(springs[i].target - springs[i].anchor) < 0.0;
  }
  const double h2 = h * h;
  ConeSolveResult res;
  for (res.iterations = 1;; ++res.iterations) {
    // (M + h^2 sum k J^T P J) V+ = M V + h (F_ext + sum J^T k P e), P by state. Sticking
    // springs by their moment sums, K = [[k0 I, -[k1]x], [[k1]x, k2]] with k2 = sum k (|r|^2 I -
    // r r^T), slipping ones as rank-one terms.
    double k0 = 0.0, kr2 = 0.0;
    Vec3 k1 = Vec3::Zero();
    Mat3 krr = Mat3::Zero();
    Mat6 lowRank = Mat6::Zero();
    Twist rhs = Twist::Zero();
    bool symmetric = true;
    for (size_t i = 0; i < n; ++i) {
      const SpringPoint& s = springs[i];
      const SpringState st = stateOf(out[i]);
      if (st == SpringState::Free) continue;
      const Vec3 r = s.anchor - body.com;
      const Vec3 e = s.target - s.anchor;
      double kStick = s.stiffness;
      if (st == SpringState::Slip) {
        const Twist b = wrench(s.normal, r);
        const double en = s.normal.dot(e);
        if (law == SlipLaw::ThesisLiteral) {  // mu_d of the whole spring, plus the normal rest
          const double kn = (1.0 - muD) * s.stiffness;
          lowRank.noalias() += (kn * b) * b.transpose();
          rhs += kn * en * b;
          kStick = muD * s.stiffness;
        } else {
          const Twist a = wrench(s.normal - muD * out[i].slipDirection, r);
          lowRank.noalias() += (s.stiffness * a) * b.transpose();
          rhs += s.stiffness * en * a;
          symmetric = false;
          continue;
        }
      }
      const Vec3 kr = kStick * r;
      k0 += kStick;
      k1 += kr;
      kr2 += kr.dot(r);
      krr.noalias() += kr * r.transpose();
      rhs.head<3>() += kStick * e;
      rhs.tail<3>() += kr.cross(e);
    }
    const Mat3 R = skew(k1);
    Mat6 A = h2 * lowRank;
    A.topLeftCorner<3, 3>().diagonal().array() += body.mass + h2 * k0;
    A.topRightCorner<3, 3>() -= h2 * R;
    A.bottomLeftCorner<3, 3>() += h2 * R;
    A.bottomRightCorner<3, 3>() += body.inertiaWorld - h2 * krr;
    A.bottomRightCorner<3, 3>().diagonal().array() += h2 * kr2;
    rhs *= h;
    rhs.head<3>() += body.mass * body.linearVelocity + h * body.externalForce;
    rhs.tail<3>() += body.inertiaWorld * body.angularVelocity + h * body.externalTorque;
    res.velocity = symmetric ? Twist(A.ldlt().solve(rhs)) : Twist(A.partialPivLu().solve(rhs));

    // The force of each spring in the state V+ was solved with (final if nothing changes), and
    // its classification at V+.
    bool changed = false;
    const bool mayStick = res.iterations <= kFreeIterations;
    for (size_t i = 0; i < n; ++i) {
      const SpringPoint& s = springs[i];
      ConeResult& o = out[i];
      const SpringState st = stateOf(o);
      const Vec3 e = s.target - s.anchor - h * pointVelocity(res.velocity, s.anchor - body.com);
      o.force = stateForce(st, s, e, o.slipDirection, muD, law);
      o.normalForce = std::max(-o.force.dot(s.normal), 0.0);
      Vec3 dir = o.slipDirection;
      SpringState next = classify(s, e, muS, dir);
      if (!mayStick && st != SpringState::Stick && next != SpringState::Free) next = st;
      if (!mayStick && st == SpringState::Free) next = st;
      // A slip direction that turned by less than about a degree is kept as solved with, so
      // that the forces stay the ones that produced V+.
      const bool turned = next == SpringState::Slip && law == SlipLaw::KineticCoulomb &&
                          (st != SpringState::Slip || dir.dot(o.slipDirection) < 0.9998);
      if (next == st && !turned) continue;
      changed = true;
      o.compressive = next != SpringState::Free;
      o.slipping = next == SpringState::Slip;
      if (next == SpringState::Slip) o.slipDirection = dir;
    }
    if (!changed) return res;
    if (res.iterations == kMaxIterations) break;
  }
  // The cap: the forces are those of the states the last V+ was solved with; the cone clips
  // what does not fit the states found at it.
  res.converged = false;
  for (size_t i = 0; i < n; ++i) {
    out[i] = frictionCone(out[i].force, springs[i].normal, muS, muD, law);
  }
  return res;
}

}  // namespace grip
