#include <gtest/gtest.h>

#include "collision/query.hpp"
#include "core/error.hpp"
#include "test_util.hpp"

using namespace grip;
using grip::test::at;
using grip::test::boxCorners;
using grip::test::rot;

namespace {

void expectHit(const Shape& s, const Transform& t, const Vec3& o, const Vec3& d, double dist,
               const Vec3& normal, double tol = 1e-12) {
  RayHit h;
  ASSERT_TRUE(rayCast(s, t, o, d.normalized(), 10.0, h)) << shapeTypeName(s.type());
  EXPECT_NEAR(h.distance, dist, tol) << shapeTypeName(s.type());
  EXPECT_LT((h.normal - normal).norm(), tol)
      << shapeTypeName(s.type()) << " " << h.normal.transpose();
  EXPECT_LT((h.point - (o + dist * d.normalized())).norm(), tol);
}

void expectMiss(const Shape& s, const Transform& t, const Vec3& o, const Vec3& d,
                double maxD = 10.0) {
  RayHit h;
  EXPECT_FALSE(rayCast(s, t, o, d.normalized(), maxD, h)) << shapeTypeName(s.type());
}

// Eight unit cubes in a row along x, 2 m apart (gaps of 1 m), the compound at y = 1.
ShapePtr rowOfCubes() {
  auto cube = Shape::box(Vec3(0.5, 0.5, 0.5));
  std::vector<CompoundChild> kids;
  for (int i = 0; i < 8; ++i) kids.push_back({cube, at(Vec3(2.0 * i, 0, 0))});
  return Shape::compound(kids);
}

}  // namespace

TEST(RayCast, SphereHitMissAndInside) {
  auto s = Shape::sphere(0.5);
  const Transform t = at(Vec3(1, 2, 3));
  expectHit(*s, t, Vec3(-2, 2, 3), Vec3::UnitX(), 2.5, -Vec3::UnitX());
  // Off-centre: hits where x^2 + 0.3^2 = 0.25.
  expectHit(*s, t, Vec3(-2, 2.3, 3), Vec3::UnitX(), 3.0 - 0.4, Vec3(-0.4, 0.3, 0) / 0.5);
  expectMiss(*s, t, Vec3(-2, 2.6, 3), Vec3::UnitX());
  expectMiss(*s, t, Vec3(-2, 2, 3), -Vec3::UnitX());                      // pointing away
  expectMiss(*s, t, Vec3(-2, 2, 3), Vec3::UnitX(), 2.4);                  // too short
  expectHit(*s, t, Vec3(1.1, 2, 3), Vec3::UnitY(), 0.0, -Vec3::UnitY());  // inside
}

TEST(RayCast, BoxRotatedAndInside) {
  auto b = Shape::box(Vec3(0.5, 1.0, 1.5));
  const Transform t = at(Vec3(0, 1, 0), rot(kPi / 2, Vec3::UnitY()));  // local x -> world -z
  expectHit(*b, t, Vec3(-5, 1.2, 0.1), Vec3::UnitX(), 5 - 1.5, -Vec3::UnitX());
  expectHit(*b, t, Vec3(0.2, 5, 0.1), -Vec3::UnitY(), 3.0, Vec3::UnitY());
  expectHit(*b, t, Vec3(0.2, 1.1, 3), -Vec3::UnitZ(), 2.5, Vec3::UnitZ());
  expectMiss(*b, t, Vec3(-5, 2.1, 0), Vec3::UnitX());
  expectHit(*b, t, Vec3(0, 1, 0), Vec3(1, 1, 0), 0.0, -Vec3(1, 1, 0).normalized());
}

TEST(RayCast, CapsuleSideAndCaps) {
  auto c = Shape::capsule(0.25, 1.0);
  const Transform t = at(Vec3::Zero());
  expectHit(*c, t, Vec3(-3, 0.5, 0), Vec3::UnitX(), 2.75, -Vec3::UnitX());
  expectHit(*c, t, Vec3(0, 4, 0), -Vec3::UnitY(), 2.75, Vec3::UnitY());
  // Into the lower cap at 45 degrees through its centre.
  const Vec3 d = Vec3(1, 1, 0).normalized();
  expectHit(*c, t, Vec3(0, -1, 0) - 2.0 * d, d, 1.75, -d);
  expectMiss(*c, t, Vec3(-3, 1.3, 0), Vec3::UnitX());
  expectHit(*c, t, Vec3(0.1, 0.9, 0), Vec3::UnitZ(), 0.0, -Vec3::UnitZ());
}

TEST(RayCast, HullAndPlane) {
  auto hull = Shape::convexHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
  const Transform t = at(Vec3(1, 0, 0));
  // The slanted face x + y + z = 1 (local), normal (1,1,1)/sqrt3.
  const Vec3 n = Vec3(1, 1, 1).normalized();
  expectHit(*hull, t, Vec3(1, 0, 0) + Vec3(0.2, 0.2, 0.2) + 2.0 * n, -n,
            2.0 + (0.6 - 1.0) / std::sqrt(3.0), n);
  expectHit(*hull, t, Vec3(1.2, -3, 0.2), Vec3::UnitY(), 3.0, -Vec3::UnitY());
  expectMiss(*hull, t, Vec3(1.8, -3, 0.8), Vec3::UnitY());
  expectHit(*hull, t, Vec3(1.1, 0.1, 0.1), Vec3::UnitX(), 0.0, -Vec3::UnitX());
  auto ground = Shape::plane(Vec3::UnitY(), 0.5);
  expectHit(*ground, at(Vec3::Zero()), Vec3(3, 2.5, 1), Vec3(0, -1, 1), 2.0 * std::sqrt(2.0),
            Vec3::UnitY());
  expectMiss(*ground, at(Vec3::Zero()), Vec3(3, 2.5, 1), Vec3(1, 0, 0));
  expectHit(*ground, at(Vec3::Zero()), Vec3(3, 0, 1), Vec3(1, 0, 0), 0.0, -Vec3::UnitX());
}

TEST(RayCast, RoundedShapesByConservativeAdvancement) {
  auto rb = Shape::box(Vec3(0.5, 0.5, 0.5), 0.1);
  expectHit(*rb, at(Vec3::Zero()), Vec3(-3, 0.2, 0.1), Vec3::UnitX(), 2.4, -Vec3::UnitX(), 1e-8);
  // Toward the rounded corner along the diagonal: the corner sphere of radius 0.1.
  const Vec3 d = Vec3(1, 1, 1).normalized();
  const double cornerDist = Vec3(0.5, 0.5, 0.5).norm() + 0.1;
  expectHit(*rb, at(Vec3::Zero()), 3.0 * d, -d, 3.0 - cornerDist, d, 1e-8);
  expectMiss(*rb, at(Vec3::Zero()), Vec3(-3, 0.65, 0.65), Vec3::UnitX());
  auto rh = Shape::convexHull(boxCorners(Vec3(0.5, 0.5, 0.5)), 0.1);
  expectHit(*rh, at(Vec3(0, 1, 0)), Vec3(0.2, 4, 0.1), -Vec3::UnitY(), 2.4, Vec3::UnitY(), 1e-8);
}

TEST(RayCast, CompoundReturnsNearestChild) {
  auto c = rowOfCubes();
  const Transform t = at(Vec3(0, 1, 0));
  RayHit h;
  ASSERT_TRUE(rayCast(*c, t, Vec3(20, 1.2, 0), -Vec3::UnitX(), 100, h));
  EXPECT_EQ(h.child, 7u);
  EXPECT_NEAR(h.distance, 20 - 14.5, 1e-12);
  ASSERT_TRUE(rayCast(*c, t, Vec3(6.2, 5, 0), -Vec3::UnitY(), 100, h));
  EXPECT_EQ(h.child, 3u);
  EXPECT_NEAR(h.distance, 3.5, 1e-12);
  EXPECT_FALSE(rayCast(*c, t, Vec3(5, 5, 0), -Vec3::UnitY(), 100, h));  // gap between cubes
  // Only child 2, even though child 7 is first along the ray.
  ASSERT_TRUE(rayCastChild(*c, t, 2, Vec3(20, 1.2, 0), -Vec3::UnitX(), 100, h));
  EXPECT_EQ(h.child, 2u);
  EXPECT_NEAR(h.distance, 20 - 4.5, 1e-12);
  EXPECT_THROW(rayCastChild(*c, t, 8, Vec3::Zero(), Vec3::UnitX(), 1, h), Error);
  EXPECT_THROW(rayCast(*c, t, Vec3::Zero(), Vec3(2, 0, 0), 1, h), Error);
}

TEST(ClosestPoint, Primitives) {
  SurfacePoint sp = closestPoint(*Shape::sphere(0.5), at(Vec3(1, 0, 0)), Vec3(1, 2, 0));
  EXPECT_NEAR(sp.distance, 1.5, 1e-12);
  EXPECT_TRUE(sp.point.isApprox(Vec3(1, 0.5, 0), 1e-12));
  EXPECT_TRUE(sp.normal.isApprox(Vec3::UnitY(), 1e-12));
  auto box = Shape::box(Vec3(0.5, 1, 1.5));
  sp = closestPoint(*box, at(Vec3::Zero()), Vec3(1.5, 2, 0.2));  // edge region
  EXPECT_NEAR(sp.distance, std::sqrt(2.0), 1e-12);
  EXPECT_TRUE(sp.point.isApprox(Vec3(0.5, 1, 0.2), 1e-12));
  sp = closestPoint(*box, at(Vec3::Zero()), Vec3(0.1, 0.2, 1.3));  // inside: nearest is +z
  EXPECT_NEAR(sp.distance, -0.2, 1e-12);
  EXPECT_TRUE(sp.point.isApprox(Vec3(0.1, 0.2, 1.5), 1e-12));
  EXPECT_TRUE(sp.normal.isApprox(Vec3::UnitZ(), 1e-12));
  sp = closestPoint(*Shape::capsule(0.25, 1), at(Vec3::Zero(), rot(kPi / 2, Vec3::UnitZ())),
                    Vec3(0.5, 1, 0));
  EXPECT_NEAR(sp.distance, 0.75, 1e-12);
  EXPECT_TRUE(sp.normal.isApprox(Vec3::UnitY(), 1e-12));
  sp = closestPoint(*Shape::plane(Vec3::UnitY(), 1.0), at(Vec3::Zero()), Vec3(3, -1, 2));
  EXPECT_NEAR(sp.distance, -2.0, 1e-12);
  EXPECT_TRUE(sp.point.isApprox(Vec3(3, 1, 2), 1e-12));
  sp = closestPoint(*Shape::box(Vec3(0.5, 0.5, 0.5), 0.1), at(Vec3::Zero()), Vec3(2, 0, 0));
  EXPECT_NEAR(sp.distance, 1.4, 1e-12);
}

TEST(ClosestPoint, HullOutsideAndInside) {
  auto hull = Shape::convexHull(boxCorners(Vec3(0.5, 1, 1.5)));
  auto box = Shape::box(Vec3(0.5, 1, 1.5));
  const Transform t = at(Vec3(1, 2, 3), rot(0.7, Vec3(1, 2, 3)));
  for (const Vec3& x :
       {Vec3(1.5, 2, 0.2), Vec3(3, 4, 5), Vec3(1.1, 2.2, 3.1), Vec3(0.9, 2.6, 4.2)}) {
    const SurfacePoint a = closestPoint(*hull, t, x), b = closestPoint(*box, t, x);
    EXPECT_NEAR(a.distance, b.distance, 1e-9) << x.transpose();
    EXPECT_LT((a.point - b.point).norm(), 1e-9) << x.transpose();
    EXPECT_LT((a.normal - b.normal).norm(), 1e-9) << x.transpose();
  }
}

TEST(ClosestPoint, CompoundNearestChildAndCenters) {
  auto cube = Shape::box(Vec3(0.5, 0.5, 0.5));
  auto c = Shape::compound({{cube, at(Vec3(-2, 0, 0))}, {cube, at(Vec3(2, 0, 0))}});
  SurfacePoint sp = closestPoint(*c, at(Vec3(0, 1, 0)), Vec3(1, 1, 0));
  EXPECT_EQ(sp.child, 1u);
  EXPECT_NEAR(sp.distance, 0.5, 1e-12);
  EXPECT_TRUE(sp.normal.isApprox(-Vec3::UnitX(), 1e-12));
  EXPECT_TRUE(childCenter(*c, at(Vec3(0, 1, 0)), 0).isApprox(Vec3(-2, 1, 0), 1e-12));
  EXPECT_TRUE(childCenter(*cube, at(Vec3(0, 1, 0)), 0).isApprox(Vec3(0, 1, 0), 1e-12));
  auto tet = Shape::convexHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)});
  EXPECT_TRUE(childCenter(*tet, at(Vec3::Zero()), 0).isApprox(Vec3(0.25, 0.25, 0.25), 1e-12));
  EXPECT_THROW(childCenter(*c, at(Vec3::Zero()), 2), Error);
}

TEST(ClosestPoint, CompoundSkipsFacesSharedBetweenChildren) {
  // Two boxes sharing the face x = 0: from inside the left box near that face, the nearest
  // point of the union's surface is on the top (y = 0.5), not on the buried shared face.
  auto cube = Shape::box(Vec3(0.5, 0.5, 0.5));
  auto c = Shape::compound({{cube, at(Vec3(-0.5, 0, 0))}, {cube, at(Vec3(0.5, 0, 0))}});
  const Transform t = at(Vec3(1, 2, 3), rot(0.5, Vec3(1, 0, 1)));
  const SurfacePoint sp = closestPoint(*c, t, t.apply(Vec3(-0.05, 0.3, 0)));
  EXPECT_NEAR(sp.distance, -0.2, 1e-12);
  EXPECT_EQ(sp.child, 0u);
  EXPECT_TRUE(sp.normal.isApprox(t.rotate(Vec3::UnitY()), 1e-12));
  EXPECT_TRUE(sp.point.isApprox(t.apply(Vec3(-0.05, 0.5, 0)), 1e-12));
  // Deep in the right box, its own nearest face (+x) is exposed and wins.
  const SurfacePoint r = closestPoint(*c, t, t.apply(Vec3(0.9, 0.1, 0)));
  EXPECT_NEAR(r.distance, -0.1, 1e-12);
  EXPECT_EQ(r.child, 1u);
}

TEST(ShapeCast, ASphereSweptIsARayCastAgainstTheTargetGrownByItsRadius) {
  const double r = 0.1;
  auto ball = Shape::sphere(r);
  const std::vector<ShapePtr> targets = {
      Shape::sphere(0.5), Shape::box(Vec3(0.5, 0.3, 0.4)), Shape::capsule(0.2, 0.5),
      Shape::convexHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}),
      Shape::box(Vec3(0.4, 0.4, 0.4), 0.05)};
  const Transform t = at(Vec3(0.1, 0.2, -0.1), rot(0.7, Vec3(1, 2, 3).normalized()));
  const std::vector<std::pair<Vec3, Vec3>> rays = {{Vec3(-3, 0.1, 0.05), Vec3(1, 0, 0)},
                                                   {Vec3(0.2, 4, 0.1), Vec3(0, -1, 0)},
                                                   {Vec3(2, 2, 2), Vec3(-1, -1, -1)},
                                                   {Vec3(0.3, -2, 3), Vec3(0, 1, -1.2)}};
  for (const ShapePtr& target : targets) {
    const ShapePtr grown = target->inflated(r);
    for (const auto& [o, d] : rays) {
      const Vec3 dir = d.normalized();
      RayHit cast, ray;
      const bool hits = rayCast(*grown, t, o, dir, 10.0, ray);
      ASSERT_EQ(shapeCast(*target, t, *ball, at(o), dir, 10.0, cast), hits)
          << shapeTypeName(target->type());
      if (!hits) continue;
      // (The grown box and hull are rounded: their ray cast converges to about 1e-7 m.)
      const char* name = shapeTypeName(target->type());
      EXPECT_NEAR(cast.distance, ray.distance, 1e-6) << name;
      EXPECT_LT((cast.normal - ray.normal).norm(), 1e-3) << name;
      // The first touch: the ball's centre a radius from the target there and not before; the
      // point on the target's surface, the normal from it to the centre.
      const Vec3 centre = o + cast.distance * dir;
      EXPECT_NEAR(closestPoint(*target, t, centre).distance, r, 1e-9) << name;
      EXPECT_GT(closestPoint(*target, t, centre - 1e-6 * dir).distance, r) << name;
      EXPECT_NEAR(closestPoint(*target, t, cast.point).distance, 0.0, 1e-9) << name;
      EXPECT_LT((cast.normal - (centre - cast.point) / r).norm(), 1e-6) << name;
    }
  }
}

TEST(ShapeCast, ABoxOnItsEdgeMeetsThePlaneWithItsLowestEdge) {
  auto cube = Shape::box(Vec3(0.5, 0.5, 0.5));
  auto ground = Shape::plane(Vec3::UnitY(), 0.0);
  const Transform onEdge = at(Vec3(0, 2, 0), rot(kPi / 4, Vec3::UnitZ()));
  RayHit h;
  ASSERT_TRUE(shapeCast(*ground, at(Vec3::Zero()), *cube, onEdge, -Vec3::UnitY(), 10.0, h));
  EXPECT_NEAR(h.distance, 2.0 - 0.5 * std::sqrt(2.0), 1e-12);
  EXPECT_LT((h.normal - Vec3::UnitY()).norm(), 1e-12);
  EXPECT_NEAR(h.point.x(), 0.0, 1e-12);
  EXPECT_NEAR(h.point.y(), 0.0, 1e-12);
  EXPECT_FALSE(shapeCast(*ground, at(Vec3::Zero()), *cube, onEdge, Vec3::UnitX(), 10.0, h));
  EXPECT_FALSE(shapeCast(*ground, at(Vec3::Zero()), *cube, onEdge, Vec3::UnitY(), 10.0, h));
  EXPECT_FALSE(shapeCast(*ground, at(Vec3::Zero()), *cube, onEdge, -Vec3::UnitY(), 1.2, h));
  // Face down onto a bigger box: the faces meet after 3 - 0.5 - 1.
  auto big = Shape::box(Vec3(1, 1, 1));
  ASSERT_TRUE(
      shapeCast(*big, at(Vec3::Zero()), *cube, at(Vec3(0.3, 3, -0.2)), -Vec3::UnitY(), 10.0, h));
  EXPECT_NEAR(h.distance, 1.5, 1e-9);
  EXPECT_LT((h.normal - Vec3::UnitY()).norm(), 1e-6);
  EXPECT_NEAR(h.point.y(), 1.0, 1e-9);
}

TEST(ShapeCast, StartingInContactHitsAtZeroWithTheNormalOpposingTheCast) {
  auto cube = Shape::box(Vec3(0.5, 0.5, 0.5));
  auto ball = Shape::sphere(0.3);
  RayHit h;
  ASSERT_TRUE(shapeCast(*cube, at(Vec3::Zero()), *ball, at(Vec3(0.6, 0, 0)), Vec3::UnitX(), 5, h));
  EXPECT_EQ(h.distance, 0.0);
  EXPECT_EQ(h.normal, -Vec3::UnitX());
  auto ground = Shape::plane(Vec3::UnitY(), 0.0);
  ASSERT_TRUE(
      shapeCast(*ground, at(Vec3::Zero()), *cube, at(Vec3(0, 0.4, 0)), Vec3::UnitY(), 5, h));
  EXPECT_EQ(h.distance, 0.0);
  EXPECT_EQ(h.normal, -Vec3::UnitY());
}

TEST(ShapeCast, ACompoundReportsTheChildMetFirst) {
  auto c = rowOfCubes();
  const Transform t = at(Vec3(0, 1, 0));
  auto ball = Shape::sphere(0.2);
  RayHit h;
  ASSERT_TRUE(shapeCast(*c, t, *ball, at(Vec3(20, 1.2, 0)), -Vec3::UnitX(), 100, h));
  EXPECT_EQ(h.child, 7u);
  EXPECT_NEAR(h.distance, 20 - 14.5 - 0.2, 1e-9);
  ASSERT_TRUE(shapeCast(*c, t, *ball, at(Vec3(6.2, 5, 0)), -Vec3::UnitY(), 100, h));
  EXPECT_EQ(h.child, 3u);
  EXPECT_NEAR(h.distance, 3.5 - 0.2, 1e-9);
  // Between two cubes a ray falls through (RayCast.CompoundReturnsNearestChild); a ball as
  // wide as the gap does not.
  EXPECT_FALSE(shapeCast(*c, t, *Shape::sphere(0.4), at(Vec3(5, 5, 0)), -Vec3::UnitY(), 100, h));
  ASSERT_TRUE(shapeCast(*c, t, *Shape::sphere(0.6), at(Vec3(5, 5, 0)), -Vec3::UnitY(), 100, h));
  EXPECT_EQ(h.child, 2u);  // a tie between children 2 and 3: the lower index
}

TEST(ShapeCast, BadInputNamesTheField) {
  auto cube = Shape::box(Vec3(0.5, 0.5, 0.5));
  const Transform t = at(Vec3::Zero());
  RayHit h;
  auto fieldOf = [&](const Shape& moving, const Transform& tm, const Vec3& dir, double maxD) {
    try {
      shapeCast(*cube, t, moving, tm, dir, maxD, h);
    } catch (const Error& e) {
      return e.field();
    }
    return std::string();
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fieldOf(*cube, at(Vec3(3, 0, 0)), Vec3(2, 0, 0), 5), "shapeCast.dir");
  EXPECT_EQ(fieldOf(*cube, at(Vec3(nan, 0, 0)), Vec3(1, 0, 0), 5), "shapeCast.pose.position");
  EXPECT_EQ(fieldOf(*cube, at(Vec3(3, 0, 0), Quat(0, 0, 0, 0)), Vec3(1, 0, 0), 5),
            "shapeCast.pose.orientation");
  EXPECT_EQ(fieldOf(*cube, at(Vec3(3, 0, 0)), Vec3(1, 0, 0), -1), "shapeCast.maxDistance");
  EXPECT_EQ(fieldOf(*Shape::plane(Vec3::UnitY(), 0), t, Vec3(1, 0, 0), 5), "shapeCast.shape");
  EXPECT_EQ(fieldOf(*Shape::compound({{cube, t}}), t, Vec3(1, 0, 0), 5), "shapeCast.shape");
  EXPECT_EQ(fieldOf(*cube, at(Vec3(3, 0, 0)), Vec3(1, 0, 0), 5), "");
}
