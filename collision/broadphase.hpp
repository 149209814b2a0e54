// Broadphase: sort-and-sweep over AABBs along the axis of largest spread, in strips across
// the next axis (a sweep over one axis alone meets every proxy in the same slab: in a pile,
// a whole row of every layer). Chosen over a dynamic tree because grip's scenes rebuild every
// step anyway and a sweep over a nearly sorted array is cache friendly and trivially
// deterministic (see docs/performance.md). With a few active proxies among many (most asleep),
// each active one is tested against every proxy instead.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "core/math.hpp"

namespace grip {

class SweepBroadphase {
 public:
  // Runs part(0) and part(1), on two threads where the caller has them (in any order: the
  // parts share nothing they write). Empty: one after the other.
  using TwoParts = std::function<void(const std::function<void(int)>& part)>;

  // All overlapping pairs (i < j) among `boxes`, sorted. `active[i]` false: i only pairs with
  // active proxies (static or sleeping proxies never pair with each other). The sweep runs in
  // two halves through `twoParts`; the pairs are the same either way.
  void findPairs(const std::vector<Aabb>& boxes, const std::vector<uint8_t>& active,
                 std::vector<std::pair<uint32_t, uint32_t>>& pairs, const TwoParts& twoParts = {});

 private:
  // A proxy as the sweep reads it, in sweep order: the inner loop walks memory in a line.
  struct Swept {
    double start, end;              // along the sweep axis
    double min1, max1, min2, max2;  // along the other two axes (axis 1 is cut in strips)
    uint32_t proxy;
    uint32_t strip;  // the strip the proxy starts in
    uint8_t active;
  };
  std::vector<uint32_t> order_;       // kept between calls: nearly sorted next time
  std::vector<uint32_t> activeList_;  // (when there are few)
  std::vector<double> keys_, widths_;
  std::vector<uint8_t> wide_;  // tested against every proxy, not in strips
  std::vector<uint32_t> stripLo_, stripHi_, stripStart_, fill_, wideList_;
  std::vector<Swept> swept_;  // each strip's proxies in sweep order, strip after strip
  std::vector<std::pair<uint32_t, uint32_t>> scratch_;
  std::vector<std::pair<uint32_t, uint32_t>> secondHalf_;  // the sweep's second half's pairs
  uint32_t splitStrip_ = 0;                                // the second half's first strip

  void sweepStrips(uint32_t first, uint32_t last,
                   std::vector<std::pair<uint32_t, uint32_t>>& out) const;
};

}  // namespace grip
