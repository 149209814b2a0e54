// Random and adversarial input through the public API. Non-finite input is rejected with
// grip::Error and leaves the world as it was; huge but finite input never puts NaN or inf
// into any body.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>

#include "stress_util.hpp"

using namespace grip;
using namespace grip::stress;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMax = std::numeric_limits<double>::max();

// A small scene with bodies of every kind, already moving.
struct Scene {
  World w;
  std::vector<BodyId> dynamic;
  explicit Scene(const WorldDef& def = WorldDef{}) : w(def) {
    scenes::addGround(w);
    addBody(w, Shape::box(Vec3(0.5, 0.1, 0.5)), Vec3(2, 0.1, 0), 0.0, BodyType::Static);
    dynamic = scenes::addBoxStack(w, 3);
    dynamic.push_back(addBody(w, Shape::sphere(0.1), Vec3(0.5, 0.5, 0)));
    dynamic.push_back(addBody(w, Shape::capsule(0.05, 0.1), Vec3(-0.5, 0.5, 0)));
    dynamic.push_back(addBody(w, Shape::box(Vec3(0.1, 0.1, 0.1)), Vec3(2, 0.5, 0), 0.01));
    for (int i = 0; i < 10; ++i) w.step(1.0 / 60.0);
  }
};

// Values that break naive code: huge (up to 1e30), tiny, subnormal, signed zero. Larger
// finite values have their own tests below.
double nastyValue(std::mt19937_64& rng) {
  static const double values[] = {1e30, -1e30, 1e15,  -1e15, 1e-300, 4.9e-324, -0.0, 0.0,
                                  1.0,  -1.0,  1e-12, 3.5,   -250.0, 1e8,      -1e8, 0.5};
  return values[rng() % (sizeof values / sizeof values[0])];
}

// One nasty component among ordinary ones.
Vec3 nastyVec(std::mt19937_64& rng) {
  Vec3 v(0.1 * static_cast<double>(rng() % 21) - 1.0, 0.5, -0.3);
  v[static_cast<int>(rng() % 3)] = nastyValue(rng);
  return v;
}

// Calls one public entry point with the given arguments; returns the name of the call.
std::string callOne(World& w, BodyId id, int which, const Vec3& a, const Vec3& b) {
  switch (which) {
    case 0:
      w.addForce(id, a);
      return "addForce";
    case 1:
      w.addForceAtPosition(id, a, b);
      return "addForceAtPosition";
    case 2:
      w.addTorque(id, a);
      return "addTorque";
    case 3:
      w.addForce(id, a, ForceMode::Impulse);
      return "addForce(Impulse)";
    case 4:
      w.addTorque(id, a, ForceMode::VelocityChange);
      return "addTorque(VelocityChange)";
    case 5:
      w.setLinearVelocity(id, a);
      return "setLinearVelocity";
    case 6:
      w.setAngularVelocity(id, a);
      return "setAngularVelocity";
    case 7:
      w.setPose(id, a, Quat(1.0, b.x(), b.y(), b.z()));
      return "setPose";
    case 8:
      w.setGravity(a);
      return "setGravity";
    default:
      w.step(a.x());
      return "step";
  }
}

}  // namespace

TEST(Adversarial, NonFiniteInputIsRejectedAndChangesNothing) {
  Scene s;
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const BodyId id = s.dynamic[rng() % s.dynamic.size()];
    const int which = static_cast<int>(rng() % 10);
    Vec3 a = nastyVec(rng), b = nastyVec(rng);
    // The first argument is always non-finite (step reads a.x() as dt).
    const double bad = (trial % 3 == 0) ? kNaN : (trial % 3 == 1) ? kInf : -kInf;
    a[which == 9 ? 0 : static_cast<int>(rng() % 3)] = bad;
    const uint64_t before = s.w.stateHash();
    const Vec3 force = s.w.accumulatedForce(id), torque = s.w.accumulatedTorque(id);
    const Vec3 gravity = s.w.gravity();
    std::string call;
    bool threw = false;
    try {
      call = callOne(s.w, id, which, a, b);
    } catch (const Error& e) {
      threw = true;
      EXPECT_FALSE(e.field().empty()) << e.what();
    }
    ASSERT_TRUE(threw) << "call " << which << " accepted a=" << a.transpose()
                       << " b=" << b.transpose();
    ASSERT_EQ(s.w.stateHash(), before) << "call " << which << " changed the world";
    ASSERT_EQ(s.w.accumulatedForce(id), force) << "call " << which;
    ASSERT_EQ(s.w.accumulatedTorque(id), torque) << "call " << which;
    ASSERT_EQ(s.w.gravity(), gravity) << "call " << which;
    if (trial % 100 == 0) s.w.step(1.0 / 60.0);
  }
  EXPECT_TRUE(allFinite(s.w));
}

TEST(Adversarial, HugeFiniteInputNeverMakesNaNOrInf) {
  Scene s;
  std::mt19937_64 rng(11);
  int accepted = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const BodyId id = s.dynamic[rng() % s.dynamic.size()];
    const int which = static_cast<int>(rng() % 8);  // forces, velocities and poses
    const Vec3 a = nastyVec(rng), b = nastyVec(rng);
    std::string call;
    try {
      call = callOne(s.w, id, which, a, b);
      ++accepted;
    } catch (const Error&) {
      continue;  // e.g. a zero quaternion: rejected, fine
    }
    s.w.step(1.0 / 60.0);
    std::string bad;
    ASSERT_TRUE(allFinite(s.w, &bad)) << bad << " after " << call << "(" << a.transpose() << ", "
                                      << b.transpose() << ") in trial " << trial;
  }
  EXPECT_GT(accepted, 1000);
}

TEST(Adversarial, HugeVelocitiesAreClampedNotPropagated) {
  Scene s;
  for (BodyId id : s.dynamic) s.w.setLinearVelocity(id, Vec3(1e30, -1e30, 1e30));
  for (int i = 0; i < 60; ++i) {
    s.w.step(1.0 / 60.0);
    std::string bad;
    ASSERT_TRUE(allFinite(s.w, &bad)) << bad << " at step " << i;
    ASSERT_LE(maxSpeed(s.w), 1.01 * s.w.def().maxLinearSpeed) << "step " << i;
  }
}

// Found here: without a spin limit, a body spinning at 1e30 rad/s handed 5e4 m/s to what it
// touched, past WorldDef.maxLinearSpeed. WorldDef.maxAngularSpeed now caps the spin.
TEST(Adversarial, HugeSpinDoesNotBypassTheSpeedClamp) {
  Scene s;
  for (BodyId id : s.dynamic) s.w.setAngularVelocity(id, Vec3(1e30, 2e30, -1e30));
  for (int i = 0; i < 60; ++i) {
    s.w.step(1.0 / 60.0);
    ASSERT_LE(maxSpeed(s.w), 1.01 * s.w.def().maxLinearSpeed) << "step " << i;
  }
}

TEST(Adversarial, HugeAngularVelocitiesStayFinite) {
  Scene s;
  for (BodyId id : s.dynamic) s.w.setAngularVelocity(id, Vec3(1e30, 2e30, -1e30));
  for (int i = 0; i < 60; ++i) {
    s.w.step(1.0 / 60.0);
    std::string bad;
    ASSERT_TRUE(allFinite(s.w, &bad)) << bad << " at step " << i;
  }
}

// Found here: a finite force or torque so large that F/m, or the accumulated sum, overflowed
// to inf made the body NaN (the speed clamp computed inf * 0). Loads are now scaled down
// before they can overflow, and the clamp keeps the direction of an infinite velocity.
TEST(Adversarial, OverflowingForceOnALightBodyStaysFinite) {
  // kMax newtons on a 10 g body overflow F/m to inf unless the engine guards against it.
  Scene s;
  const BodyId light = s.dynamic.back();
  s.w.addForce(light, Vec3(kMax, 0, 0));
  s.w.step(1.0 / 60.0);
  std::string bad;
  EXPECT_TRUE(allFinite(s.w, &bad)) << bad;
  s.w.addForce(light, Vec3(kMax, 0, 0));
  s.w.addForce(light, Vec3(kMax, 0, 0));  // the accumulated sum overflows
  s.w.step(1.0 / 60.0);
  EXPECT_TRUE(allFinite(s.w, &bad)) << bad;
}

TEST(Adversarial, OverflowingTorqueStaysFinite) {
  Scene s;
  const BodyId capsule = s.dynamic[4];
  s.w.addTorque(capsule, Vec3(1, 0.5, -1e300));
  s.w.step(1.0 / 60.0);
  std::string bad;
  EXPECT_TRUE(allFinite(s.w, &bad)) << bad;
}

TEST(Adversarial, HugeCoordinatesStayFinite) {
  Scene s;
  s.w.setPose(s.dynamic[0], Vec3(1e30, 1e30, -1e30), Quat::Identity());
  s.w.setPose(s.dynamic[1], Vec3(0, -1e30, 0), Quat::Identity());  // deep under the ground
  for (int i = 0; i < 30; ++i) {
    s.w.step(1.0 / 60.0);
    std::string bad;
    ASSERT_TRUE(allFinite(s.w, &bad)) << bad << " at step " << i;
  }
}
