#include <gtest/gtest.h>

#include <functional>
#include <map>
#include <set>

#include "collision/shape.hpp"
#include "core/error.hpp"
#include "test_util.hpp"

using namespace grip;
using grip::test::boxCorners;
using grip::test::randomPoints;

namespace {

// Expects `f` to throw grip::Error whose field is `field`.
template <class F>
void expectError(F&& f, const std::string& field) {
  try {
    f();
    ADD_FAILURE() << "no error thrown, expected one naming " << field;
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

void expectEuler(const ConvexHullData& h) {
  EXPECT_EQ(static_cast<int>(h.vertices.size()) - static_cast<int>(h.edges.size()) +
                static_cast<int>(h.faces.size()),
            2);
}

}  // namespace

TEST(ShapeFactory, RejectsBadArgumentsNamingThem) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  expectError([] { Shape::sphere(0.0); }, "Shape::sphere.radius");
  expectError([] { Shape::sphere(-1.0); }, "Shape::sphere.radius");
  expectError([&] { Shape::sphere(nan); }, "Shape::sphere.radius");
  expectError([&] { Shape::box(Vec3(1, inf, 1)); }, "Shape::box.halfExtents");
  expectError([] { Shape::box(Vec3(1, 0, 1)); }, "Shape::box.halfExtents");
  expectError([] { Shape::box(Vec3(1, 1, 1), -0.1); }, "Shape::box.rounding");
  expectError([] { Shape::capsule(0.1, 0.0); }, "Shape::capsule.halfHeight");
  expectError([] { Shape::capsule(-0.1, 1.0); }, "Shape::capsule.radius");
  expectError([] { Shape::plane(Vec3::Zero(), 0.0); }, "Shape::plane.normal");
  expectError([&] { Shape::plane(Vec3::UnitY(), nan); }, "Shape::plane.offset");
  expectError(
      [] {
        Shape::convexHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)});
      },
      "Shape::convexHull.points");
  // Coplanar and collinear point sets have no volume.
  expectError(
      [] {
        Shape::convexHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)});
      },
      "Shape::convexHull.points");
  expectError(
      [] {
        Shape::convexHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)});
      },
      "Shape::convexHull.points");
  expectError(
      [&] {
        Shape::convexHull({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, nan)});
      },
      "Shape::convexHull.points");
  expectError([] { Shape::compound({}); }, "Shape::compound.children");
  expectError(
      [] {
        Shape::compound({{Shape::plane(Vec3::UnitY(), 0.0), Transform{}}});
      },
      "Shape::compound.children[0].shape");
  auto inner = Shape::compound({{Shape::sphere(1.0), Transform{}}});
  expectError(
      [&] {
        Shape::compound({{Shape::sphere(1.0), Transform{}}, {inner, Transform{}}});
      },
      "Shape::compound.children[1].shape");
  expectError(
      [] {
        Shape::compound({{nullptr, Transform{}}});
      },
      "Shape::compound.children[0].shape");
  expectError([] { Shape::sphere(1.0)->inflated(-0.1); }, "Shape::inflated.margin");
  expectError([] { Shape::sphere(1.0)->massProperties(0.0); }, "Shape::massProperties.density");
}

TEST(ConvexHull, CubeGivesSixQuadFacesWithOutwardNormals) {
  auto s = Shape::convexHull(boxCorners(Vec3(1, 2, 3)));
  const ConvexHullData& h = s->hull();
  ASSERT_EQ(h.vertices.size(), 8u);
  ASSERT_EQ(h.faces.size(), 6u);
  EXPECT_EQ(h.edges.size(), 12u);
  expectEuler(h);
  std::set<std::pair<int, int>> normals;
  for (const auto& f : h.faces) {
    EXPECT_EQ(f.vertices.size(), 4u);
    // Axis-aligned unit normal, offset equal to the half extent on that axis.
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(f.normal[k]) > std::abs(f.normal[axis])) axis = k;
    EXPECT_NEAR(std::abs(f.normal[axis]), 1.0, 1e-12);
    EXPECT_NEAR(f.offset, Vec3(1, 2, 3)[axis], 1e-12);
    normals.insert({axis, f.normal[axis] > 0 ? 1 : -1});
    // Counter-clockwise seen from outside: the loop's winding agrees with the normal.
    const Vec3 a = h.vertices[f.vertices[0]], b = h.vertices[f.vertices[1]],
               c = h.vertices[f.vertices[2]];
    EXPECT_GT((b - a).cross(c - b).dot(f.normal), 0.0);
  }
  EXPECT_EQ(normals.size(), 6u);
}

TEST(ConvexHull, RandomPointsAreInsideAndEulerHolds) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const auto pts = randomPoints(200, seed, 0.5);
    auto s = Shape::convexHull(pts);
    const ConvexHullData& h = s->hull();
    expectEuler(h);
    for (const Vec3& p : pts)
      for (const auto& f : h.faces) EXPECT_LE(f.normal.dot(p) - f.offset, 1e-12);
    for (const auto& f : h.faces) {
      EXPECT_NEAR(f.normal.norm(), 1.0, 1e-12);
      for (int v : f.vertices) EXPECT_NEAR(f.normal.dot(h.vertices[v]), f.offset, 1e-9);
    }
    // Each edge is shared by exactly two faces.
    std::map<std::pair<int, int>, int> uses;
    for (const auto& f : h.faces)
      for (size_t i = 0; i < f.vertices.size(); ++i) {
        int a = f.vertices[i], b = f.vertices[(i + 1) % f.vertices.size()];
        uses[{std::min(a, b), std::max(a, b)}]++;
      }
    for (const auto& [e, n] : uses) EXPECT_EQ(n, 2);
  }
}

TEST(ConvexHull, InteriorAndDuplicatePointsAreDropped) {
  auto pts = boxCorners(Vec3(1, 1, 1));
  pts.push_back(Vec3(0, 0, 0));
  pts.push_back(Vec3(0.5, 0.2, -0.3));
  pts.push_back(Vec3(1, 1, 1));  // duplicate corner
  pts.push_back(Vec3(1, 0, 0));  // centre of a face
  pts.push_back(Vec3(1, 1, 0));  // middle of an edge
  auto s = Shape::convexHull(pts);
  EXPECT_EQ(s->hull().vertices.size(), 8u);
  EXPECT_EQ(s->hull().faces.size(), 6u);
  expectEuler(s->hull());
}

TEST(ConvexHull, IsDeterministic) {
  const auto pts = randomPoints(300, 42, 1.0);
  auto a = Shape::convexHull(pts), b = Shape::convexHull(pts);
  ASSERT_EQ(a->hull().faces.size(), b->hull().faces.size());
  for (size_t i = 0; i < a->hull().faces.size(); ++i)
    EXPECT_EQ(a->hull().faces[i].vertices, b->hull().faces[i].vertices);
}

TEST(MassProperties, HullOfBoxCornersEqualsBoxMass) {
  const Vec3 h(0.3, 0.5, 0.7);
  const MassProperties box = Shape::box(h)->massProperties(800.0);
  auto pts = boxCorners(h);
  for (Vec3& p : pts) p += Vec3(1, 2, 3);  // off-centre hull: com must follow
  const MassProperties hull = Shape::convexHull(pts)->massProperties(800.0);
  EXPECT_NEAR(hull.mass, box.mass, 1e-9 * box.mass);
  EXPECT_NEAR(hull.volume, 8 * 0.3 * 0.5 * 0.7, 1e-12);
  EXPECT_TRUE(hull.com.isApprox(Vec3(1, 2, 3), 1e-12));
  EXPECT_TRUE(hull.inertia.isApprox(box.inertia, 1e-9));
}

TEST(MassProperties, CompoundOfTwoBoxesMatchesOneLongBox) {
  // Two unit cubes side by side along x (one rotated 90 degrees about y: same cube) form a
  // 2x1x1 box centred between them.
  const Vec3 h(0.5, 0.5, 0.5);
  auto cube = Shape::box(h);
  auto c = Shape::compound(
      {{cube, Transform{Vec3(1.5, 0, 0), Quat::Identity()}},
       {cube, Transform{Vec3(2.5, 0, 0), grip::test::rot(kPi / 2, Vec3::UnitY())}}});
  const MassProperties m = c->massProperties(2.0);
  const MassProperties ref = boxMass(Vec3(1.0, 0.5, 0.5), 2.0);
  EXPECT_NEAR(m.mass, ref.mass, 1e-12);
  EXPECT_TRUE(m.com.isApprox(Vec3(2, 0, 0), 1e-12));
  EXPECT_TRUE(m.inertia.isApprox(ref.inertia, 1e-12));
}

TEST(MassProperties, PrimitivesAndPlanes) {
  EXPECT_NEAR(Shape::sphere(0.5)->massProperties(1000).mass, 1000 * 4.0 / 3.0 * kPi * 0.125, 1e-9);
  EXPECT_NEAR(Shape::capsule(0.1, 0.2)->massProperties(1).volume,
              kPi * 0.01 * 0.4 + 4.0 / 3.0 * kPi * 0.001, 1e-12);
  EXPECT_EQ(Shape::plane(Vec3::UnitY(), 0)->massProperties(1).mass, 0.0);
}

TEST(ShapeSupport, IncludesRounding) {
  const Vec3 d = Vec3(1, 1, 1).normalized();
  EXPECT_TRUE(Shape::sphere(2.0)->support(d).isApprox(2.0 * d, 1e-14));
  EXPECT_TRUE(Shape::box(Vec3(1, 2, 3), 0.5)->support(d).isApprox(Vec3(1, 2, 3) + 0.5 * d, 1e-14));
  EXPECT_TRUE(Shape::capsule(0.5, 1.0)->support(-d).isApprox(Vec3(0, -1, 0) - 0.5 * d, 1e-14));
  auto hull = Shape::convexHull(boxCorners(Vec3(1, 1, 1)), 0.25);
  EXPECT_TRUE(hull->support(d).isApprox(Vec3(1, 1, 1) + 0.25 * d, 1e-14));
}

TEST(ShapeBounds, TransformedAndInflated) {
  auto cap = Shape::capsule(0.5, 1.0);
  Transform t{Vec3(1, 0, 0), grip::test::rot(kPi / 2, Vec3::UnitZ())};  // axis along -x
  const Aabb b = cap->bounds(t);
  EXPECT_TRUE(b.min.isApprox(Vec3(-0.5, -0.5, -0.5), 1e-12));
  EXPECT_TRUE(b.max.isApprox(Vec3(2.5, 0.5, 0.5), 1e-12));
  auto box = Shape::box(Vec3(1, 1, 1))->inflated(0.1);
  EXPECT_NEAR(box->radius(), 0.1, 0);
  EXPECT_TRUE(box->localBounds().max.isApprox(Vec3::Constant(1.1), 1e-14));
  auto ground = Shape::plane(Vec3(0, 2, 0), 1.0);  // y <= 0.5
  EXPECT_NEAR(ground->planeOffset(), 0.5, 1e-15);
  EXPECT_NEAR(ground->localBounds().max.y(), 0.5, 1e-15);
  EXPECT_NEAR(ground->inflated(0.2)->planeOffset(), 0.7, 1e-15);
}

TEST(CompoundTree, QueryReturnsExactlyTheOverlappingChildren) {
  std::vector<CompoundChild> kids;
  auto cube = Shape::box(Vec3(0.1, 0.1, 0.1));
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      kids.push_back({cube, Transform{Vec3(0.5 * i, 0.5 * j, 0), Quat::Identity()}});
  auto c = Shape::compound(kids);
  EXPECT_LT(c->tree().nodes.size(), 2 * kids.size());
  // Depth stays logarithmic.
  std::function<int(int)> depth = [&](int n) {
    const auto& node = c->tree().nodes[n];
    return node.child >= 0 ? 1 : 1 + std::max(depth(node.left), depth(node.right));
  };
  EXPECT_LE(depth(0), 9);
  const Aabb q{Vec3(0.9, 0.9, -1), Vec3(2.1, 1.6, 1)};
  std::set<int> got;
  c->tree().query(q, [&](int i) { EXPECT_TRUE(got.insert(i).second); });
  std::set<int> expected;
  for (int i = 0; i < 100; ++i)
    if (c->children()[i].shape->bounds(c->children()[i].local).overlaps(q)) expected.insert(i);
  EXPECT_EQ(got, expected);
  EXPECT_EQ(expected.size(), 6u);  // i in 2..4, j in 2..3
}
