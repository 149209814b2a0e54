// The baked signed-distance field against an analytic torus: distances, closest points, normals
// and ray casts, near the surface and far from it.
#include <gtest/gtest.h>

#include <random>

#include "collision/sdf.hpp"
#include "voxel_test_util.hpp"

namespace grip::voxel::test {
namespace {

class TorusSdf : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // A fine tessellation: the facets stay within 0.02 mm of the analytic torus, far below the
    // tolerances tested here (the SDF spacing is ~2.7 mm).
    const Mesh mesh = repairMesh(torus.mesh(256, 128));
    PrepOptions opt;
    opt.lod = Lod::High;
    asset = new AssetData(prepare(mesh, opt));
    sdf = new SignedDistanceField(asset->sdf);
  }
  static void TearDownTestSuite() {
    delete sdf;
    delete asset;
  }
  static inline Torus torus;
  static inline AssetData* asset = nullptr;
  static inline SignedDistanceField* sdf = nullptr;

  // Random points whose true distance to the torus lies in [lo, hi].
  static std::vector<Vec3> pointsAtDistance(double lo, double hi, int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.08, 0.08);
    std::vector<Vec3> out;
    while (static_cast<int>(out.size()) < count) {
      const Vec3 p(u(rng), 0.5 * u(rng), u(rng));
      const double d = torus.distance(p);
      if (d >= lo && d <= hi && std::hypot(p.x(), p.z()) > 1e-3) out.push_back(p);
    }
    return out;
  }
};

TEST_F(TorusSdf, DistanceMatchesTheTorusNearTheSurface) {
  const double h = sdf->spacing();
  double worst = 0.0;
  for (const Vec3& p : pointsAtDistance(-2.0 * h, 2.0 * h, 2000, 1))
    worst = std::max(worst, std::abs(sdf->distance(p) - torus.distance(p)));
  EXPECT_LT(worst, 0.25 * h) << "spacing " << h;
}

TEST_F(TorusSdf, SignIsRightEverywhere) {
  const double h = sdf->spacing();
  for (const Vec3& p : pointsAtDistance(-0.015, 0.1, 2000, 2)) {
    const double truth = torus.distance(p);
    if (std::abs(truth) < 0.5 * h) continue;
    EXPECT_EQ(sdf->distance(p) < 0.0, truth < 0.0) << p.transpose();
  }
}

TEST_F(TorusSdf, ClosestPointsLieWithinAQuarterVoxelOfTheSurface) {
  const double h = sdf->spacing();
  const double band = asset->sdf.band;
  // Within the narrow band (contact range): on the surface and the true nearest point.
  double worstOnSurface = 0.0, worstNearest = 0.0;
  for (const Vec3& p : pointsAtDistance(-(band - h), band - h, 2000, 3)) {
    const Vec3 c = sdf->closestPoint(p);
    worstOnSurface = std::max(worstOnSurface, std::abs(torus.distance(c)));
    worstNearest = std::max(worstNearest, std::abs((c - p).norm() - std::abs(torus.distance(p))));
  }
  EXPECT_LT(worstOnSurface, 0.25 * h);
  EXPECT_LT(worstNearest, 0.25 * h);
  // Far beyond the band (answered through the coarse lattice): still a point on the surface,
  // and not much farther than the true nearest one (documented: within a coarse cell).
  double worstFarOnSurface = 0.0, worstFarExcess = 0.0;
  for (const Vec3& p : pointsAtDistance(band, 0.06, 1000, 6)) {
    const Vec3 c = sdf->closestPoint(p);
    worstFarOnSurface = std::max(worstFarOnSurface, std::abs(torus.distance(c)));
    worstFarExcess = std::max(worstFarExcess, (c - p).norm() - torus.distance(p));
  }
  EXPECT_LT(worstFarOnSurface, 0.25 * h);
  EXPECT_LT(worstFarExcess, SignedDistanceField::kBrick * h);
}

TEST_F(TorusSdf, NormalsAgreeWithinAFewDegrees) {
  const double h = sdf->spacing();
  double worst = 0.0;
  for (const Vec3& p : pointsAtDistance(-1.5 * h, 1.5 * h, 2000, 4)) {
    const double cosAngle = sdf->normal(p).dot(torus.normal(p));
    worst = std::max(worst, std::acos(std::clamp(cosAngle, -1.0, 1.0)) * 180.0 / kPi);
  }
  EXPECT_LT(worst, 3.0) << "degrees";
}

TEST_F(TorusSdf, RaysHitTheSurface) {
  const double h = sdf->spacing();
  // Straight down onto the top of the tube: analytic hit at t = 0.1 - r.
  double t = 0.0;
  Vec3 n;
  ASSERT_TRUE(sdf->rayCast(Vec3(torus.R, 0.1, 0.0), -Vec3::UnitY(), 1.0, t, n));
  EXPECT_NEAR(t, 0.1 - torus.r, 0.25 * h);
  EXPECT_GT(n.dot(Vec3::UnitY()), std::cos(3.0 * kPi / 180.0));
  // Down the hole misses; too short a ray misses.
  EXPECT_FALSE(sdf->rayCast(Vec3(0.0, 0.1, 0.0), -Vec3::UnitY(), 1.0, t, n));
  EXPECT_FALSE(sdf->rayCast(Vec3(torus.R, 0.1, 0.0), -Vec3::UnitY(), 0.05, t, n));
  // From random outside points toward random surface targets: the hit is on the surface and
  // no farther than the target.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(0.0, 2.0 * kPi);
  for (int i = 0; i < 500; ++i) {
    const double a = angle(rng), b = angle(rng);
    const double rr = torus.R + torus.r * std::cos(b);
    const Vec3 target(rr * std::cos(a), torus.r * std::sin(b), rr * std::sin(a));
    const Vec3 from =
        target + 0.05 * torus.normal(target) + 0.01 * Vec3(std::cos(b), 0.3, std::sin(a));
    if (torus.distance(from) < 0.01) continue;
    const Vec3 dir = (target - from).normalized();
    ASSERT_TRUE(sdf->rayCast(from, dir, 1.0, t, n));
    EXPECT_LT(std::abs(torus.distance(from + t * dir)), 0.25 * h);
    EXPECT_LT(t, (target - from).norm() + 0.25 * h);
  }
  // Starting inside: a hit at t = 0.
  ASSERT_TRUE(sdf->rayCast(Vec3(torus.R, 0.0, 0.0), Vec3::UnitX(), 1.0, t, n));
  EXPECT_EQ(t, 0.0);
}

TEST(SignedDistanceField, RefusesInconsistentData) {
  SignedDistanceField::Data d;
  d.spacing = 0.01;
  d.band = 0.03;
  d.samples = {4, 4, 4};
  d.bricks = {SignedDistanceField::kOutside};
  d.coarse.assign(8, 1.0f);
  EXPECT_NO_THROW(SignedDistanceField{d});
  auto bad = d;
  bad.samples = {5, 4, 4};
  EXPECT_THROW(SignedDistanceField{bad}, Error);
  bad = d;
  bad.bricks = {3};  // no such brick
  EXPECT_THROW(SignedDistanceField{bad}, Error);
  bad = d;
  bad.coarse.pop_back();
  EXPECT_THROW(SignedDistanceField{bad}, Error);
  bad = d;
  bad.spacing = std::nan("");
  EXPECT_THROW(SignedDistanceField{bad}, Error);
}

}  // namespace
}  // namespace grip::voxel::test
