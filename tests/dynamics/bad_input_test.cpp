// Bad input: a clear error naming the field, and the world exactly as it was.
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "dynamics/world.hpp"

using namespace grip;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

struct Fixture {
  World w;
  BodyId box;
  Fixture() {
    BodyDef g;
    g.type = BodyType::Static;
    g.shape = Shape::plane(Vec3::UnitY(), 0);
    w.createBody(g);
    BodyDef d;
    d.shape = Shape::box(Vec3::Constant(0.1));
    d.position = Vec3(0, 0.3, 0);
    box = w.createBody(d);
    for (int i = 0; i < 5; ++i) w.step(1.0 / 60.0);
  }
};

// Runs `call`, expects grip::Error whose field is `field`, and checks the world is unchanged.
void expectRejected(Fixture& f, const std::string& field, const std::function<void()>& call) {
  const uint64_t before = f.w.stateHash();
  const int bodies = f.w.bodyCount();
  const Vec3 force = f.w.accumulatedForce(f.box);
  try {
    call();
    ADD_FAILURE() << "no error for " << field;
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos);
  }
  EXPECT_EQ(f.w.stateHash(), before) << field;
  EXPECT_EQ(f.w.bodyCount(), bodies) << field;
  EXPECT_EQ(f.w.accumulatedForce(f.box), force) << field;
}

}  // namespace

TEST(BadInput, NonFiniteValuesNameTheField) {
  Fixture f;
  expectRejected(f, "addForce.force", [&] { f.w.addForce(f.box, Vec3(kNaN, 0, 0)); });
  expectRejected(f, "setGravityScale.scale", [&] { f.w.setGravityScale(f.box, kInf); });
  expectRejected(f, "setDamping.angular", [&] { f.w.setDamping(f.box, 0.1, kNaN); });
  expectRejected(f, "setDamping.linear", [&] { f.w.setDamping(f.box, -1.0, 0.0); });
  expectRejected(f, "addForceAtPosition.position",
                 [&] { f.w.addForceAtPosition(f.box, Vec3(1, 0, 0), Vec3(0, kInf, 0)); });
  expectRejected(f, "addTorque.torque", [&] { f.w.addTorque(f.box, Vec3(0, 0, kInf)); });
  expectRejected(f, "setPose.position",
                 [&] { f.w.setPose(f.box, Vec3(kNaN, 0, 0), Quat::Identity()); });
  expectRejected(f, "setPose.orientation",
                 [&] { f.w.setPose(f.box, Vec3::Zero(), Quat(0, 0, 0, 0)); });
  expectRejected(f, "setLinearVelocity.velocity",
                 [&] { f.w.setLinearVelocity(f.box, Vec3(0, kInf, 0)); });
  expectRejected(f, "step.dt", [&] { f.w.step(kNaN); });
  expectRejected(f, "step.dt", [&] { f.w.step(-0.1); });
  expectRejected(f, "rayCast.dir", [&] { (void)f.w.rayCast(Vec3::Zero(), Vec3(0, 2, 0), 1.0); });
  BodyDef d;
  d.shape = Shape::sphere(0.1);
  d.position = Vec3(0, kNaN, 0);
  expectRejected(f, "BodyDef.position", [&] { f.w.createBody(d); });
  d.position = Vec3::Zero();
  d.linearVelocity = Vec3(kInf, 0, 0);
  expectRejected(f, "BodyDef.linearVelocity", [&] { f.w.createBody(d); });
}

TEST(BadInput, ZeroOrNegativeMassesAndSizes) {
  Fixture f;
  BodyDef d;
  d.shape = Shape::sphere(0.1);
  d.mass = -1.0;
  expectRejected(f, "BodyDef.mass", [&] { f.w.createBody(d); });
  d.mass = 0.0;
  d.material.density = 0.0;
  expectRejected(f, "BodyDef.material.density", [&] { f.w.createBody(d); });
  d.material = MaterialDef{};
  d.material.dynamicFriction = 0.9;  // above static 0.6
  expectRejected(f, "BodyDef.material.dynamicFriction", [&] { f.w.createBody(d); });
  d.material = MaterialDef{};
  d.shape = nullptr;
  expectRejected(f, "BodyDef.shape", [&] { f.w.createBody(d); });
  d.shape = Shape::plane(Vec3::UnitY(), 0.0);
  expectRejected(f, "BodyDef.shape", [&] { f.w.createBody(d); });  // dynamic plane
  EXPECT_THROW(Shape::sphere(0.0), Error);
  EXPECT_THROW(Shape::sphere(-1.0), Error);
  EXPECT_THROW(Shape::box(Vec3(1, 0, 1)), Error);
  EXPECT_THROW(Shape::capsule(0.1, -0.5), Error);
  EXPECT_THROW(Shape::box(Vec3(1, kNaN, 1)), Error);
  WorldDef wd;
  wd.substeps = 0;
  EXPECT_THROW({ World w(wd); }, Error);
  // A WorldDef that `spoil` makes wrong is refused with an error naming `field`.
  auto expectRefused = [](const char* field, const auto& spoil) {
    WorldDef t;
    spoil(t);
    try {
      World w(t);
      ADD_FAILURE() << field << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("WorldDef.") + field), std::string::npos)
          << e.what();
    }
  };
  expectRefused("contactReuseDistance", [](WorldDef& t) { t.contactReuseDistance = -1e-3; });
  expectRefused("contactReuseAngle", [](WorldDef& t) { t.contactReuseAngle = -1e-3; });
  for (double substep : {0.0, -0.01, kNaN, kInf})
    expectRefused("maxSubstep", [&](WorldDef& t) { t.maxSubstep = substep; });
  for (int threads : {0, -1, 65})
    expectRefused("workerThreads", [&](WorldDef& t) { t.workerThreads = threads; });
}

TEST(BadInput, UnknownAndStaleIds) {
  Fixture f;
  expectRejected(f, "addForce.id", [&] { f.w.addForce(BodyId{}, Vec3(1, 0, 0)); });
  expectRejected(f, "pose.id", [&] { (void)f.w.pose(BodyId{77, 1}); });
  BodyDef d;
  d.shape = Shape::sphere(0.1);
  d.position = Vec3(5, 1, 5);
  const BodyId temp = f.w.createBody(d);
  f.w.destroyBody(temp);
  EXPECT_FALSE(f.w.isValid(temp));
  expectRejected(f, "setLinearVelocity.id", [&] { f.w.setLinearVelocity(temp, Vec3::Zero()); });
  expectRejected(f, "destroyBody.id", [&] { f.w.destroyBody(temp); });
  expectRejected(f, "setCollisionFilter.id", [&] {
    f.w.setCollisionFilter(temp, CollisionFilter{2, 0, 0});
  });
  expectRejected(f, "collisionFilter.id", [&] { (void)f.w.collisionFilter(temp); });
  expectRejected(f, "contactForce.b", [&] { (void)f.w.contactForce(f.box, temp); });
  expectRejected(f, "setUserData.id", [&] { f.w.setUserData(temp, 1); });
  expectRejected(f, "setAllowSleep.id", [&] { f.w.setAllowSleep(temp, false); });
  expectRejected(f, "contactManifolds.b",
                 [&] { (void)f.w.contactManifolds(f.w.bodies()[0], temp); });
  // The slot is reused with a new generation: the old id stays stale.
  const BodyId again = f.w.createBody(d);
  EXPECT_EQ(again.index, temp.index);
  EXPECT_NE(again.generation, temp.generation);
  EXPECT_THROW((void)f.w.pose(temp), Error);
  EXPECT_NO_THROW((void)f.w.pose(again));
}
