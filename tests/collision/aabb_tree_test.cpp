// The query tree against the definition: every item whose box overlaps the query box, or that
// the ray meets within its length, once, and nothing else; whatever the boxes' layout (a plane's
// half-infinite box among them, an infinite one, boxes with one centre, a single box, none).
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <vector>

#include "collision/aabb_tree.hpp"

namespace grip {
namespace {

std::vector<uint32_t> treeOverlaps(const AabbTree& t, const Aabb& box) {
  std::vector<uint32_t> out;
  t.query(box, [&](uint32_t id) { out.push_back(id); });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<uint32_t> treeRay(const AabbTree& t, const Vec3& o, const Vec3& d, double maxT) {
  std::vector<uint32_t> out;
  t.rayQuery(o, d, maxT, [&](uint32_t id) { out.push_back(id); });
  std::sort(out.begin(), out.end());
  return out;
}

// Ids are 1000 + index, so a mix-up of ids and positions shows.
void expectExact(const std::vector<Aabb>& boxes, std::mt19937& rng, int queries) {
  std::vector<uint32_t> ids;
  for (uint32_t i = 0; i < boxes.size(); ++i) ids.push_back(1000 + i);
  AabbTree tree;
  tree.build(boxes, ids);
  ASSERT_EQ(tree.size(), boxes.size());
  std::uniform_real_distribution<double> at(-6.0, 6.0), size(0.0, 1.5), unit(-1.0, 1.0);
  for (int q = 0; q < queries; ++q) {
    const Vec3 c(at(rng), at(rng), at(rng));
    const Aabb box{c - Vec3::Constant(size(rng)), c + Vec3::Constant(size(rng))};
    std::vector<uint32_t> expected;
    for (uint32_t i = 0; i < boxes.size(); ++i)
      if (boxes[i].overlaps(box)) expected.push_back(1000 + i);
    ASSERT_EQ(treeOverlaps(tree, box), expected) << "query " << q;

    Vec3 dir(unit(rng), unit(rng), unit(rng));
    if (q % 5 == 0) dir = Vec3(0.0, -1.0, 0.0);  // along an axis: zero components
    dir.normalize();
    const double length = q % 7 == 0 ? std::numeric_limits<double>::infinity() : 4.0 * size(rng);
    expected.clear();
    for (uint32_t i = 0; i < boxes.size(); ++i)
      if (AabbTree::rayMeetsBox(boxes[i], c, dir, length)) expected.push_back(1000 + i);
    ASSERT_EQ(treeRay(tree, c, dir, length), expected) << "ray " << q;
  }
}

TEST(AabbTree, FindsExactlyWhatEveryBoxTestFinds) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> at(-5.0, 5.0), half(0.01, 0.4);
  std::vector<Aabb> boxes;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 c(at(rng), at(rng), at(rng));
    boxes.push_back(
        {c - Vec3(half(rng), half(rng), half(rng)), c + Vec3(half(rng), half(rng), half(rng))});
  }
  // A ground plane's box: half-infinite, its centre far below everything else.
  boxes.push_back({Vec3(-1e15, -1e15, -1e15), Vec3(1e15, 0.0, 1e15)});
  expectExact(boxes, rng, 400);
}

TEST(AabbTree, CopesWithBoxesThatShareACentreAndWithTinyTrees) {
  std::mt19937 rng(5);
  std::vector<Aabb> same(100, Aabb{Vec3::Constant(-0.5), Vec3::Constant(0.5)});
  for (int i = 0; i < 100; i += 3) same[i].max.x() += 0.01 * i;  // one centre line
  expectExact(same, rng, 100);
  expectExact({Aabb{Vec3::Zero(), Vec3::Ones()}}, rng, 50);
  // A box without bounds (its centre NaN) among others, and one out at 1e300.
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<Aabb> wild = same;
  wild.push_back({Vec3::Constant(-inf), Vec3::Constant(inf)});
  wild.push_back({Vec3::Constant(1e300), Vec3::Constant(1e300) + Vec3::Ones()});
  expectExact(wild, rng, 100);
  AabbTree empty;
  empty.build({}, {});
  EXPECT_EQ(empty.size(), 0u);
  EXPECT_TRUE(treeOverlaps(empty, Aabb{Vec3::Constant(-1e9), Vec3::Constant(1e9)}).empty());
}

}  // namespace
}  // namespace grip
