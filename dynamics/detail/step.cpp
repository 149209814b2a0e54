// One step of the World, top to bottom:
//   collide       broadphase -> narrowphase -> contact manifolds (warm-start memory kept)
//   contactEvents begin/end of touching pairs, sensor overlaps
//   solve         soft-step solver: per substep integrate velocities, warm start, solve with
//                 bias, integrate positions, relax, hand loads down; then restitution,
//                 position projection, store impulses
//   updateSleep   islands; islands at rest long enough fall asleep
//   finishStep    clear forces, advance time
#include <algorithm>
#include <atomic>
#include <functional>
#include <limits>
#include <numeric>
#include <tuple>

#include "dynamics/detail/world_impl.hpp"

namespace grip {

using detail::Body;
using detail::ContactManifold;

void World::step(double dt) {
  requireFinite(dt, "step.dt");
  if (dt < 0.0) throw Error("step.dt", "must not be negative");
  if (dt == 0.0) return;
  Impl& w = *impl_;
  w.beginEvents.clear(), w.sensorBegin.clear();
  w.endEvents.swap(w.droppedEnds), w.sensorEnd.swap(w.droppedSensorEnds);
  w.droppedEnds.clear(), w.droppedSensorEnds.clear();
  w.jointBreaks.clear();
  w.queries.dirty = true;  // the solve moves boxes
  if (w.jointAliveCount > 0) w.wakeJoinedBodies();
  // A body woke: collide again so its island sees its resting contacts (and so on, should
  // that island touch another sleeping one; each round wakes one more island, so it ends).
  while (w.collide(dt)) {
  }
  w.contactEvents();
  w.solve(dt);
  w.updateSleep(dt);
  w.finishStep();
  w.time += dt;
  w.lastSubstep = dt / w.substepsFor(dt);
  if (w.jointAliveCount > 0) w.breakJoints();
  ++w.steps;
}

// ---- collide ------------------------------------------------------------------------------

namespace {
constexpr double kTouching = 1e-3;  // m: a manifold point this close counts as touching

// Warm-start memory for a new point: the old point with the same feature id, else the
// nearest old point within 5 mm (feature ids change when a face pair flips near a tie).
detail::PointState matchPoint(const ContactManifold& old, const ContactPoint& p) {
  int best = -1;
  double bestDist2 = 0.005 * 0.005;
  for (int j = 0; j < old.m.pointCount; ++j) {
    if (old.state[j].featureId == p.featureId) return old.state[j];
    const double d2 = (old.m.points[j].position - p.position).squaredNorm();
    if (d2 < bestDist2) best = j, bestDist2 = d2;
  }
  return best >= 0 ? old.state[best] : detail::PointState{};
}

bool isPolytope(const Shape& s) {
  return s.type() == ShapeType::Box || s.type() == ShapeType::ConvexHull;
}

// The velocity of the body's material at x.
Vec3 pointVelocity(const Body& b, const Vec3& x) {
  return b.v + b.w.cross(x - b.com);
}

// How fast the bodies close along `normal` at x.
double closingSpeedAt(const Body& A, const Body& B, const Vec3& normal, const Vec3& x) {
  return -(pointVelocity(B, x) - pointVelocity(A, x)).dot(normal);
}

// How fast the bodies close along the normal at the manifold's first point.
double closingSpeed(const Body& A, const Body& B, const Manifold& m) {
  return closingSpeedAt(A, B, m.normal, m.points[0].position);
}

// Whether B's pose relative to A (`relative`) is within `distance` and the angle whose half
// has cosine `halfCos` of `was`. A distance of 0 accepts nothing.
bool closeTo(const Transform& relative, const Transform& was, double distance, double halfCos) {
  return (relative.p - was.p).squaredNorm() < distance * distance &&
         std::abs(relative.q.dot(was.q)) >= halfCos;
}

// The points of a fresh convex manifold as fixed on each body, for carryAlong.
void remember(const Transform& relative, double margin, const Body& A, const Body& B,
              ContactManifold& c) {
  c.computedAt = relative;
  c.margin = margin;
  const Mat3 RA = A.pose.q.toRotationMatrix(), RB = B.pose.q.toRotationMatrix();
  c.localNormal = RA.transpose() * c.m.normal;
  for (int k = 0; k < c.m.pointCount; ++k) {
    const Vec3 half = (0.5 * c.m.points[k].separation) * c.m.normal;
    c.onA[k] = RA.transpose() * (c.m.points[k].position - half - A.pose.p);
    c.onB[k] = RB.transpose() * (c.m.points[k].position + half - B.pose.p);
  }
}

// c, a copy of last step's manifold, moved with the bodies: its points stay fixed on them, so
// the normal and the separations follow the motion (exactly for the points it has; a point that
// a new narrowphase would add or drop waits until the pair leaves the thresholds).
void carryAlong(const ContactManifold& last, const Body& A, const Body& B, ContactManifold& c) {
  const Mat3 RA = A.pose.q.toRotationMatrix(), RB = B.pose.q.toRotationMatrix();
  c.m.normal = RA * c.localNormal;
  c.touching = false;
  c.reused = true;
  for (int k = 0; k < c.m.pointCount; ++k) {
    const Vec3 a = RA * c.onA[k] + A.pose.p, b = RB * c.onB[k] + B.pose.p;
    c.m.points[k].position = 0.5 * (a + b);
    c.m.points[k].separation = (b - a).dot(c.m.normal);
    c.touching |= c.m.points[k].separation < kTouching;
  }
  c.approachSpeed = std::max(closingSpeed(A, B, c.m), last.touching ? 0.0 : last.approachSpeed);
}

// How far any point of the body can move in dt by turning: its spin times its reach from the
// centre of mass (bounded by its box's). Capped at 1 m, as the speculative margin is; an
// unbounded reach (not a finite box) counts as the cap.
double turnTravel(const Body& b, double dt) {
  const double spin = b.w.norm();
  if (!(spin > 0.0)) return 0.0;
  const double reach = (b.aabb.center() - b.com).norm() + 0.5 * (b.aabb.max - b.aabb.min).norm();
  const double travel = spin * reach * dt;
  return travel < 1.0 ? travel : 1.0;
}

// What accelerates the body this step before any contact, capped at 1 m of travel in the step
// as the margin is.
Vec3 accelerationOf(const Body& b, const Vec3& gravity, double dt) {
  if (!b.isDynamic()) return Vec3::Zero();
  return detail::limitLength(b.loadAcceleration(gravity), 1.0 / (dt * dt));
}

// v holds three runs, each sorted, ending at ends[0..2]: one sorted list after.
template <class T, class Less>
void mergeRuns(std::vector<T>& v, const size_t (&ends)[3], const Less& less) {
  const auto at = [&](size_t i) { return v.begin() + static_cast<long>(i); };
  std::inplace_merge(v.begin(), at(ends[0]), at(ends[1]), less);
  std::inplace_merge(v.begin(), at(ends[1]), at(ends[2]), less);
}

}  // namespace

bool World::Impl::collide(double dt) {
  // Proxies: the moving bodies (awake and not static: active) and the still ones they may
  // meet, in slot order. Among many still bodies, only those whose boxes a moving one's meets
  // (the queries' tree finds them) are proxies: a step of a world of sleeping bodies costs
  // what its moving ones do. Otherwise every live body is: pairs the same either way.
  const uint32_t n = static_cast<uint32_t>(bodies.size());
  detail::setSlots(movingSlot, movers);
  proxyBoxes.clear(), proxyActive.clear(), proxyBody.clear();
  motion.resize(n);
  auto moverBox = [&](uint32_t i) {
    const Body& b = bodies[i];
    detail::BodyMotion& m = motion[i];
    m.turnTravel = turnTravel(b, dt);
    m.acceleration = accelerationOf(b, def.gravity, dt);
    // b.aabb is current: every pose change (createBody, setPose, the solver's write-back)
    // refreshes it. Grow it by the speculative distance and by the motion of this step.
    Aabb box = b.aabb.inflated(def.speculativeDistance + m.turnTravel);
    // Its travel lies between the speed it has and the speed it gains (v dt + a dt^2 bounds a
    // substepped Euler step's).
    const Vec3 now = b.v * dt, gained = (b.v + m.acceleration * dt) * dt;
    box.min += now.cwiseMin(gained).cwiseMin(Vec3::Zero());
    box.max += now.cwiseMax(gained).cwiseMax(Vec3::Zero());
    return box;
  };
  auto addProxy = [&](uint32_t i, bool active, const Aabb& box) {
    if (!active) motion[i] = detail::BodyMotion{};
    proxyBoxes.push_back(box), proxyActive.push_back(active), proxyBody.push_back(i);
  };
  constexpr size_t kStillPerMover = 32;
  if (movers.size() * kStillPerMover < static_cast<size_t>(aliveCount)) {
    static thread_local std::vector<Aabb> moverBoxes;
    static thread_local std::vector<uint32_t> found;
    moverBoxes.clear(), nearMovers.clear();
    for (uint32_t i : movers) {
      moverBoxes.push_back(moverBox(i));
      queryCandidates(moverBoxes.back(), found);
      for (uint32_t j : found)
        if (!movingSlot[j]) nearMovers.push_back(j);
    }
    std::sort(nearMovers.begin(), nearMovers.end());
    nearMovers.erase(std::unique(nearMovers.begin(), nearMovers.end()), nearMovers.end());
    size_t k = 0;  // the two ascending lists merged
    for (uint32_t j : nearMovers) {
      for (; k < movers.size() && movers[k] < j; ++k) addProxy(movers[k], true, moverBoxes[k]);
      addProxy(j, false, bodies[j].aabb);
    }
    for (; k < movers.size(); ++k) addProxy(movers[k], true, moverBoxes[k]);
  } else {
    for (uint32_t i = 0; i < n; ++i) {
      if (!bodies[i].alive) continue;
      if (movingSlot[i])
        addProxy(i, true, moverBox(i));
      else
        addProxy(i, false, bodies[i].aabb);
    }
  }
  assignRegions();
  // A world at rest: nothing moves now, and last step's contacts were all kept ones (nothing
  // moved then either). No pair can be found, and every contact would be kept as it is: last
  // step's contacts stay this step's, with nothing to report (a settled 1000-box pile: 182 ->
  // 10 us a step).
  atRest = regionSlots.empty() && contacts.run[0].empty() && contacts.run[1].empty();
  if (atRest) {
    pairs.clear();
    previousSensorPairs = sensorPairs;  // every overlap stays (keepSensorPairs)
    stats.candidatePairs = 0, stats.reusedManifolds = 0;
    regionPairEnd = 0;
    return false;
  }
  broadphase.findPairs(proxyBoxes, proxyActive, pairs,
                       [this](const std::function<void(int)>& part) { inBothRegions(part); });

  std::swap(previous, contacts);
  for (std::vector<ContactManifold>& run : contacts.run) run.clear();
  previousSensorPairs.swap(sensorPairs);
  sensorPairs.clear();
  stats.candidatePairs = static_cast<int>(pairs.size());

  // Narrowphase and warm-start matching, pure functions of the poses: each region's pairs (by
  // the pair's first moving body, in key order) on the thread that will solve them, into the
  // region's run of the contact list. Waking (a side effect) follows.
  regionPairEnd = pairs.size();
  if (regionCount == 2) {  // region 1's pairs to the end, in order (a stable partition)
    regionOnePairs.clear();
    size_t kept = 0;
    for (const auto& pair : pairs) {
      const uint8_t a = bodyRegion[proxyBody[pair.first]];
      const uint8_t region = a != detail::kNoRegion ? a : bodyRegion[proxyBody[pair.second]];
      if (region == 1)
        regionOnePairs.push_back(pair);
      else
        pairs[kept++] = pair;
    }
    regionPairEnd = kept;
    std::copy(regionOnePairs.begin(), regionOnePairs.end(),
              pairs.begin() + static_cast<long>(kept));
  }
  inBothRegions([&](int region) { narrowphase(region, dt); });
  bool woke = false;
  stats.reusedManifolds = 0;
  for (const detail::NarrowphaseOut& out : narrowphaseOut) {
    sensorPairs.insert(sensorPairs.end(), out.sensorPairs.begin(), out.sensorPairs.end());
    for (uint32_t sleeper : out.sleepersTouched) {
      if (bodies[sleeper].awake) continue;  // its island woke already
      wakeBody(sleeper);
      woke = true;
    }
    stats.reusedManifolds += out.reused;
  }
  if (woke) {  // collide again from the same warm-start memory
    std::swap(previous, contacts);
    previousSensorPairs.swap(sensorPairs);
    return true;
  }
  keepContacts();
  keepSensorPairs();
  return false;
}

// The overlaps of a sensor and a visitor that both stay put (sleeping, or one static) go on
// as they were: no pair between still bodies is looked for, and a box that falls asleep
// inside a trigger has not left it (Unity's triggers report no exit for a sleeping body).
// Two static bodies never make a pair, so a visitor turned static leaves.
void World::Impl::keepSensorPairs() {
  for (const detail::SensorPair& p : previousSensorPairs) {
    const Body &S = bodies[p.sensor], &V = bodies[p.visitor];
    const bool oneMovable = S.type != BodyType::Static || V.type != BodyType::Static;
    if (!movingSlot[p.sensor] && !movingSlot[p.visitor] && oneMovable) sensorPairs.push_back(p);
  }
}

// The contacts between bodies that do not move (sleeping or static) are not recomputed: last
// step's are kept as they were, in key order. Where they are exactly last step's kept ones
// (none of those bodies woke, none fell asleep: a hand moving one object among sleeping
// ones), the run is taken over whole instead of copied (3 000 manifolds of a sleeping pile:
// 2 MB a step), and the events leave it out (contactEvents).
void World::Impl::keepContacts() {
  constexpr int kKept = detail::ContactRuns::kKept;
  auto stays = [&](uint64_t key) {
    return !movingSlot[detail::firstOfPair(key)] && !movingSlot[detail::secondOfPair(key)];
  };
  auto allStay = [&](const detail::ContactRuns::Run& run, bool stay) {
    return std::all_of(run.pairKeys.begin(), run.pairKeys.end(),
                       [&](uint64_t key) { return stays(key) == stay; });
  };
  detail::ContactRuns::Run& kept = contacts.run[kKept];
  // The same movers as the contacts were made with: each pair is still or not as it was, so
  // the test below holds without walking the kept run (a contact per sleeping body).
  keptTakenOver = movers == contactMovers ||
                  (allStay(previous.run[kKept], true) && allStay(previous.run[0], false) &&
                   allStay(previous.run[1], false));
  contactMovers = movers;
  if (keptTakenOver) {
    std::swap(kept, previous.run[kKept]);
    return;
  }
  size_t ends[3] = {};
  for (int run = 0; run < 3; ++run) {
    const detail::ContactRuns::Run& list = previous.run[run];
    for (size_t i = 0; i < list.size(); ++i)
      if (stays(list.pairKeys[i])) kept.push_back(list[i]);
    ends[run] = kept.size();
  }
  mergeRuns(kept, ends,
            [](const ContactManifold& x, const ContactManifold& y) { return x.keyLess(y); });
  kept.indexKeys();
}

// Regions: with many moving bodies, the step's work is cut in two halves, at the median of
// the moving bodies' centres along their widest extent; each half's narrowphase and solve run
// on their own thread (collide, solve), and the manifolds across the cut after both. The order
// is the same with one thread as with two, so the result is too. Fewer bodies stay one region
// (the order of the step as it was before regions).
// The moving bodies are collide's movers (in slot order): the bodies are not walked.
void World::Impl::assignRegions() {
  for (uint32_t slot : regionSlots) bodyRegion[slot] = detail::kNoRegion;  // last round's
  bodyRegion.resize(bodies.size(), detail::kNoRegion);
  regionSlots.assign(movers.begin(), movers.end());
  for (uint32_t slot : regionSlots) bodyRegion[slot] = 0;
  const size_t n = regionSlots.size();
  regionCount = n < detail::kRegionBodies ? 1 : 2;
  regionSlotEnd = n;
  if (regionCount == 1) return;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (uint32_t slot : regionSlots) {
    lo = lo.cwiseMin(bodies[slot].com);
    hi = hi.cwiseMax(bodies[slot].com);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  regionScratch.resize(n);
  for (size_t k = 0; k < n; ++k) regionScratch[k] = bodies[regionSlots[k]].com[axis];
  std::nth_element(regionScratch.begin(), regionScratch.begin() + static_cast<long>(n / 2),
                   regionScratch.end());
  const double median = regionScratch[n / 2];
  for (uint32_t slot : regionSlots) bodyRegion[slot] = bodies[slot].com[axis] < median ? 0 : 1;
  // Region 0's first (each in index order): the solve's bodies in this order keep each
  // region's cache lines together.
  regionOrder.clear();
  for (uint8_t region = 0; region < 2; ++region) {
    for (uint32_t slot : regionSlots)
      if (bodyRegion[slot] == region) regionOrder.push_back(slot);
    if (region == 0) regionSlotEnd = regionOrder.size();
  }
  regionSlots.swap(regionOrder);
}

void World::Impl::narrowphase(int region, double dt) {
  detail::NarrowphaseOut& out = narrowphaseOut[region];
  detail::ContactRuns::Run& made = contacts.run[region];
  out.sensorPairs.clear(), out.sleepersTouched.clear();
  const size_t begin = region == 0 ? 0 : regionPairEnd;
  const size_t end = region == 0 ? regionPairEnd : pairs.size();
  const double reuseHalfCos = std::cos(0.5 * def.contactReuseAngle);
  // A convex pair makes one manifold at most: room for all, and to spare, so that the list does
  // not grow a few times as a pile lands (each time into fresh pages).
  if (end - begin > made.capacity()) made.reserve(2 * (end - begin));
  // Last step's manifolds, each run walked along with the pairs (all in key order) from this
  // region's first pair on.
  PreviousCursors cursor{};
  if (begin < end) {
    const uint64_t first =
        detail::makePairKey(proxyBody[pairs[begin].first], proxyBody[pairs[begin].second]);
    for (int run = 0; run < 3; ++run)
      cursor[static_cast<size_t>(run)] = previous.firstOf(run, first);
  }
  for (size_t pair = begin; pair < end; ++pair) {
    const uint32_t ia = proxyBody[pairs[pair].first], ib = proxyBody[pairs[pair].second];
    const Body &A = bodies[ia], &B = bodies[ib];
    if (!A.isDynamic() && !B.isDynamic() && !A.sensor && !B.sensor) continue;
    if (!shouldCollide(A.filter, B.filter)) continue;
    if (!jointPairs.empty() &&
        std::binary_search(jointPairs.begin(), jointPairs.end(),
                           detail::makePairKey(std::min(ia, ib), std::max(ia, ib))))
      continue;  // joined, without contacts between them
    if (A.sensor || B.sensor) {
      if (A.sensor && B.sensor) continue;
      out.scratch.clear();
      grip::collide(*A.shape, A.pose, *B.shape, B.pose, 0.0, out.scratch);
      bool overlapping = false;
      for (const Manifold& m : out.scratch)
        for (int k = 0; k < m.pointCount; ++k) overlapping |= m.points[k].separation < 0.0;
      if (overlapping) out.sensorPairs.push_back({A.sensor ? ia : ib, A.sensor ? ib : ia});
      continue;
    }
    // A convex pair with a box or hull (whose narrowphase costs more than this) that barely
    // moved since its manifold was computed carries the manifold along.
    const bool carriable = A.shape->isConvex() && B.shape->isConvex() &&
                           (isPolytope(*A.shape) || isPolytope(*B.shape));
    const Transform relative = carriable ? A.pose.inverse() * B.pose : Transform{};
    // Speculative margin: the contact is made early enough to stop this step's approach, by
    // their relative motion (two bodies falling side by side do not close), the speed gravity and
    // applied forces add within the step (a box at rest above the floor falls g dt^2 towards it)
    // and their turns (the tip of a spinning plank closes at its spin times its length).
    const double approach = (B.v - A.v).norm() * dt +
                            (motion[ib].acceleration - motion[ia].acceleration).norm() * dt * dt +
                            motion[ia].turnTravel + motion[ib].turnTravel;
    const double margin = def.speculativeDistance + std::min(approach, 1.0);
    // A sleeping body wakes (collide) when a point touches or closes this step at the speed
    // it closes with: treated as still, the sleeper would stop a ball rolling into it dead, its
    // speculative contact a wall, and wake a step later without the blow. Not where nothing
    // moves at the point (a kinematic platform standing still under a sleeping box would
    // wake it each time it fell asleep).
    const size_t first = made.size();
    auto wakeIfReached = [&] {
      if (A.awake == B.awake) return;
      const uint32_t sleeper = A.awake ? ib : ia;
      if (!bodies[sleeper].isDynamic()) return;
      const Vec3 gain = motion[ia].acceleration - motion[ib].acceleration;
      for (size_t i = first; i < made.size(); ++i) {
        const Manifold& m = made[i].m;
        const double gained = gain.dot(m.normal);
        for (int k = 0; k < m.pointCount; ++k) {
          const Vec3& x = m.points[k].position;
          const bool moves = gain != Vec3::Zero() || pointVelocity(A, x) != pointVelocity(B, x);
          const double closing = closingSpeedAt(A, B, m.normal, x);
          if (moves &&
              m.points[k].separation < kTouching + std::max(closing + gained * dt, 0.0) * dt) {
            out.sleepersTouched.push_back(sleeper);
            return;
          }
        }
      }
    };
    // Carried along, but not when the margin has grown by half the speculative distance or
    // more: a point it left out could then close this step (it was farther than the old
    // margin, less the pair's motion since, a few mm at the thresholds).
    const ContactManifold* last = findPrevious(cursor, ia, ib, 0, 0);  // cursor at the pair
    if (carriable && last && margin < last->margin + 0.5 * def.speculativeDistance &&
        closeTo(relative, last->computedAt, def.contactReuseDistance, reuseHalfCos)) {
      carryAlong(*last, A, B, made.emplace_back(*last));
      wakeIfReached();
      continue;
    }
    out.scratch.clear();
    grip::collide(*A.shape, A.pose, *B.shape, B.pose, margin, out.scratch);
    for (const Manifold& m : out.scratch) {
      if (m.pointCount == 0) continue;
      ContactManifold& c = made.emplace_back();
      c.bodyA = ia, c.bodyB = ib, c.m = m;
      // Carry warm-start impulses over from last step by matching feature ids.
      auto from = cursor;
      const ContactManifold* old =
          carriable ? last : findPrevious(from, ia, ib, m.childA, m.childB);
      for (int k = 0; k < m.pointCount; ++k) {
        c.touching |= m.points[k].separation < kTouching;
        if (old) c.state[k] = matchPoint(*old, m.points[k]);
        c.state[k].featureId = m.points[k].featureId;
      }
      if (old) {
        for (int r = 0; r < 3; ++r) c.friction[r] = old->friction[r];
        c.sliding = old->sliding;
        c.anchored = old->anchored, c.anchorA = old->anchorA, c.anchorB = old->anchorB;
      }
      // Speculative contacts slow bodies before they touch: remember how fast they closed.
      c.approachSpeed =
          std::max(closingSpeed(A, B, m), old && !old->touching ? old->approachSpeed : 0.0);
      if (carriable) remember(relative, margin, A, B, c);
    }
    wakeIfReached();
  }
  made.indexKeys();
  out.reused = 0;
  for (const ContactManifold& c : made) out.reused += c.reused;
}

// Last step's manifold of a pair of bodies and children, or null. Each cursor moves forward
// along its run's pair keys to the pair's first manifold (or past where it would be), so a
// walk over pairs in order is one pass over the keys.
const ContactManifold* World::Impl::findPrevious(PreviousCursors& from, uint32_t ia, uint32_t ib,
                                                 uint32_t childA, uint32_t childB) const {
  const uint64_t pair = detail::makePairKey(ia, ib);
  const auto key = std::make_tuple(ia, ib, childA, childB);
  for (int run = 0; run < 3; ++run) {
    const detail::ContactRuns::Run& list = previous.run[run];
    size_t& i = from[static_cast<size_t>(run)];
    while (i < list.size() && list.pairKeys[i] < pair) ++i;
    for (size_t j = i; j < list.size() && list.pairKeys[j] == pair; ++j)  // one per child pair
      if (list[j].key() == key) return &list[j];
  }
  return nullptr;
}

// ---- events -------------------------------------------------------------------------------

namespace {
struct PairTouch {
  uint64_t key;
  const ContactManifold* first;  // the first touching manifold of the pair
};

// The touching pairs of the first `runs` runs (a pair's manifolds are all in one run), merged
// in key order.
void touchingPairs(const detail::ContactRuns& list, int runs, std::vector<PairTouch>& out) {
  out.clear();
  size_t ends[3] = {};
  for (int run = 0; run < runs; ++run) {
    const size_t runStart = out.size();
    const detail::ContactRuns::Run& r = list.run[run];
    for (size_t i = 0; i < r.size(); ++i) {
      if (!r.touching[i]) continue;
      if (out.size() > runStart && out.back().key == r.pairKeys[i]) continue;
      out.push_back({r.pairKeys[i], &r[i]});
    }
    ends[run] = out.size();
  }
  for (int run = runs; run < 3; ++run) ends[run] = out.size();
  mergeRuns(out, ends, [](const PairTouch& x, const PairTouch& y) { return x.key < y.key; });
}
}  // namespace

ContactEvent World::Impl::contactEvent(const ContactManifold& c) const {
  ContactEvent e;
  e.a = idOf(c.bodyA), e.b = idOf(c.bodyB);
  e.normal = c.m.normal;
  e.point = c.m.points[0].position;
  e.approachSpeed = std::max(0.0, c.approachSpeed);
  return e;
}

void World::Impl::contactEvents() {
  static thread_local std::vector<PairTouch> now, before;
  // At rest the contacts are last step's (collide), and `previous` was not moved up to them.
  // A kept run taken over whole (keepContacts) holds the same pairs before and now, none of
  // them in another run: it makes no event.
  now.clear(), before.clear();
  const int runs = keptTakenOver ? 2 : 3;
  if (!atRest) touchingPairs(contacts, runs, now), touchingPairs(previous, runs, before);
  size_t i = 0, j = 0;
  while (i < now.size() || j < before.size()) {
    if (j == before.size() || (i < now.size() && now[i].key < before[j].key)) {
      beginEvents.push_back(contactEvent(*now[i++].first));
    } else if (i == now.size() || before[j].key < now[i].key) {
      const ContactManifold& c = *before[j++].first;
      if (bodies[c.bodyA].alive && bodies[c.bodyB].alive) endEvents.push_back(contactEvent(c));
    } else {
      ++i, ++j;
    }
  }
  std::sort(sensorPairs.begin(), sensorPairs.end());
  static thread_local std::vector<detail::SensorPair> diff;
  diff.clear();
  std::set_difference(sensorPairs.begin(), sensorPairs.end(), previousSensorPairs.begin(),
                      previousSensorPairs.end(), std::back_inserter(diff));
  for (const auto& p : diff) sensorBegin.push_back({idOf(p.sensor), idOf(p.visitor)});
  diff.clear();
  std::set_difference(previousSensorPairs.begin(), previousSensorPairs.end(), sensorPairs.begin(),
                      sensorPairs.end(), std::back_inserter(diff));
  for (const auto& p : diff)
    if (bodies[p.sensor].alive && bodies[p.visitor].alive)
      sensorEnd.push_back({idOf(p.sensor), idOf(p.visitor)});
}

// ---- sleep --------------------------------------------------------------------------------

namespace {
uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}
}  // namespace

// Whether a body is still calm. Its calm time starts at an instant below both sleep velocities
// and goes on while its mean velocities since then stay low and it never moves faster than
// kTremble times them. Mean velocities because a settled pile trembles (measured: about a
// hundred of its 1000 boxes turning at 0.05-0.4 rad/s at any instant, each about a fixed
// pose): read by the instant, its one island never slept. The mean linear velocity is held to
// half the sleep velocity, so a body speeding up from rest stays awake as long as its speed
// alone would keep it awake (a box starting to slide is not frozen).
bool World::Impl::calm(const Body& b, double dt) const {
  constexpr double kTremble = 10.0;
  const double v = b.v.norm(), w = b.w.norm();
  if (b.sleepTime == 0.0) return v < def.sleepLinearVelocity && w < def.sleepAngularVelocity;
  if (!(v < kTremble * def.sleepLinearVelocity && w < kTremble * def.sleepAngularVelocity))
    return false;
  const double t = b.sleepTime + dt;
  if (!((b.com - b.restCom).norm() < 0.5 * def.sleepLinearVelocity * t)) return false;
  return Eigen::AngleAxisd(b.pose.q * b.restQ.conjugate()).angle() < def.sleepAngularVelocity * t;
}

void World::Impl::updateSleep(double dt) {
  stats.islands = stats.sleepingIslands = 0;
  if (awakeBodies.empty()) return;  // (a world at rest)
  // Islands: awake dynamic bodies joined by touching contacts (static bodies do not join), by
  // solver index (a world of sleeping bodies is not walked); each island's root is its body
  // of the lowest slot.
  static thread_local std::vector<uint32_t> parent, roots, islandGroup;
  static thread_local std::vector<double> islandSleepTime;
  const uint32_t n = static_cast<uint32_t>(awakeBodies.size());
  parent.resize(n + 1);
  std::iota(parent.begin(), parent.end(), 0u);
  // Each body's calm time, on the thread of its region (the body's cache lines are that
  // thread's); the islands read the packed copies.
  calmTimes.resize(n), calmDynamic.resize(n);
  const auto movingKinematic = [](const Body& b) {
    return b.type == BodyType::Kinematic && !(b.v.isZero(0.0) && b.w.isZero(0.0));
  };
  std::atomic<bool> kinematicMoves = false;
  inBothRegions([&](int region) {
    for (int k : bodiesOf(region)) {
      Body& b = bodies[awakeBodies[k]];
      if (b.allowSleep && b.isDynamic() && calm(b, dt))
        b.sleepTime += dt;
      else
        b.restartCalm();
      calmTimes[k] = b.sleepTime, calmDynamic[k] = b.isDynamic();
      if (movingKinematic(b)) kinematicMoves.store(true, std::memory_order_relaxed);
    }
  });
  // A body touching a moving kinematic one is carried or pushed by it: not calm, however slow
  // (a box on a platform that has just started is, for a step or two).
  if (kinematicMoves)
    for (int r = 0; r < 2; ++r) {
      const detail::ContactRuns::Run& run = contacts.run[r];
      for (size_t i = 0; i < run.size(); ++i) {
        if (!run.touching[i]) continue;
        const uint32_t a = detail::firstOfPair(run.pairKeys[i]);
        const uint32_t b = detail::secondOfPair(run.pairKeys[i]);
        for (const auto& [mover, other] : {std::pair{a, b}, std::pair{b, a}}) {
          const int s = solverIndexOf[other];
          if (s == 0 || !movingKinematic(bodies[mover])) continue;
          bodies[other].restartCalm();
          calmTimes[static_cast<size_t>(s - 1)] = 0.0;
        }
      }
    }
  // The solver index of a body awake (moving) and dynamic, else 0.
  auto awakeDynamic = [&](uint32_t slot) {
    const int s = solverIndexOf[slot];
    return s != 0 && calmDynamic[static_cast<size_t>(s - 1)] ? static_cast<uint32_t>(s) : 0u;
  };
  auto join = [&](uint32_t a, uint32_t b) {
    if (a == 0 || b == 0) return;
    const uint32_t ra = findRoot(parent, a), rb = findRoot(parent, b);
    if (ra == rb) return;
    if (awakeBodies[ra - 1] < awakeBodies[rb - 1])
      parent[rb] = ra;
    else
      parent[ra] = rb;
  };
  for (int r = 0; r < 2; ++r) {  // (the kept run joins only bodies that do not move)
    const detail::ContactRuns::Run& run = contacts.run[r];
    for (size_t i = 0; i < run.size(); ++i)
      if (run.touching[i])
        join(awakeDynamic(detail::firstOfPair(run.pairKeys[i])),
             awakeDynamic(detail::secondOfPair(run.pairKeys[i])));
  }
  for (const detail::Joint& j : joints)  // joined bodies sleep and wake together
    if (j.alive) join(awakeDynamic(j.a), awakeDynamic(j.b));
  islandSleepTime.assign(n + 1, 1e300);
  for (uint32_t k = 1; k <= n; ++k) {
    const uint32_t r = findRoot(parent, k);
    islandSleepTime[r] = std::min(islandSleepTime[r], calmTimes[k - 1]);
  }
  // The islands in the slot order of their roots (awakeBodies is not in slot order), each
  // falling asleep numbered in turn.
  roots.clear();
  for (uint32_t k = 1; k <= n; ++k)
    if (parent[k] == k) roots.push_back(k);
  std::sort(roots.begin(), roots.end(),
            [&](uint32_t x, uint32_t y) { return awakeBodies[x - 1] < awakeBodies[y - 1]; });
  islandGroup.assign(n + 1, 0);
  int sleeping = 0;
  for (uint32_t r : roots) {
    if (!def.enableSleep || islandSleepTime[r] < def.timeToSleep) continue;
    ++sleeping;
    islandGroup[r] = nextSleepGroup++;
    if (nextSleepGroup == 0) nextSleepGroup = 1;
  }
  if (sleeping > 0) {
    for (uint32_t k = 1; k <= n; ++k) {
      const uint32_t group = islandGroup[findRoot(parent, k)];
      if (group == 0) continue;
      const uint32_t slot = awakeBodies[k - 1];
      Body& b = bodies[slot];
      b.awake = false;
      b.v.setZero(), b.w.setZero();
      b.sleepGroup = group;
      sleepingIslands[group].push_back(slot);
      markMoving(slot);
    }
  }
  stats.islands = static_cast<int>(roots.size());
  stats.sleepingIslands = sleeping;
}

void World::Impl::finishStep() {
  // Only the bodies with loads: a store, even of zeros, takes the body's cache line from the
  // thread that solves it. Every load wakes its body (addForce, addTorque, addForcesAtPositions)
  // so they are all on bodies that moved this step.
  const auto loaded = [](const Vec3& x) { return (x.array() != 0.0).any(); };
  for (uint32_t slot : awakeBodies) {
    Body& b = bodies[slot];
    if (!loaded(b.force) && !loaded(b.torque) && !loaded(b.linearAccel) && !loaded(b.angularAccel))
      continue;
    b.force.setZero(), b.torque.setZero();
    b.linearAccel.setZero(), b.angularAccel.setZero();
  }
}

}  // namespace grip
