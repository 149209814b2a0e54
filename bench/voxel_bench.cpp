// Concave objects: preparation time and box count per level of detail, SDF query cost, and the
// cost of a voxel compound resting on a plane per level of detail.
//   BM_Voxel_Prepare/<object>/<lod>   counters: boxes, voxels, volume error (%)
//   BM_Voxel_Sdf*                     one query per iteration, near the mug's surface
//   BM_Voxel_CompoundVsPlane/<lod>    narrowphase of the mug standing on a plane
#include <benchmark/benchmark.h>

#include <random>

#include "collision/asset.hpp"
#include "collision/narrowphase.hpp"
#include "collision/sdf.hpp"
#include "voxel/voxel.hpp"

using namespace grip;
using namespace grip::voxel;

namespace {

const char* kObjects[] = {"mug", "axe", "torus", "l-block", "figurine"};
const Lod kLods[] = {Lod::Low, Lod::Medium, Lod::High, Lod::VeryHigh};

void BM_Voxel_Prepare(benchmark::State& state) {
  const std::string name = kObjects[state.range(0)];
  const Lod lod = kLods[state.range(1)];
  const Mesh mesh = repairMesh(builtinMesh(name));
  PrepOptions opt;
  opt.lod = lod;
  PrepStats st;
  for (auto _ : state) benchmark::DoNotOptimize(prepare(mesh, opt, &st));
  state.SetLabel(name + "/" + lodName(lod));
  state.counters["boxes"] = static_cast<double>(st.boxes);
  state.counters["voxels"] = static_cast<double>(st.voxels);
  state.counters["volErr%"] = 100.0 * st.volumeError();
}
BENCHMARK(BM_Voxel_Prepare)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1, 2, 3}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

// The mug at high detail and query points within 1 cm of its surface.
struct MugQueries {
  AssetData asset;
  std::unique_ptr<SignedDistanceField> sdf;
  std::vector<Vec3> points;
  MugQueries() {
    PrepOptions opt;
    asset = prepare(repairMesh(builtinMesh("mug")), opt);
    sdf = std::make_unique<SignedDistanceField>(asset.sdf);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.06, 0.09);
    while (points.size() < 4096) {
      const Vec3 p(u(rng), u(rng) + 0.03, u(rng));
      if (std::abs(sdf->distance(p)) < 0.01) points.push_back(p);
    }
  }
};
const MugQueries& mugQueries() {
  static const MugQueries q;
  return q;
}

void BM_Voxel_SdfDistance(benchmark::State& state) {
  const auto& q = mugQueries();
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(q.sdf->distance(q.points[i++ & 4095]));
}
BENCHMARK(BM_Voxel_SdfDistance);

void BM_Voxel_SdfDistanceAndNormal(benchmark::State& state) {
  const auto& q = mugQueries();
  size_t i = 0;
  Vec3 n;
  for (auto _ : state) {
    benchmark::DoNotOptimize(q.sdf->distanceAndNormal(q.points[i++ & 4095], n));
    benchmark::DoNotOptimize(n);
  }
}
BENCHMARK(BM_Voxel_SdfDistanceAndNormal);

void BM_Voxel_SdfClosestPoint(benchmark::State& state) {
  const auto& q = mugQueries();
  size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(q.sdf->closestPoint(q.points[i++ & 4095]));
}
BENCHMARK(BM_Voxel_SdfClosestPoint);

void BM_Voxel_SdfRayCast(benchmark::State& state) {
  const auto& q = mugQueries();
  size_t i = 0;
  double t = 0.0;
  Vec3 n;
  for (auto _ : state) {
    const Vec3 p = q.points[i++ & 4095];
    const Vec3 from = p + 0.05 * (p - Vec3(0.0, 0.05, 0.0)).normalized();
    benchmark::DoNotOptimize(q.sdf->rayCast(from, (p - from).normalized(), 1.0, t, n));
  }
}
BENCHMARK(BM_Voxel_SdfRayCast);

void BM_Voxel_CompoundVsPlane(benchmark::State& state) {
  const Lod lod = kLods[state.range(0)];
  PrepOptions opt;
  opt.lod = lod;
  const LoadedAsset a = makeAssetShape(prepare(repairMesh(builtinMesh("mug")), opt));
  const ShapePtr plane = Shape::plane(Vec3::UnitY(), 0.0);
  Transform mugPose;
  mugPose.p = Vec3(0.0, 0.001, 0.0);
  std::vector<Manifold> out;
  for (auto _ : state) {
    out.clear();
    collide(*plane, Transform{}, *a.shape, mugPose, 0.02, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetLabel(lodName(lod));
  state.counters["boxes"] = static_cast<double>(a.shape->children().size());
  state.counters["manifolds"] = static_cast<double>(out.size());
}
BENCHMARK(BM_Voxel_CompoundVsPlane)->DenseRange(0, 3);

}  // namespace
