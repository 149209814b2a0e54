#include "collision/broadphase.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grip {

namespace {

// A proxy wider than this many strips along some axis is tested against every proxy.
constexpr double kWideStrips = 8.0;
constexpr uint32_t kBruteForce = 16;  // proxies up to which every pair is tested directly
// Active proxies up to which each is tested against every proxy instead of sweeping them all
// (a hand moving one object over a table of sleeping ones): 16 x 1000 box tests cost less than
// one sweep of 1000 proxies.
constexpr size_t kFewActive = 16;

}  // namespace

namespace {

// Stable counting sort of `in` into `out` by key(p) in [0, n).
template <class Key>
void countingSortBy(const std::vector<std::pair<uint32_t, uint32_t>>& in,
                    std::vector<std::pair<uint32_t, uint32_t>>& out, uint32_t n, Key key,
                    std::vector<uint32_t>& start) {
  start.assign(n + 1, 0);
  for (const auto& p : in) ++start[key(p) + 1];
  for (uint32_t i = 0; i < n; ++i) start[i + 1] += start[i];
  for (const auto& p : in) out[start[key(p)]++] = p;
}

}  // namespace

void SweepBroadphase::findPairs(const std::vector<Aabb>& boxes, const std::vector<uint8_t>& active,
                                std::vector<std::pair<uint32_t, uint32_t>>& pairs,
                                const TwoParts& twoParts) {
  pairs.clear();
  const uint32_t n = static_cast<uint32_t>(boxes.size());
  if (n <= kBruteForce) {  // a few proxies: every pair, in order, beats setting up the sweep
    for (uint32_t i = 0; i < n; ++i)
      for (uint32_t j = i + 1; j < n; ++j)
        if ((active[i] | active[j]) && boxes[i].overlaps(boxes[j])) pairs.emplace_back(i, j);
    return;
  }
  activeList_.clear();
  for (uint32_t i = 0; i < n && activeList_.size() <= kFewActive; ++i)
    if (active[i]) activeList_.push_back(i);
  if (activeList_.size() <= kFewActive) {
    for (uint32_t a : activeList_)
      for (uint32_t j = 0; j < n; ++j)  // (a pair of two active proxies once: from the first)
        if (j != a && (!active[j] || a < j) && boxes[a].overlaps(boxes[j]))
          pairs.emplace_back(std::min(a, j), std::max(a, j));
    std::sort(pairs.begin(), pairs.end());
    return;
  }

  // Wide proxies (the ground, a table: wider than kWideStrips strips along some axis, or with a
  // NaN bound) are few; they are tested against every proxy and take no part in the rest.
  Vec3 strip;  // twice the median width along each axis
  widths_.resize(n);
  for (int k = 0; k < 3; ++k) {
    for (uint32_t i = 0; i < n; ++i) {
      const double w = boxes[i].max[k] - boxes[i].min[k];
      widths_[i] = std::isnan(w) ? std::numeric_limits<double>::infinity() : w;  // sortable
    }
    std::nth_element(widths_.begin(), widths_.begin() + n / 2, widths_.end());
    strip[k] = 2.0 * widths_[n / 2];
  }
  wide_.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 w = boxes[i].max - boxes[i].min;
    wide_[i] = !((boxes[i].min.array() <= boxes[i].max.array()).all() && w.allFinite() &&
                 (w.array() <= kWideStrips * strip.array()).all());
  }

  // Sweep along the axis where the centres spread most; cut the next one into strips.
  Vec3 mean = Vec3::Zero(), meanSq = Vec3::Zero();
  uint32_t narrow = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (wide_[i]) continue;
    const Vec3 c = boxes[i].center();
    mean += c, meanSq += c.cwiseProduct(c);
    ++narrow;
  }
  const double count = std::max(narrow, 1u);
  const Vec3 variance = meanSq / count - (mean / count).cwiseProduct(mean / count);
  int axis = 0;
  if (variance.y() > variance[axis]) axis = 1;
  if (variance.z() > variance[axis]) axis = 2;
  int axis1 = (axis + 1) % 3, axis2 = (axis + 2) % 3;
  if (variance[axis2] > variance[axis1]) std::swap(axis1, axis2);

  // Keep last call's order: insertion sort on a nearly sorted array is close to linear.
  if (order_.size() != n) {
    order_.resize(n);
    for (uint32_t i = 0; i < n; ++i) order_[i] = i;
  }
  keys_.resize(n);
  for (uint32_t i = 0; i < n; ++i)  // wide proxies first (a NaN key would break the order)
    keys_[i] = wide_[i] ? -std::numeric_limits<double>::infinity() : boxes[i].min[axis];
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

  // Strips across axis1: a sweep along one axis alone meets every proxy in the same slab (a
  // pile's whole row, all layers); in strips it meets the proxy's neighbours. A pair is
  // reported in the strip where the later of its two starts along axis1 falls, so once.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (uint32_t i = 0; i < n; ++i) {
    if (wide_[i]) continue;
    lo = std::min(lo, boxes[i].min[axis1]), hi = std::max(hi, boxes[i].max[axis1]);
  }
  double width = strip[axis1];
  if (!(width > 0.0 && std::isfinite(width))) width = hi > lo ? hi - lo : 1.0;
  if (hi > lo) width = std::max(width, (hi - lo) / n);  // at most n + 1 strips
  stripLo_.resize(n), stripHi_.resize(n);
  uint32_t stripCount = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (wide_[i]) continue;
    stripLo_[i] = static_cast<uint32_t>((boxes[i].min[axis1] - lo) / width);
    stripHi_[i] = static_cast<uint32_t>((boxes[i].max[axis1] - lo) / width);
    stripCount = std::max(stripCount, stripHi_[i] + 1);
  }
  // Each strip's proxies in sweep order (a counting sort by strip, stable).
  wideList_.clear();
  stripStart_.assign(stripCount + 1, 0);
  for (uint32_t i = 0; i < n; ++i) {
    if (wide_[i]) continue;
    for (uint32_t s = stripLo_[i]; s <= stripHi_[i]; ++s) ++stripStart_[s + 1];
  }
  for (uint32_t s = 0; s < stripCount; ++s) stripStart_[s + 1] += stripStart_[s];
  swept_.resize(stripStart_[stripCount]);
  fill_.assign(stripStart_.begin(), stripStart_.end() - 1);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t i = order_[k];
    if (wide_[i]) {
      wideList_.push_back(i);
      continue;
    }
    const Aabb& b = boxes[i];
    const Swept entry{b.min[axis],  b.max[axis], b.min[axis1], b.max[axis1], b.min[axis2],
                      b.max[axis2], i,           stripLo_[i],  active[i]};
    for (uint32_t s = stripLo_[i]; s <= stripHi_[i]; ++s) swept_[fill_[s]++] = entry;
  }

  // The strips in two halves of about as many entries, each into its own list, so that two
  // threads can share the sweep (two thirds of the broadphase's time; on two threads the
  // 1000-box pile's broadphase went from 0.63 to 0.53 Mcycles a step).
  splitStrip_ = static_cast<uint32_t>(
      std::upper_bound(stripStart_.begin(), stripStart_.end(), stripStart_[stripCount] / 2) -
      stripStart_.begin() - 1);
  secondHalf_.clear();
  // (Capturing two pointers only: std::function keeps it without allocating.)
  const std::function<void(int)> part = [this, &pairs](int k) {
    if (k == 0) sweepStrips(0, splitStrip_, pairs);
    if (k == 1)
      sweepStrips(splitStrip_, static_cast<uint32_t>(stripStart_.size() - 1), secondHalf_);
  };
  if (twoParts)
    twoParts(part);
  else
    part(0), part(1);
  pairs.insert(pairs.end(), secondHalf_.begin(), secondHalf_.end());
  // The wide proxies against everything (each pair of two wide ones once).
  for (uint32_t g : wideList_) {
    for (uint32_t i = 0; i < n; ++i) {
      if (i == g || (wide_[i] && i < g)) continue;
      if (!(active[g] | active[i]) || !boxes[g].overlaps(boxes[i])) continue;
      pairs.emplace_back(std::min(g, i), std::max(g, i));
    }
  }
  // Sorted by (first, second): two stable counting sorts on proxy indices (by second, then by
  // first), linear where a comparison sort took a tenth of the broadphase's time on a pile.
  scratch_.resize(pairs.size());
  countingSortBy(
      pairs, scratch_, n, [](const auto& p) { return p.second; }, fill_);
  countingSortBy(
      scratch_, pairs, n, [](const auto& p) { return p.first; }, fill_);
}

// The pairs whose later start along axis 1 falls in strips [first, last), in sweep order.
void SweepBroadphase::sweepStrips(uint32_t first, uint32_t last,
                                  std::vector<std::pair<uint32_t, uint32_t>>& out) const {
  for (uint32_t s = first; s < last; ++s) {
    const uint32_t end = stripStart_[s + 1];
    for (uint32_t i = stripStart_[s]; i < end; ++i) {
      const Swept& a = swept_[i];
      for (uint32_t j = i + 1; j < end; ++j) {
        const Swept& b = swept_[j];
        if (b.start > a.end) break;
        // One branch for the whole test: one per part mispredicted often (perf, the pile:
        // findPairs 6.5 -> 5.3 % of the step).
        const bool apart = (a.min1 > b.max1) | (b.min1 > a.max1) | (a.min2 > b.max2) |
                           (b.min2 > a.max2) | !(a.active | b.active) |
                           (std::max(a.strip, b.strip) != s);  // or reported in another strip
        if (apart) continue;
        out.emplace_back(std::min(a.proxy, b.proxy), std::max(a.proxy, b.proxy));
      }
    }
  }
}

}  // namespace grip
