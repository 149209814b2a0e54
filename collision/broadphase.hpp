// Broadphase: sort-and-sweep over AABBs along the axis of largest spread. Chosen over a
// dynamic tree because grip's scenes rebuild every step anyway and a sweep over a nearly
// sorted array is cache friendly and trivially deterministic (see docs/performance.md).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/math.hpp"

namespace grip {

class SweepBroadphase {
 public:
  // All overlapping pairs (i < j) among `boxes`, sorted. `active[i]` false: i only pairs with
  // active proxies (static or sleeping proxies never pair with each other).
  void findPairs(const std::vector<Aabb>& boxes, const std::vector<uint8_t>& active,
                 std::vector<std::pair<uint32_t, uint32_t>>& pairs);

 private:
  std::vector<uint32_t> order_;  // kept between calls: nearly sorted next time
  std::vector<double> keys_;
};

}  // namespace grip
