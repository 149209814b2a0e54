// Collision and query filters: which pairs collide (Box2D's rule), that a changed filter takes
// effect on sleeping bodies too, and that queries skip the kinds their mask leaves out.
#include <gtest/gtest.h>

#include <set>
#include <utility>
#include <vector>

#include "dynamics/world.hpp"

using namespace grip;

namespace {

constexpr double kDt = 1.0 / 60.0;
constexpr double kHalf = 0.1;  // the boxes' half size

BodyId addGround(World& w, const CollisionFilter& filter = {}) {
  BodyDef g;
  g.type = BodyType::Static;
  g.shape = Shape::plane(Vec3::UnitY(), 0.0);
  g.filter = filter;
  return w.createBody(g);
}

BodyId addBox(World& w, const Vec3& pos, const CollisionFilter& filter = {}) {
  BodyDef d;
  d.shape = Shape::box(Vec3::Constant(kHalf));
  d.position = pos;
  d.mass = 1.0;
  d.filter = filter;
  return w.createBody(d);
}

void run(World& w, double seconds) {
  for (int i = 0; i < static_cast<int>(seconds * 60.0 + 0.5); ++i) w.step(kDt);
}

constexpr uint64_t kAll = ~uint64_t{0};

}  // namespace

TEST(CollisionFilter, TheRuleIsBox2Ds) {
  const CollisionFilter plain;
  EXPECT_TRUE(shouldCollide(plain, plain));
  const CollisionFilter kind2{2, kAll, 0}, blind2{1, kAll & ~uint64_t{2}, 0};
  EXPECT_TRUE(shouldCollide(plain, kind2));
  EXPECT_FALSE(shouldCollide(blind2, kind2));  // one mask leaving the other out is enough
  EXPECT_FALSE(shouldCollide(kind2, blind2));
  // A shared group decides before the bits, either way; different groups fall back to them.
  EXPECT_TRUE(shouldCollide({2, 0, 5}, {2, 0, 5}));
  EXPECT_FALSE(shouldCollide({1, kAll, -5}, {1, kAll, -5}));
  EXPECT_TRUE(shouldCollide({1, kAll, -5}, {1, kAll, -6}));
  EXPECT_FALSE(shouldCollide({2, 0, 5}, {2, 0, 6}));
}

TEST(CollisionFilter, ABoxMaskedOffTheGroundFallsAsThoughTheGroundWereNotThere) {
  World filtered, empty;
  addGround(filtered, {2, kAll, 0});
  const BodyId a = addBox(filtered, Vec3(0, 0.5, 0), {1, kAll & ~uint64_t{2}, 0});
  const BodyId b = addBox(empty, Vec3(0, 0.5, 0));
  for (int i = 0; i < 60; ++i) {
    filtered.step(kDt), empty.step(kDt);
    ASSERT_EQ(filtered.contactConstraintCount(), 0) << "step " << i;
    ASSERT_TRUE(filtered.contactBeginEvents().empty());
  }
  // Bit for bit the same fall.
  EXPECT_EQ(filtered.pose(a).p, empty.pose(b).p);
  EXPECT_EQ(filtered.linearVelocity(a), empty.linearVelocity(b));
  EXPECT_LT(filtered.pose(a).p.y(), -4.0);
}

TEST(CollisionFilter, TheGroundsMaskCountsAsMuchAsTheBoxs) {
  World w;
  addGround(w, {1, kAll & ~uint64_t{4}, 0});  // collides with everything but kind 4
  const BodyId ghost = addBox(w, Vec3(0, 0.5, 0), {4, kAll, 0});
  const BodyId plain = addBox(w, Vec3(1, 0.5, 0));
  run(w, 1.0);
  EXPECT_LT(w.pose(ghost).p.y(), -2.0);
  EXPECT_NEAR(w.pose(plain).p.y(), kHalf, 1e-3);
}

TEST(CollisionFilter, ANegativeGroupPassesThroughItselfAPositiveOneAlwaysCollides) {
  for (const int group : {-3, 3}) {
    World w;
    addGround(w);
    // Masks that leave each other out: only the group can make them collide.
    const CollisionFilter f{2, kAll & ~uint64_t{2}, group};
    const BodyId low = addBox(w, Vec3(0, 0.5, 0), f);
    const BodyId high = addBox(w, Vec3(0.02, 1.0, 0), f);
    run(w, 2.0);
    EXPECT_NEAR(w.pose(low).p.y(), kHalf, 1e-3) << group;
    if (group < 0) {
      EXPECT_NEAR(w.pose(high).p.y(), kHalf, 1e-3) << "passed through, on the ground";
    } else {
      EXPECT_NEAR(w.pose(high).p.y(), 3 * kHalf, 2e-3) << "stacked";
    }
  }
}

TEST(CollisionFilter, ANewFilterWakesASleepingStackAndDropsItsPair) {
  World w;
  addGround(w);
  const BodyId low = addBox(w, Vec3(0, kHalf, 0), {2, kAll, 0});
  const BodyId high = addBox(w, Vec3(0, 3 * kHalf, 0));
  run(w, 3.0);
  ASSERT_FALSE(w.isAwake(low));
  ASSERT_FALSE(w.isAwake(high));
  const uint64_t asleep = w.stateHash();
  w.step(kDt);
  ASSERT_EQ(w.stateHash(), asleep);  // at rest, nothing changes

  const CollisionFilter through{1, kAll & ~uint64_t{2}, 0};
  w.setCollisionFilter(high, through);
  EXPECT_EQ(w.collisionFilter(high).mask, through.mask);
  EXPECT_TRUE(w.isAwake(high));
  EXPECT_TRUE(w.isAwake(low));  // it touches the body whose filter changed
  w.step(kDt);
  std::set<std::pair<uint32_t, uint32_t>> ended;
  for (const ContactEvent& e : w.contactEndEvents())
    ended.insert({std::min(e.a.index, e.b.index), std::max(e.a.index, e.b.index)});
  EXPECT_EQ(ended.count({low.index, high.index}), 1u);
  EXPECT_TRUE(w.contactManifolds(low, high).empty());
  run(w, 1.0);
  EXPECT_NEAR(w.pose(high).p.y(), kHalf, 1e-3);  // fell through onto the ground
  EXPECT_NEAR(w.pose(low).p.y(), kHalf, 1e-3);
}

TEST(CollisionFilter, ANewFilterOnTheGroundWakesWhatRestsOnIt) {
  World w;
  const BodyId ground = addGround(w);
  const BodyId box = addBox(w, Vec3(0, kHalf, 0));
  run(w, 3.0);
  ASSERT_FALSE(w.isAwake(box));
  w.setCollisionFilter(ground, {1, 0, 0});  // collides with nothing
  EXPECT_TRUE(w.isAwake(box));
  run(w, 1.0);
  EXPECT_LT(w.pose(box).p.y(), -2.0);
}

TEST(CollisionFilter, ANewFilterThatLetsTwoOverlappingBodiesCollideWakesThemToPartThem) {
  World w;
  addGround(w);
  BodyDef d;  // a static slab through the middle of a box it does not collide with yet
  d.type = BodyType::Static;
  d.shape = Shape::box(Vec3(0.5, 0.05, 0.5));
  d.position = Vec3(0, kHalf, 0);
  d.filter = {2, kAll & ~uint64_t{1}, 0};
  const BodyId slab = w.createBody(d);
  const BodyId box = addBox(w, Vec3(0, kHalf, 0));
  run(w, 3.0);
  ASSERT_FALSE(w.isAwake(box));  // on the ground, without a contact with the slab
  w.setCollisionFilter(slab, CollisionFilter{});
  EXPECT_TRUE(w.isAwake(box));
  run(w, 2.0);
  EXPECT_FALSE(w.contactManifolds(slab, box).empty());
  EXPECT_NEAR(w.pose(box).p.y(), 0.15 + kHalf, 2e-3);  // pushed out on top of the slab
}

TEST(CollisionFilter, SensorsReportOnlyWhatTheirFilterLetsThrough) {
  World w;
  BodyDef s;  // a static sensor box that does not see kind 2
  s.isSensor = true;
  s.filter = {1, kAll & ~uint64_t{2}, 0};
  s.type = BodyType::Static;
  s.shape = Shape::box(Vec3(2, 0.5, 1));
  s.position = Vec3(0, 0.5, 0);
  const BodyId sensor = w.createBody(s);
  const BodyId seen = addBox(w, Vec3(-1, 2, 0));
  addBox(w, Vec3(1, 2, 0), {2, kAll, 0});  // unseen
  std::vector<SensorEvent> begins;
  for (int i = 0; i < 60; ++i) {
    w.step(kDt);
    for (const SensorEvent& e : w.sensorBeginEvents()) begins.push_back(e);
  }
  ASSERT_EQ(begins.size(), 1u);
  EXPECT_EQ(begins[0].sensor, sensor);
  EXPECT_EQ(begins[0].visitor, seen);
}

TEST(QueryFilter, RayCastsAndOverlapsSkipTheKindsTheMaskLeavesOut) {
  WorldDef def;
  def.gravity = Vec3::Zero();
  World w(def);
  const BodyId near = addBox(w, Vec3(1, 0, 0), {2, kAll, 0});
  const BodyId far = addBox(w, Vec3(2, 0, 0));
  const Vec3 origin(-1, 0, 0), dir(1, 0, 0);
  auto hit = w.rayCast(origin, dir, 10.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->body, near);
  EXPECT_NEAR(hit->hit.distance, 2.0 - kHalf, 1e-9);
  hit = w.rayCast(origin, dir, 10.0, QueryFilter{kAll & ~uint64_t{2}});
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->body, far);
  EXPECT_NEAR(hit->hit.distance, 3.0 - kHalf, 1e-9);
  EXPECT_FALSE(w.rayCast(origin, dir, 10.0, QueryFilter{0}));

  // A shape cast along the same line: the ball's radius short of the ray's hits.
  const ShapePtr small = Shape::sphere(0.05);
  auto cast = w.shapeCast(*small, Transform{origin, Quat::Identity()}, dir, 10.0);
  ASSERT_TRUE(cast);
  EXPECT_EQ(cast->body, near);
  EXPECT_NEAR(cast->hit.distance, 2.0 - kHalf - 0.05, 1e-9);
  cast = w.shapeCast(*small, Transform{origin, Quat::Identity()}, dir, 10.0,
                     QueryFilter{kAll & ~uint64_t{2}});
  ASSERT_TRUE(cast);
  EXPECT_EQ(cast->body, far);
  EXPECT_NEAR(cast->hit.distance, 3.0 - kHalf - 0.05, 1e-9);

  const ShapePtr ball = Shape::sphere(1.0);
  const Transform at{Vec3(1.5, 0, 0), Quat::Identity()};
  std::vector<OverlapHit> hits;
  w.overlap(*ball, at, 0.0, hits);
  ASSERT_EQ(hits.size(), 2u);
  w.overlap(*ball, at, 0.0, hits, QueryFilter{2});
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].body, near);
}
