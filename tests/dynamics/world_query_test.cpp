// The world's queries walk a tree over the bodies that have not moved since it was built and
// test the moved ones one by one (dynamics/detail/world.cpp, "queries"). Whatever happened
// since the build, they must find what testing every body finds, in body order (overlaps, rays,
// the bodies in a box): checked here
// against exactly that, through a pile landing and falling asleep, a sleeping box set
// elsewhere, a body destroyed and its slot reused, few queries a step and many.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "collision/narrowphase.hpp"
#include "dynamics/scenes.hpp"
#include "dynamics/world.hpp"

using namespace grip;

namespace {

std::vector<OverlapHit> everyBodyOverlap(const World& w, const Shape& shape, const Transform& t,
                                         double margin) {
  std::vector<OverlapHit> hits;
  const Aabb box = shape.bounds(t).inflated(margin);
  for (BodyId id : w.bodies()) {
    if (w.isSensor(id) || !w.bounds(id).overlaps(box)) continue;
    std::vector<Manifold> found;
    collide(shape, t, w.shape(id), w.pose(id), margin, found);
    for (const Manifold& m : found) hits.push_back(OverlapHit{id, m});
  }
  return hits;
}

std::optional<WorldRayHit> everyBodyRay(const World& w, const Vec3& o, const Vec3& d,
                                        double maxDistance) {
  std::optional<WorldRayHit> best;
  for (BodyId id : w.bodies()) {
    if (w.isSensor(id)) continue;
    const std::optional<RayHit> h = w.rayCastBody(id, o, d, maxDistance);
    if (h && (!best || h->distance < best->hit.distance)) best = WorldRayHit{id, *h};
  }
  return best;
}

// `count` random overlaps and rays over the pile's ground, each compared with every body's.
void expectEveryBodysAnswers(const World& w, std::mt19937& rng, int count) {
  std::uniform_real_distribution<double> across(-1.5, 1.5), up(0.0, 1.5), size(0.02, 0.3);
  for (int q = 0; q < count; ++q) {
    const ShapePtr ball = Shape::sphere(size(rng));
    const Transform t{Vec3(across(rng), up(rng), across(rng)), Quat::Identity()};
    std::vector<OverlapHit> hits;
    w.overlap(*ball, t, 0.01, hits);
    const std::vector<OverlapHit> expected = everyBodyOverlap(w, *ball, t, 0.01);
    ASSERT_EQ(hits.size(), expected.size()) << "overlap " << q << " at step " << w.stepCount();
    for (size_t i = 0; i < hits.size(); ++i) {
      EXPECT_EQ(hits[i].body, expected[i].body);
      EXPECT_EQ(hits[i].manifold.pointCount, expected[i].manifold.pointCount);
      EXPECT_EQ(hits[i].manifold.points[0].separation, expected[i].manifold.points[0].separation);
    }
    const Aabb box = ball->bounds(t);
    std::vector<BodyId> near, expectedNear;
    w.queryBounds(box, near);
    for (BodyId id : w.bodies())
      if (!w.isSensor(id) && w.bounds(id).overlaps(box)) expectedNear.push_back(id);
    EXPECT_EQ(near, expectedNear) << "bounds " << q;
    const Vec3 o(across(rng), 3.0, across(rng));
    const Vec3 d = Vec3(0.3 * across(rng), -1.0, 0.3 * across(rng)).normalized();
    const std::optional<WorldRayHit> ray = w.rayCast(o, d, 4.0);
    const std::optional<WorldRayHit> expectedRay = everyBodyRay(w, o, d, 4.0);
    ASSERT_EQ(ray.has_value(), expectedRay.has_value()) << "ray " << q;
    if (ray) {
      EXPECT_EQ(ray->body, expectedRay->body);
      EXPECT_EQ(ray->hit.distance, expectedRay->hit.distance);
    }
  }
}

}  // namespace

TEST(WorldQueries, FindWhatTestingEveryBodyFinds) {
  World w;
  scenes::addGround(w);
  std::vector<BodyId> boxes = scenes::addBoxPile(w, 300);
  std::mt19937 rng(3);
  int steps = 0;
  // Landing: most steps ask once (the moved boxes tested one by one), every tenth asks 40
  // times (the tree built again within the step).
  for (; steps < 180; ++steps) {
    w.step(1.0 / 60.0);
    expectEveryBodysAnswers(w, rng, steps % 10 == 0 ? 40 : 1);
  }
  for (; steps < 1200 && w.isAwake(boxes[0]); ++steps) w.step(1.0 / 60.0);
  for (BodyId b : boxes) ASSERT_FALSE(w.isAwake(b));  // asleep: the tree holds them all
  expectEveryBodysAnswers(w, rng, 100);

  w.setPose(boxes[7], Vec3(0.0, 1.2, 0.0), Quat::Identity());  // above the pile
  w.destroyBody(boxes[8]);
  BodyDef d;
  d.shape = Shape::sphere(0.2);
  d.position = Vec3(1.0, 1.0, -1.0);
  const BodyId ball = w.createBody(d);
  EXPECT_EQ(ball.index, boxes[8].index);  // the slot reused
  expectEveryBodysAnswers(w, rng, 100);
  const std::optional<WorldRayHit> hit = w.rayCast(Vec3(0.0, 3.0, 0.0), Vec3(0, -1, 0), 5.0);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->body, boxes[7]);
  EXPECT_NEAR(hit->hit.distance, 3.0 - 1.3, 1e-9);
  w.step(1.0 / 60.0);
  expectEveryBodysAnswers(w, rng, 100);
}

// queryBounds refuses a box that is not one, naming the field.
TEST(WorldQueries, ABadBoxNamesItsField) {
  World w;
  scenes::addGround(w);
  std::vector<BodyId> near;
  const std::pair<const char*, Aabb> cases[] = {
      {"queryBounds.box.min", Aabb{Vec3(std::nan(""), 0, 0), Vec3::Ones()}},
      {"queryBounds.box.max", Aabb{Vec3::Zero(), Vec3(1, INFINITY, 1)}},
      {"queryBounds.box", Aabb{Vec3::Ones(), Vec3::Zero()}},
  };
  for (const auto& [field, box] : cases) {
    try {
      w.queryBounds(box, near);
      ADD_FAILURE() << "accepted a bad " << field;
    } catch (const Error& e) {
      EXPECT_EQ(e.field(), field);
    }
  }
  w.queryBounds(Aabb{Vec3(-1, -1, -1), Vec3(1, 1, 1)}, near);
  EXPECT_EQ(near.size(), 1u);  // the ground
}
