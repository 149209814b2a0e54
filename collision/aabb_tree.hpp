// A bounding-volume tree over boxes for queries (rays, overlaps): built at once over the
// boxes in the Morton order of their centres, each node halving its run of them, then only
// read. The world's queries keep one over the bodies that have not moved since it was built
// (dynamics/detail/world.cpp, "queries"): a scene at rest answers in O(log n), not O(n).
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.hpp"

namespace grip {

class AabbTree {
 public:
  // Replaces the tree with one over `boxes`, item i being ids[i] (the two the same length).
  void build(const std::vector<Aabb>& boxes, const std::vector<uint32_t>& ids);
  size_t size() const { return items_.size(); }

  // Calls visit(id) for each item whose box overlaps `box`, in no particular order.
  template <class Visit>
  void query(const Aabb& box, const Visit& visit) const {
    walk([&](const Aabb& b) { return b.overlaps(box); }, visit);
  }
  // Calls visit(id) for each item whose box the ray origin + t dir, t in [0, maxT], meets.
  template <class Visit>
  void rayQuery(const Vec3& origin, const Vec3& dir, double maxT, const Visit& visit) const {
    walk([&](const Aabb& b) { return rayMeetsBox(b, origin, dir, maxT); }, visit);
  }

  // Whether the ray origin + t dir, t in [0, maxT], meets the box (slabs; a direction with a
  // zero component stays within that slab or misses).
  static bool rayMeetsBox(const Aabb& b, const Vec3& origin, const Vec3& dir, double maxT);

 private:
  // A leaf holds items [first, first + count); an inner node (count 0) has its first child
  // next to it and its second at `first`.
  struct Node {
    Aabb box;
    uint32_t first = 0, count = 0;
  };
  std::vector<Node> nodes_;
  std::vector<uint32_t> items_;  // ids, in leaf order
  std::vector<Aabb> itemBoxes_;  // their boxes, the same order
  // The build's scratch, kept as the tree is: fresh pages cost more than the build (over
  // 50 000 boxes on an AMD EPYC VM: 14-18 ms for the first build, 0.9-1.4 ms for later ones).
  std::vector<uint32_t> codes_, order_, sorted_;

  uint32_t buildRange(uint32_t begin, uint32_t end);

  template <class Hits, class Visit>
  void walk(const Hits& hits, const Visit& visit) const {
    if (nodes_.empty()) return;
    uint32_t stack[64];  // the tree is balanced: depth about log2(n / 4)
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!hits(n.box)) continue;
      if (n.count > 0) {
        for (uint32_t i = n.first; i < n.first + n.count; ++i)
          if (hits(itemBoxes_[i])) visit(items_[i]);
        continue;
      }
      const uint32_t self = static_cast<uint32_t>(&n - nodes_.data());
      stack[top++] = n.first;
      stack[top++] = self + 1;
    }
  }
};

}  // namespace grip
