#include "collision/broadphase.hpp"

#include <algorithm>

namespace grip {

void SweepBroadphase::findPairs(const std::vector<Aabb>& boxes, const std::vector<uint8_t>& active,
                                std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
  pairs.clear();
  const uint32_t n = static_cast<uint32_t>(boxes.size());
  if (n < 2) return;

  // Sweep along the axis where the centres spread most.
  Vec3 mean = Vec3::Zero(), meanSq = Vec3::Zero();
  for (const Aabb& b : boxes) {
    const Vec3 c = b.center();
    mean += c;
    meanSq += c.cwiseProduct(c);
  }
  const Vec3 variance = meanSq / n - (mean / n).cwiseProduct(mean / n);
  int axis = 0;
  if (variance.y() > variance[axis]) axis = 1;
  if (variance.z() > variance[axis]) axis = 2;

  // Keep last call's order: insertion sort on a nearly sorted array is close to linear.
  if (order_.size() != n) {
    order_.resize(n);
    for (uint32_t i = 0; i < n; ++i) order_[i] = i;
  }
  keys_.resize(n);
  for (uint32_t i = 0; i < n; ++i) keys_[i] = boxes[i].min[axis];
  auto less = [&](uint32_t a, uint32_t b) {
    return keys_[a] < keys_[b] || (keys_[a] == keys_[b] && a < b);
  };
  for (uint32_t i = 1; i < n; ++i) {
    const uint32_t v = order_[i];
    uint32_t j = i;
    while (j > 0 && less(v, order_[j - 1])) {
      order_[j] = order_[j - 1];
      --j;
    }
    order_[j] = v;
  }

  const int axis1 = (axis + 1) % 3, axis2 = (axis + 2) % 3;
  swept_.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    const Aabb& b = boxes[order_[i]];
    swept_[i] = {b.min[axis],  b.max[axis],  b.min[axis1], b.max[axis1],
                 b.min[axis2], b.max[axis2], order_[i],    active[order_[i]]};
  }
  for (uint32_t i = 0; i < n; ++i) {
    const Swept& a = swept_[i];
    for (uint32_t j = i + 1; j < n; ++j) {
      const Swept& b = swept_[j];
      if (b.start > a.end) break;
      if (!(a.active | b.active)) continue;
      if (a.min1 > b.max1 || b.min1 > a.max1 || a.min2 > b.max2 || b.min2 > a.max2) continue;
      pairs.emplace_back(std::min(a.proxy, b.proxy), std::max(a.proxy, b.proxy));
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace grip
