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

  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t a = order_[i];
    const Aabb& ba = boxes[a];
    const double end = ba.max[axis];
    for (uint32_t j = i + 1; j < n; ++j) {
      const uint32_t b = order_[j];
      if (keys_[b] > end) break;
      if (!active[a] && !active[b]) continue;
      if (!ba.overlaps(boxes[b])) continue;
      pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace grip
