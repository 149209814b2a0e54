// Narrowphase cost per pair type. Each benchmark collides one fixed, touching configuration
// into a reused vector (as the world's step does).
#include <benchmark/benchmark.h>

#include <random>

#include "collision/narrowphase.hpp"

using namespace grip;

namespace {

Transform at(const Vec3& p, const Quat& q = Quat::Identity()) {
  return Transform{p, q};
}

void run(benchmark::State& state, const Shape& a, const Transform& ta, const Shape& b,
         const Transform& tb) {
  std::vector<Manifold> out;
  out.reserve(256);
  for (auto _ : state) {
    out.clear();
    benchmark::DoNotOptimize(collide(a, ta, b, tb, 0.02, out));
    benchmark::ClobberMemory();
  }
  if (out.empty()) state.SkipWithError("no contact: the scene is wrong");
}

std::vector<Vec3> roundish(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Vec3> v;
  for (int i = 0; i < n; ++i) v.push_back(Vec3(g(rng), g(rng), g(rng)).normalized() * 0.5);
  return v;
}

}  // namespace

static void BM_Collision_SphereSphere(benchmark::State& state) {
  auto s = Shape::sphere(0.5);
  run(state, *s, at(Vec3::Zero()), *s, at(Vec3(0.3, 0.9, 0.1)));
}
BENCHMARK(BM_Collision_SphereSphere);

static void BM_Collision_BoxBox(benchmark::State& state) {
  auto b = Shape::box(Vec3(0.5, 0.5, 0.5));
  const Quat q(Eigen::AngleAxisd(0.3, Vec3::UnitY()));
  run(state, *b, at(Vec3::Zero()), *b, at(Vec3(0.1, 0.99, 0.05), q));
}
BENCHMARK(BM_Collision_BoxBox);

static void BM_Collision_BoxPlane(benchmark::State& state) {
  auto ground = Shape::plane(Vec3::UnitY(), 0.0);
  auto b = Shape::box(Vec3(0.5, 0.5, 0.5));
  run(state, *ground, at(Vec3::Zero()), *b, at(Vec3(0.0, 0.49, 0.0)));
}
BENCHMARK(BM_Collision_BoxPlane);

static void BM_Collision_CapsuleBox(benchmark::State& state) {
  auto c = Shape::capsule(0.1, 0.3);
  auto b = Shape::box(Vec3(0.5, 0.5, 0.5));
  const Quat q(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
  run(state, *b, at(Vec3::Zero()), *c, at(Vec3(0.1, 0.59, 0.0), q));
}
BENCHMARK(BM_Collision_CapsuleBox);

static void BM_Collision_HullHull(benchmark::State& state) {
  // Overlapping cores: GJK, then libccd's EPA, then face clipping.
  auto h = Shape::convexHull(roundish(32, 7));
  const Quat q(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  run(state, *h, at(Vec3::Zero()), *h, at(Vec3(0.2, 0.85, 0.1), q));
}
BENCHMARK(BM_Collision_HullHull);

static void BM_Collision_Compound100Plane(benchmark::State& state) {
  auto cube = Shape::box(Vec3(0.05, 0.05, 0.05));
  std::vector<CompoundChild> kids;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) kids.push_back({cube, at(Vec3(0.1 * i, 0.1 * j, 0.0))});
  auto c = Shape::compound(kids);
  auto ground = Shape::plane(Vec3::UnitY(), 0.0);
  // Lying flat (rotated so the 10x10 grid faces the ground): every child touches.
  const Quat q(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));
  run(state, *c, at(Vec3(0, 0.049, 0), q), *ground, at(Vec3::Zero()));
}
BENCHMARK(BM_Collision_Compound100Plane);
