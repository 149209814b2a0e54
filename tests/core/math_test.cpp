#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/mass.hpp"
#include "core/math.hpp"

using namespace grip;

TEST(Transform, ComposeAndInvert) {
  Transform a{Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(0.7, Vec3(1, 1, 0).normalized()))};
  Transform b{Vec3(-2, 0.5, 4), Quat(Eigen::AngleAxisd(-1.2, Vec3::UnitZ()))};
  const Vec3 x(0.3, -0.4, 0.9);
  EXPECT_TRUE((a * b).apply(x).isApprox(a.apply(b.apply(x)), 1e-14));
  EXPECT_TRUE(a.inverse().apply(a.apply(x)).isApprox(x, 1e-14));
  EXPECT_TRUE(a.applyInverse(a.apply(x)).isApprox(x, 1e-14));
}

TEST(Rotation, IntegrationFollowsConstantAngularVelocity) {
  const Vec3 w(0, 0, 2.0);  // rad/s about z
  Quat q = Quat::Identity();
  const int n = 10000;
  for (int i = 0; i < n; ++i) q = integrateRotation(q, w, 1.0 / n);
  const Quat expected(Eigen::AngleAxisd(2.0, Vec3::UnitZ()));
  EXPECT_NEAR(q.angularDistance(expected), 0.0, 1e-6);
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
}

TEST(TangentBasis, IsOrthonormalAndRightHanded) {
  for (const Vec3& n : {Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, -1), Vec3(1, 2, 3).normalized(),
                        Vec3(-0.6, 0.0, 0.8)}) {
    Vec3 t1, t2;
    tangentBasis(n, t1, t2);
    EXPECT_NEAR(t1.norm(), 1.0, 1e-14);
    EXPECT_NEAR(t2.norm(), 1.0, 1e-14);
    EXPECT_NEAR(t1.dot(n), 0.0, 1e-14);
    EXPECT_NEAR(t2.dot(n), 0.0, 1e-14);
    EXPECT_TRUE(t1.cross(t2).isApprox(n, 1e-14));
  }
}

TEST(MassProperties, BoxMatchesAnalytic) {
  const MassProperties mp = boxMass(Vec3(0.5, 1.0, 1.5), 2.0);  // 1 x 2 x 3 m
  EXPECT_DOUBLE_EQ(mp.volume, 6.0);
  EXPECT_DOUBLE_EQ(mp.mass, 12.0);
  EXPECT_DOUBLE_EQ(mp.inertia(0, 0), 12.0 / 12.0 * (4 + 9));
  EXPECT_DOUBLE_EQ(mp.inertia(1, 1), 12.0 / 12.0 * (1 + 9));
  EXPECT_DOUBLE_EQ(mp.inertia(2, 2), 12.0 / 12.0 * (1 + 4));
}

TEST(MassProperties, SphereMatchesAnalytic) {
  const MassProperties mp = sphereMass(0.5, 1000.0);
  EXPECT_NEAR(mp.mass, 1000.0 * 4.0 / 3.0 * kPi * 0.125, 1e-9);
  EXPECT_NEAR(mp.inertia(1, 1), 0.4 * mp.mass * 0.25, 1e-9);
}

TEST(MassProperties, CapsuleTendsToSphereAndCylinder) {
  // Zero-length capsule is a sphere.
  const MassProperties s = capsuleMass(0.3, 0.0, 500.0);
  const MassProperties ref = sphereMass(0.3, 500.0);
  EXPECT_NEAR(s.mass, ref.mass, 1e-12);
  EXPECT_TRUE(s.inertia.isApprox(ref.inertia, 1e-12));
  // A long thin capsule approaches a rod: I_lateral ~ m L^2 / 12.
  const MassProperties rod = capsuleMass(1e-3, 1.0, 1000.0);
  EXPECT_NEAR(rod.inertia(0, 0) / (rod.mass * 4.0 / 12.0), 1.0, 1e-2);
}

TEST(MassProperties, MeshOfBoxMatchesBox) {
  // A 1 x 2 x 3 box offset from the origin, as 12 outward triangles.
  std::vector<Vec3> v;
  const Vec3 c(5, -1, 2), h(0.5, 1.0, 1.5);
  for (int i = 0; i < 8; ++i)
    v.push_back(c + Vec3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
  const std::vector<std::array<int, 3>> t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                             {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                             {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  const MassProperties mp = meshMass(v, t, 2.0);
  const MassProperties ref = boxMass(h, 2.0);
  EXPECT_NEAR(mp.volume, 6.0, 1e-12);
  EXPECT_TRUE(mp.com.isApprox(c, 1e-12));
  EXPECT_TRUE(mp.inertia.isApprox(ref.inertia, 1e-12));
}

TEST(MassProperties, ParallelAxis) {
  const MassProperties mp = sphereMass(1.0, 1.0);
  const Mat3 shifted = shiftInertia(mp.inertia, mp.mass, Vec3(2, 0, 0));
  EXPECT_NEAR(shifted(0, 0), mp.inertia(0, 0), 1e-12);
  EXPECT_NEAR(shifted(1, 1), mp.inertia(1, 1) + 4 * mp.mass, 1e-12);
}

TEST(StateHash, EqualBitsEqualHash) {
  StateHash a, b, c;
  a.add(Vec3(1, 2, 3));
  b.add(Vec3(1, 2, 3));
  c.add(Vec3(1, 2, std::nextafter(3.0, 4.0)));
  EXPECT_EQ(a.value(), b.value());
  EXPECT_NE(a.value(), c.value());
  EXPECT_EQ(a.hex().size(), 16u);
}

TEST(Errors, NameTheField) {
  try {
    requirePositive(-1.0, "BodyDef.mass");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "BodyDef.mass");
    EXPECT_NE(std::string(e.what()).find("must be positive"), std::string::npos);
  }
  EXPECT_THROW(requireFinite(Vec3(0, NAN, 0), "x"), Error);
  EXPECT_THROW(requireFinite(std::numeric_limits<double>::infinity(), "x"), Error);
}
