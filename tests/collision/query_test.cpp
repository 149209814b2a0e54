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
  auto cube = Shape::box(Vec3(0.5, 0.5, 0.5));
  std::vector<CompoundChild> kids;
  for (int i = 0; i < 8; ++i) kids.push_back({cube, at(Vec3(2.0 * i, 0, 0))});
  auto c = Shape::compound(kids);
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
