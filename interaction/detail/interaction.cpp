// The interaction update. One pass per world step, top to bottom:
//   take tracking frames -> drop dead contacts -> find contacts (bone overlaps) ->
//   place contact points -> friction forces (or the kinematic baseline) -> visual hands.
#include "interaction/interaction.hpp"

#include "collision/sdf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace grip {

namespace {

constexpr int kMaxSamples = 9;
// A slipping point moved along the surface is kept only where the surface faces about the same
// way (3.7: the point stays in the "blocked" area instead of jumping to a hidden face).
const double kNormalAgreement = std::cos(35.0 * kPi / 180.0);
constexpr double kRayBackoff = 0.001;  // m

struct Sample {
  Vec3 cLocal = Vec3::Zero();   // contact point, body coordinates
  Vec3 nLocal = Vec3::UnitY();  // outward normal, body coordinates
  Vec3 pBone = Vec3::Zero();    // target point, bone coordinates
};

struct Contact {
  uint32_t hand = 0;  // hand slot
  int bone = 0;
  BodyId body;
  uint32_t child = 0;
  bool seen = false;      // reported by this update's overlap query
  bool anchored = false;  // pressing: the patch is fixed on the body
  bool passive = false;   // began too deep (resumed tracking): no force until it surfaces
  bool slipping = false;
  bool fresh = false;   // began in this update (its begin event is still to be sent)
  bool swept = false;   // began on the bone's path (fast bone): anchored at the first touch
  Transform touchPose;  // the bone's pose at that first touch
  // From this update's overlap: the deepest point pair, normal from bone to body.
  Vec3 bonePoint = Vec3::Zero();
  Vec3 contactNormal = Vec3::UnitY();
  double separation = 0.0;
  int sampleCount = 0;
  std::array<Sample, kMaxSamples> samples{};
  Transform boneInBody;  // visual hand: the bone relative to the body at anchoring time
  Vec3 point = Vec3::Zero(), normal = Vec3::UnitY();  // world, for events and queries
  Vec3 force = Vec3::Zero();
};

bool contactLess(const Contact& a, const Contact& b) {
  if (a.body != b.body) return a.body < b.body;
  if (a.hand != b.hand) return a.hand < b.hand;
  return a.bone < b.bone;
}

struct Hand {
  uint32_t generation = 0;
  bool alive = false;
  HandDef def;
  HandShapes shapes;
  HandPose tracked;
  HandPose visual;
  HandPose pending;
  HandPose previous;  // the tracked pose before this update's frame (for swept contacts)
  bool hasPrevious = false;
  bool hasPending = false;
  bool active = false;   // has a usable pose (tracked now or within the grace period)
  bool release = false;  // end all contacts at the next update
  double sinceFrame = 0.0;
  Transform previousPalm;
  bool hasPreviousPalm = false;
  Vec3 palmVelocity = Vec3::Zero();
  Vec3 palmAngularVelocity = Vec3::Zero();
};

// What the last update saw of a touched body, to estimate the forces the World applied to it
// since (gravity, contacts with other bodies): M dV/dt minus the forces that were accumulated.
struct BodyMemory {
  BodyId body;
  uint64_t step = 0;  // World::stepCount() at that update
  double time = 0.0;
  Vec3 v = Vec3::Zero(), w = Vec3::Zero();
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();  // accumulated after our forces
};

struct Attachment {
  BodyId body;
  uint32_t hand = 0;
  Transform bodyInPalm;
};

Vec3 angularVelocityBetween(const Quat& from, const Quat& to, double dt) {
  Quat d = to * from.conjugate();
  if (d.w() < 0.0) d.coeffs() = -d.coeffs();
  const Eigen::AngleAxisd aa(d.normalized());
  return (aa.angle() / dt) * aa.axis();
}

double maxBoneJump(const HandPose& a, const HandPose& b) {
  double m = 0.0;
  for (int i = 0; i < kBonesPerHand; ++i) m = std::max(m, (a.bones[i].p - b.bones[i].p).norm());
  return m;
}

// Where along a capsule bone's axis (-halfHeight..halfHeight) the middle of its deepest part
// is: `samples` axis points, the middle of those within `band` of the deepest. With `sameFace`
// only points whose nearest surface faces the way the deepest one's does (within 5 degrees)
// count: not a neighbouring facet of a prism, nor past an edge; and the two ends of that part
// are then found by bisection between samples, so that the middle does not move in steps of
// the sample spacing (half a step off the middle, a 5 N pinch already twists a light block).
// NaN if no distance is finite.
double middleOfDeepest(const World& w, BodyId body, const Shape& bone, const Transform& pose,
                       int samples, double band, bool sameFace = false) {
  constexpr int kMaxAxisSamples = 17;
  const Vec3 axis = pose.rotate(Vec3::UnitY());
  // Without `sameFace` only distances are needed: a body with a distance field answers them from
  // the field, without the Newton projection and the normal of closestPoint (the same number:
  // closestPoint's distance is the field's). It was most of axe_tower's time.
  const SignedDistanceField* field = sameFace ? nullptr : w.shape(body).sdf();
  const Transform bodyPose = w.pose(body);
  std::array<double, kMaxAxisSamples> sep{}, along{};
  std::array<Vec3, kMaxAxisSamples> normal;
  normal.fill(Vec3::Zero());
  int deepest = -1;
  for (int k = 0; k < samples; ++k) {
    along[k] = bone.halfHeight() * (2.0 * k / (samples - 1) - 1.0);
    const Vec3 x = pose.p + along[k] * axis;
    if (field) {
      sep[k] = field->distance(bodyPose.applyInverse(x)) - bone.radius();
    } else {
      const SurfacePoint sp = w.closestPoint(body, x);
      sep[k] = sp.distance - bone.radius();
      normal[k] = sp.normal;
    }
    if (std::isfinite(sep[k]) && (deepest < 0 || sep[k] < sep[deepest])) deepest = k;
  }
  if (deepest < 0) return std::numeric_limits<double>::quiet_NaN();
  const double minAgreement = std::cos(5.0 * kPi / 180.0);
  const double limit = sep[deepest] + band;
  if (!sameFace) {
    double y = 0.0;
    int count = 0;
    for (int k = 0; k < samples; ++k) {
      if (sep[k] <= limit) y += along[k], ++count;
    }
    return y / count;
  }
  auto counts = [&](double s, const Vec3& n) {
    return s <= limit && n.dot(normal[deepest]) >= minAgreement;
  };
  auto countsAt = [&](double y) {
    const SurfacePoint sp = w.closestPoint(body, pose.p + y * axis);
    return counts(sp.distance - bone.radius(), sp.normal);
  };
  int lo = deepest, hi = deepest;
  while (lo > 0 && counts(sep[lo - 1], normal[lo - 1])) --lo;
  while (hi + 1 < samples && counts(sep[hi + 1], normal[hi + 1])) ++hi;
  // Each end lies between its last counting sample and the next one: 8 halvings.
  auto bisect = [&](double in, double out) {
    for (int i = 0; i < 8; ++i) {
      const double mid = 0.5 * (in + out);
      (countsAt(mid) ? in : out) = mid;
    }
    return in;
  };
  const double yLo = lo > 0 ? bisect(along[lo], along[lo - 1]) : along[lo];
  const double yHi = hi + 1 < samples ? bisect(along[hi], along[hi + 1]) : along[hi];
  return 0.5 * (yLo + yHi);
}

}  // namespace

struct Interaction::Impl {
  InteractionDef def;
  std::vector<Hand> hands;
  std::vector<Contact> contacts;  // sorted by (body, hand, bone) after each update
  std::vector<std::pair<BodyId, BodyInteractionDef>> overrides;  // sorted by body
  std::vector<Attachment> attachments;
  std::vector<BodyMemory> memory, nextMemory;  // sorted by body
  double springEnergy = 0.0;
  int slippingSamples = 0;
  std::vector<HandContactEvent> beginEvents, endEvents;
  std::vector<std::pair<BodyId, Vec3>> applied;  // per touched body, sorted
  InteractionStats stats;
  std::vector<BodyId> nearBodies;  // scratch (keepPressingContact)
  std::array<int, kBonesPerHand> boneContact{};
  // Scratch, reused every update so the hot path does not allocate.
  std::vector<OverlapHit> hits;
  std::vector<SpringPoint> springs;
  std::vector<ConeResult> cone;
  std::vector<Vec3> forceBatch, pointBatch;  // one addForcesAtPositions call per body

  const Hand& hand(HandId id, const char* field) const {
    if (id.index >= hands.size() || !hands[id.index].alive ||
        hands[id.index].generation != id.generation) {
      throw Error(field, "unknown or removed hand id");
    }
    return hands[id.index];
  }
  Hand& hand(HandId id, const char* field) {
    return const_cast<Hand&>(static_cast<const Impl*>(this)->hand(id, field));
  }
  HandId idOf(uint32_t slot) const { return HandId{slot, hands[slot].generation}; }

  // ---- per-body parameters ----
  const BodyInteractionDef* overrideFor(BodyId b) const {
    auto it = std::lower_bound(overrides.begin(), overrides.end(), b,
                               [](const auto& e, BodyId k) { return e.first < k; });
    return it != overrides.end() && it->first == b ? &it->second : nullptr;
  }
  double gammaFor(const World& w, BodyId b) const {
    const BodyInteractionDef* o = overrideFor(b);
    if (o && o->gamma > 0.0) return o->gamma;
    if (o && o->autoGamma) {
      const double g = w.gravity().norm();
      const double d = w.shape(b).localBounds().extent().norm();
      if (g > 0.0 && d > 0.0) return autoTuneGamma(w.mass(b), g, muStatic(b), d);
    }
    return def.gamma;
  }
  double muStatic(BodyId b) const {
    const BodyInteractionDef* o = overrideFor(b);
    return o && o->staticFriction > 0.0 ? o->staticFriction : def.skin.staticFriction;
  }
  double muDynamic(BodyId b) const {
    const BodyInteractionDef* o = overrideFor(b);
    return o && o->dynamicFriction > 0.0 ? o->dynamicFriction : def.skin.dynamicFriction;
  }
  bool useClosestPoint(const World& w, BodyId b) const {
    if (def.contactPoint == ContactPointMethod::ClosestPoint) return true;
    if (def.contactPoint == ContactPointMethod::RayCast) return false;
    return w.shape(b).sdf() != nullptr;
  }

  HandContactEvent eventOf(const Contact& c) const {
    return {idOf(c.hand), c.bone, c.body, c.point, c.normal};
  }
  void endContact(const Contact& c) { endEvents.push_back(eventOf(c)); }

  // ---- the stages ----
  void takeFrames(double dt);
  Transform sweptBonePose(const World& w, const Hand& h, int bone, double reach) const;
  void dropDeadContacts(const World& w);
  void findContacts(const World& w);
  bool keepPressingContact(const World& w, uint32_t hand, int bone, double reach);
  void centreOnContactLine(const World& w, BodyId body, const Shape& bone, const Transform& pose,
                           const Vec3& normal, Vec3& point) const;
  void refineOnDistanceField(const World& w, BodyId body, const Shape& bone, const Transform& pose,
                             Vec3& point, double& separation, Vec3& normal) const;
  void placeContactPoints(const World& w);
  void applyFrictionForces(World& w, double dt);
  void updateAttachments(World& w);
  void updateVisualHands(const World& w);
  void updateStats();

  bool placePoint(const World& w, const Contact& c, Vec3& point, Vec3& normal) const;
  void anchor(const World& w, Contact& c, const Vec3& point, const Vec3& normal);
  void slideSample(const World& w, const Transform& body, Contact& c, Sample& s, const Vec3& shift,
                   double offset);
  double gripForce(const World& w, uint32_t hand, BodyId body, bool& opposing) const;
  void externalForces(const World& w, BodyId body, RigidBodyState& s) const;
  Twist solveSpringForces(const RigidBodyState& state, double muS, double muD, double dt);
};

// Tracking frames become the poses this update uses. A hand without a new frame keeps its last
// pose for the grace period, then lets go.
void Interaction::Impl::takeFrames(double dt) {
  for (Hand& h : hands) {
    if (!h.alive) continue;
    if (h.hasPending) {
      h.previous = h.tracked;
      h.hasPrevious = h.active;
      h.tracked = h.pending;
      h.hasPending = false;
      h.active = true;
      h.sinceFrame = 0.0;
      const Transform& palm = h.tracked.bones[kPalmBone];
      if (h.hasPreviousPalm) {
        h.palmVelocity = (palm.p - h.previousPalm.p) / dt;
        h.palmAngularVelocity = angularVelocityBetween(h.previousPalm.q, palm.q, dt);
      }
      h.previousPalm = palm;
      h.hasPreviousPalm = true;
    } else if (h.active) {
      h.sinceFrame += dt;
      if (h.sinceFrame > def.trackingGrace) {
        h.active = false;
        h.release = true;
        h.hasPrevious = false;
        h.hasPreviousPalm = false;
        h.palmVelocity = h.palmAngularVelocity = Vec3::Zero();
      }
    }
  }
}

// Contacts of released hands and of destroyed or no longer dynamic bodies end here.
void Interaction::Impl::dropDeadContacts(const World& w) {
  auto dead = [&](const Contact& c) {
    const Hand& h = hands[c.hand];
    return !h.alive || h.release || !w.isValid(c.body) || w.bodyType(c.body) != BodyType::Dynamic;
  };
  for (const Contact& c : contacts) {
    if (dead(c)) endContact(c);
  }
  std::erase_if(contacts, dead);
  std::erase_if(attachments, [&](const Attachment& a) {
    return !hands[a.hand].alive || hands[a.hand].release || !w.isValid(a.body);
  });
  for (Hand& h : hands) h.release = false;
}

// A bone that moved farther than the contact reach since the last frame could have passed
// through a thin body between the two frames. The bone's shape swept along its path (at its
// last orientation) finds the first body its surface would meet; the bone is then tested at
// the pose just before it, so the contact begins there and its spring to the bone's pose
// pushes the body instead of the bone passing through. One shape cast per fast free bone;
// bones that moved less are tested where they are.
Transform Interaction::Impl::sweptBonePose(const World& w, const Hand& h, int bone,
                                           double reach) const {
  const Transform& to = h.tracked.bones[bone];
  if (!h.hasPrevious) return to;
  const Transform& from = h.previous.bones[bone];
  const Vec3 path = to.p - from.p;
  const double travel = path.norm();
  // Beyond the teleport distance the frame is a jump, not a motion (and it releases anyway).
  if (travel <= reach || !(travel <= def.teleportDistance)) return to;
  const std::optional<WorldRayHit> hit =
      w.shapeCast(*h.shapes.bones[bone], from, path / travel, travel, def.touchable);
  if (!hit || w.bodyType(hit->body) != BodyType::Dynamic) return to;
  const double t = std::max(0.0, (hit->hit.distance - 0.5 * def.contactOffset) / travel);
  if (t >= 1.0) return to;
  return Transform{from.p + t * path, from.q.slerp(t, to.q)};
}

// Bone-versus-body proximity with the World's overlap query: a contact begins within the
// contact offset and ends beyond contactOffset + releaseMargin (hysteresis, so that a finger
// resting on a surface does not flicker).
void Interaction::Impl::findContacts(const World& w) {
  for (Contact& c : contacts) c.seen = false;
  const double reach = def.contactOffset + def.releaseMargin;
  for (uint32_t hi = 0; hi < hands.size(); ++hi) {
    const Hand& h = hands[hi];
    if (!h.alive || !h.active) continue;
    // The contact of each bone of this hand (-1: none, -2: several bodies).
    boneContact.fill(-1);
    for (size_t i = 0; i < contacts.size(); ++i) {
      if (contacts[i].hand != hi) continue;
      int& slot = boneContact[contacts[i].bone];
      slot = slot == -1 ? static_cast<int>(i) : -2;
    }
    for (int bone = 0; bone < kBonesPerHand; ++bone) {
      if (keepPressingContact(w, hi, bone, reach)) continue;
      hits.clear();
      // A bone pressing a body is tested where it is; a free or merely touching one is swept.
      const bool pressing = boneContact[bone] >= 0 && contacts[boneContact[bone]].anchored;
      const Transform pose = boneContact[bone] == -2 || pressing ? h.tracked.bones[bone]
                                                                 : sweptBonePose(w, h, bone, reach);
      w.overlap(*h.shapes.bones[bone], pose, reach, hits, def.touchable);
      for (size_t i = 0; i < hits.size(); ++i) {
        const BodyId body = hits[i].body;
        if (w.bodyType(body) != BodyType::Dynamic) continue;
        // Hits come ordered by body; one contact per (bone, body): its deepest point.
        const Manifold* best = nullptr;
        const ContactPoint* bestPoint = nullptr;
        for (; i < hits.size() && hits[i].body == body; ++i) {
          const Manifold& m = hits[i].manifold;
          for (int k = 0; k < m.pointCount; ++k) {
            if (!bestPoint || m.points[k].separation < bestPoint->separation) {
              best = &m;
              bestPoint = &m.points[k];
            }
          }
        }
        --i;
        if (!bestPoint) continue;
        // A bone lying along a face touches it along a line: take the middle of the points
        // about as deep as the deepest, not one end.
        Vec3 nearPoint = Vec3::Zero();
        int nearCount = 0;
        for (int k = 0; k < best->pointCount; ++k) {
          if (best->points[k].separation <= bestPoint->separation + 1e-3) {
            nearPoint += best->points[k].position;
            ++nearCount;
          }
        }
        nearPoint /= nearCount;
        double separation = bestPoint->separation;
        Vec3 normal = best->normal;
        if (useClosestPoint(w, body)) {
          refineOnDistanceField(w, body, *h.shapes.bones[bone], pose, nearPoint, separation,
                                normal);
        } else if (nearCount == 1) {
          centreOnContactLine(w, body, *h.shapes.bones[bone], pose, normal, nearPoint);
        }
        auto it = std::find_if(contacts.begin(), contacts.end(), [&](const Contact& c) {
          return c.hand == hi && c.bone == bone && c.body == body;
        });
        if (it == contacts.end()) {
          if (separation > def.contactOffset) continue;
          Contact c;
          c.hand = hi;
          c.bone = bone;
          c.body = body;
          c.passive = separation < -def.resumeDepth;
          contacts.push_back(c);
          it = contacts.end() - 1;
          it->fresh = true;
          it->point = nearPoint + 0.5 * separation * normal;
          it->normal = -normal;
        }
        it->seen = true;
        if (!it->anchored) {
          it->swept = pose.p != h.tracked.bones[bone].p;
          it->touchPose = pose;
        }
        it->child = best->childB;
        it->separation = separation;
        it->contactNormal = normal;
        it->bonePoint = nearPoint - 0.5 * separation * normal;
      }
    }
  }
  for (const Contact& c : contacts) {
    if (!c.seen) endContact(c);
  }
  std::erase_if(contacts, [](const Contact& c) { return !c.seen; });
}

// On a body with a signed-distance field the nearest pair comes from the field, not from the
// compound of boxes the narrowphase saw: a finger lying across a thin part (a mug's 9 mm handle,
// a few voxel boxes thick) meets box corners at both ends of the overlap, and their middle or
// their deepest point can sit off the part's centre line, where the closest surface point is on
// its side. The capsule axis is sampled for its point nearest the surface. `point` becomes the
// midpoint of the pair, `normal` points from the bone into the body (as a manifold's).
void Interaction::Impl::refineOnDistanceField(const World& w, BodyId body, const Shape& bone,
                                              const Transform& pose, Vec3& point,
                                              double& separation, Vec3& normal) const {
  if (bone.type() != ShapeType::Capsule) return;
  // A bone lying along a face is about equally deep along its length: take the middle of the
  // samples within 0.1 mm of the deepest, as for the manifold points.
  const double y = middleOfDeepest(w, body, bone, pose, 9, 1e-4);
  if (!std::isfinite(y)) return;
  const Vec3 x = pose.p + y * pose.rotate(Vec3::UnitY());
  const SurfacePoint sp = w.closestPoint(body, x);
  if (!std::isfinite(sp.distance) || !isFinite(sp.normal)) return;
  // The bone's surface point toward the body (x - r n, also right when x is inside) and the
  // body's surface point; their midpoint, as a manifold point's position.
  point = 0.5 * (x - bone.radius() * sp.normal + sp.point);
  separation = sp.distance - bone.radius();
  normal = -sp.normal;
}

// The narrowphase reports a capsule lying (nearly) flat on a face by the ends of the line of
// contact (two clipped points), or, on a hull face it overhangs, by a single point, GJK's
// closest pair: often its end on the face's edge (a fingertip along a Jenga block's 15 mm
// face). A patch anchored at an end, as it once was, left the two fingertips of a pinch on opposite
// edges and their normal forces, 1.7 N each 15 mm apart, rolled the block out of the grasp. The
// middle of the line is found by sampling the axis: the samples over the same face (a neighbouring
// facet of a prism or an edge is not the line) within 1 mm of the deepest, the tolerance used for
// manifold points. A bone touching with its end (tilted more than ~6 degrees to the face) keeps the
// point.
void Interaction::Impl::centreOnContactLine(const World& w, BodyId body, const Shape& bone,
                                            const Transform& pose, const Vec3& normal,
                                            Vec3& point) const {
  if (bone.type() != ShapeType::Capsule) return;
  const Vec3 axis = pose.rotate(Vec3::UnitY());
  if (std::abs(axis.dot(normal)) > 0.1) return;
  const double y = middleOfDeepest(w, body, bone, pose, 17, 1e-3, true);
  if (std::isfinite(y)) point += (y - axis.dot(point - pose.p)) * axis;
}

// A bone pressing into a body, with no other dynamic body's bounds near it, needs no overlap
// query this step: it is inside the body it presses (the patch lets go when the press turns
// tensile, and the next query then decides whether the contact ends). The narrowphase query is
// most of the cost of a firm grasp; this skips it exactly when it cannot find anything new
// (the bodies near the bone from the world's query tree: walking every body's bounds here cost
// more than the query it saved in a room of objects).
bool Interaction::Impl::keepPressingContact(const World& w, uint32_t hand, int bone, double reach) {
  const int index = boneContact[bone];
  if (index < 0) return false;  // none, or contacts with several bodies
  Contact& c = contacts[index];
  if (!c.anchored || c.passive) return false;
  const Hand& h = hands[hand];
  const Aabb box = h.shapes.bones[bone]->bounds(h.tracked.bones[bone]).inflated(reach);
  w.queryBounds(box, nearBodies, def.touchable);  // (what the overlap query could find)
  for (BodyId b : nearBodies)
    if (b != c.body && w.bodyType(b) == BodyType::Dynamic) return false;
  c.seen = true;
  return true;
}

// The thesis's contact point (3.5.2, 3.7): a ray from the bone's near point toward the centre
// of the touched sub-shape, its first hit is C. The ray starts backed out of the body along the
// contact normal so that it also works when the bone is already inside. With an SDF (or when
// chosen) the closest surface point is used instead.
bool Interaction::Impl::placePoint(const World& w, const Contact& c, Vec3& point,
                                   Vec3& normal) const {
  if (!useClosestPoint(w, c.body)) {
    // Start just outside the surface: a longer back-off would tilt the ray and shift C
    // tangentially (by lateral offset * back-off / distance to the centre).
    const Vec3 origin =
        c.bonePoint - (std::max(0.0, -c.separation) + kRayBackoff) * c.contactNormal;
    const Vec3 centre = childCenter(w.shape(c.body), w.pose(c.body), c.child);
    const Vec3 toCentre = centre - origin;
    const double len = toCentre.norm();
    if (len > 1e-9) {
      const auto hit =
          w.rayCastBody(c.body, origin, toCentre / len, len, static_cast<int>(c.child));
      if (hit && hit->distance > 0.0) {
        point = hit->point;
        normal = hit->normal;
        return true;
      }
    }
  }
  const SurfacePoint sp = w.closestPoint(c.body, c.bonePoint);
  point = sp.point;
  normal = sp.normal;
  return isFinite(point) && isFinite(normal);
}

// Fixes the patch on the body (3.5.4): samples around C in its tangent plane, the matching
// targets on the bone at the same offsets from the bone's near point.
void Interaction::Impl::anchor(const World& w, Contact& c, const Vec3& point, const Vec3& normal) {
  const Transform body = w.pose(c.body);
  // A swept contact is fixed where the bone first touched, so its springs reach from there to
  // the bone's pose now and push the body along the bone's path.
  const Transform& bone = c.swept ? c.touchPose : hands[c.hand].tracked.bones[c.bone];
  Vec3 t1, t2;
  tangentBasis(normal, t1, t2);
  const double radius = c.bone == kPalmBone    ? def.palmPatchRadius
                        : hasWidePatch(c.bone) ? def.widePatchRadius
                                               : def.patchRadius;
  const int n = def.patchSamples;
  c.sampleCount = n;
  for (int k = 0; k < n; ++k) {
    Vec3 offset = Vec3::Zero();
    if (k > 0) {
      const double a = 2.0 * kPi * (k - 1) / (n - 1);
      offset = radius * (std::cos(a) * t1 + std::sin(a) * t2);
    }
    c.samples[k].cLocal = body.applyInverse(point + offset);
    c.samples[k].nLocal = body.rotateInverse(normal);
    c.samples[k].pBone = bone.applyInverse(c.bonePoint + offset);
  }
  c.anchored = true;
  c.boneInBody = body.inverse() * bone;
}

void Interaction::Impl::placeContactPoints(const World& w) {
  for (Contact& c : contacts) {
    if (c.passive && c.separation >= -def.contactOffset) c.passive = false;  // surfaced
    if (c.anchored) continue;
    Vec3 point, normal;
    const bool placed = placePoint(w, c, point, normal);
    if (placed) {
      c.point = point;
      c.normal = normal;
    }
    if (c.fresh) beginEvents.push_back(eventOf(c));
    c.fresh = false;
    if (!placed) continue;
    const double depth = -(c.bonePoint - point).dot(normal);
    if (c.swept && !c.passive) {
      anchor(w, c, point, normal);
    } else if (depth > 0.0 && !c.passive) {
      // Anchor straight above the bone's point on the face the ray found: the ray's tilt toward
      // the sub-shape centre is an artifact of where it started, and the tangential stretch it
      // leaves would make the patch slip (or, in many-contact grasps, kick) at the first step.
      anchor(w, c, c.bonePoint + depth * normal, normal);
    }
  }
}

// Surface update (3.5.3, 3.7) for a slipping sample: shift C along the surface so that the
// stretch sits on the kinetic cone, then put it back on the surface by the inverse ray cast
// (from outside, along -n) or the closest point; keep the new point only where the normal
// agrees with the old one.
void Interaction::Impl::slideSample(const World& w, const Transform& body, Contact& c, Sample& s,
                                    const Vec3& shift, double offset) {
  const Vec3 n = body.rotate(s.nLocal);
  const Vec3 moved = body.apply(s.cLocal) + shift;
  Vec3 point, normal;
  if (useClosestPoint(w, c.body)) {
    const SurfacePoint sp = w.closestPoint(c.body, moved);
    point = sp.point;
    normal = sp.normal;
  } else {
    const auto hit = w.rayCastBody(c.body, moved + offset * n, -n, 2.0 * offset);
    if (!hit) return;
    point = hit->point;
    normal = hit->normal;
  }
  if (!isFinite(point) || normal.dot(n) < kNormalAgreement) return;
  s.cLocal = body.applyInverse(point);
  s.nLocal = body.rotateInverse(normal);
}

// The forces of all springs on one body: the implicit solve with the friction cone inside it
// (eqs. 3.5-3.8 decide per sample whether it sticks, slips or lets go, and the solve uses each
// sample's law), or the explicit springs followed by the cone. Returns the body's velocity the
// forces were solved with (zero for the explicit springs: they act on the stretch as it is).
Twist Interaction::Impl::solveSpringForces(const RigidBodyState& state, double muS, double muD,
                                           double dt) {
  const size_t n = springs.size();
  cone.resize(n);
  if (def.integration == SpringIntegration::Implicit)
    return implicitConeForces(state, springs, muS, muD, def.slipLaw, dt, cone).velocity;
  for (size_t j = 0; j < n; ++j) {
    const SpringPoint& sp = springs[j];
    cone[j] =
        frictionCone(sp.stiffness * (sp.target - sp.anchor), sp.normal, muS, muD, def.slipLaw);
  }
  return Twist::Zero();
}

// The force law, body by body: the implicit spring of every pressing sample on the body with
// the friction cone inside the solve, then the forces at their points in a fixed order.
void Interaction::Impl::applyFrictionForces(World& w, double dt) {
  for (size_t first = 0; first < contacts.size();) {
    const BodyId bodyId = contacts[first].body;
    size_t last = first;
    while (last < contacts.size() && contacts[last].body == bodyId) ++last;

    const Transform body = w.pose(bodyId);
    const Mat3 bodyR = body.q.toRotationMatrix();  // one matrix for all the body's samples
    springs.clear();
    const double gamma = gammaFor(w, bodyId);
    for (size_t i = first; i < last; ++i) {
      Contact& c = contacts[i];
      c.force.setZero();
      c.slipping = false;
      if (!c.anchored || c.passive) continue;
      const Transform& bone = hands[c.hand].tracked.bones[c.bone];
      const Mat3 boneR = bone.q.toRotationMatrix();
      const double k = gamma / c.sampleCount;
      for (int s = 0; s < c.sampleCount; ++s) {
        const Sample& sm = c.samples[s];
        springs.push_back(
            {bodyR * sm.cLocal + body.p, boneR * sm.pBone + bone.p, k, bodyR * sm.nLocal});
      }
    }
    if (springs.empty()) {
      first = last;
      continue;
    }
    RigidBodyState state;
    state.mass = w.mass(bodyId);
    state.inertiaWorld = w.inertiaWorld(bodyId);
    state.com = w.centerOfMass(bodyId);
    state.linearVelocity = w.linearVelocity(bodyId);
    state.angularVelocity = w.angularVelocity(bodyId);
    externalForces(w, bodyId, state);
    const Twist solved = solveSpringForces(state, muStatic(bodyId), muDynamic(bodyId), dt);
    const double muD = muDynamic(bodyId);

    Vec3 total = Vec3::Zero();
    forceBatch.clear();
    pointBatch.clear();
    size_t j = 0;
    for (size_t i = first; i < last; ++i) {
      Contact& c = contacts[i];
      if (!c.anchored || c.passive) continue;
      double depth = 0.0;
      for (int si = 0; si < c.sampleCount; ++si, ++j) {
        const SpringPoint& sp = springs[j];
        Sample& s = c.samples[si];
        const Vec3& n = sp.normal;
        const Vec3 stretch = sp.target - sp.anchor;
        const double along = stretch.dot(n);
        depth -= along;
        if (along < 0.0) springEnergy += 0.5 * sp.stiffness * stretch.squaredNorm();
        const ConeResult& r = cone[j];
        if (!r.compressive) continue;
        forceBatch.push_back(r.force);
        pointBatch.push_back(sp.anchor);
        c.force += r.force;
        if (r.slipping) {
          c.slipping = true;
          ++slippingSamples;
          // The shift puts the stretch the cone judged, the one at the end of the step (the
          // body moved by h V+), on the kinetic cone. Shifting the start-of-step stretch left
          // the next step's spring short of the kinetic force by the body's travel: a lifted
          // cube then slid at a force averaging m g and never caught up with the fingers.
          if (def.surfaceUpdates) {
            const Vec3 arm = sp.anchor - state.com;
            const Vec3 travel = dt * (solved.head<3>() + solved.tail<3>().cross(arm));
            slideSample(w, body, c, s, slipShift(stretch - travel, n, muD), def.contactOffset);
          }
        }
      }
      total += c.force;
      // No adhesion: once the bone has left the surface the patch lets go, and the point is
      // estimated afresh if the bone presses again.
      if (depth <= 0.0) c.anchored = false;
      c.point = body.apply(c.samples[0].cLocal);
      c.normal = body.rotate(c.samples[0].nLocal);
    }
    // Sample by sample in the fixed order, as addForceAtPosition would (bit for bit).
    w.addForcesAtPositions(bodyId, forceBatch, pointBatch, ForceMode::Force);
    applied.emplace_back(bodyId, total);
    nextMemory.push_back({bodyId, w.stepCount(), w.time(), state.linearVelocity,
                          state.angularVelocity, w.accumulatedForce(bodyId),
                          w.accumulatedTorque(bodyId)});
    first = last;
  }
  std::swap(memory, nextMemory);
  nextMemory.clear();
}

// The known forces on a body for this step, besides the hand springs. Gravity and what the host
// added so far; with observedExternalForce, also what the World's own contacts did to the body
// over the last step, measured as M dV/dt minus the forces that were accumulated then. Without
// that, a body resting on a floor would be predicted to fall through it and the implicit spring
// would push more softly than gamma * depth; with it the force is exact whenever the body is at
// rest, on a floor or in the air.
void Interaction::Impl::externalForces(const World& w, BodyId body, RigidBodyState& s) const {
  s.externalForce = s.mass * w.gravity() + w.accumulatedForce(body);
  s.externalTorque = w.accumulatedTorque(body);
  if (!def.observedExternalForce) return;
  auto it = std::lower_bound(memory.begin(), memory.end(), body,
                             [](const BodyMemory& m, BodyId k) { return m.body < k; });
  if (it == memory.end() || it->body != body || w.stepCount() != it->step + 1) return;
  const double h = w.time() - it->time;
  if (!(h > 0.0)) return;
  s.externalForce = s.mass * (s.linearVelocity - it->v) / h - it->force + w.accumulatedForce(body);
  s.externalTorque =
      s.inertiaWorld * (s.angularVelocity - it->w) / h - it->torque + w.accumulatedTorque(body);
}

// Normal grip of one hand on one body (sum of the elastic normal spring forces), and whether
// two of its pressing patches face each other (a grasp, not a push).
double Interaction::Impl::gripForce(const World& w, uint32_t hand, BodyId bodyId,
                                    bool& opposing) const {
  const Transform body = w.pose(bodyId);
  const double gamma = gammaFor(w, bodyId);
  double grip = 0.0;
  opposing = false;
  const Hand& h = hands[hand];
  for (const Contact& a : contacts) {
    if (a.hand != hand || a.body != bodyId || !a.anchored || a.passive) continue;
    const Vec3 n = body.rotate(a.samples[0].nLocal);
    const Vec3 stretch =
        h.tracked.bones[a.bone].apply(a.samples[0].pBone) - body.apply(a.samples[0].cLocal);
    grip += std::max(0.0, -gamma * stretch.dot(n));
    for (const Contact& b : contacts) {
      if (b.hand == hand && b.body == bodyId && b.anchored && !b.passive &&
          n.dot(body.rotate(b.samples[0].nLocal)) < -0.5) {
        opposing = true;
      }
    }
  }
  return grip;
}

// The kinematic baseline (3.9): M_object = M_object^hand * M_hand while the grip holds.
void Interaction::Impl::updateAttachments(World& w) {
  // Release grips that opened (half the attach force: hysteresis).
  std::erase_if(attachments, [&](const Attachment& a) {
    bool opposing = false;
    const double grip = gripForce(w, a.hand, a.body, opposing);
    return !opposing || grip < 0.5 * def.kinematicGripForce;
  });
  // New grips.
  for (const Contact& c : contacts) {
    const bool attached = std::any_of(attachments.begin(), attachments.end(),
                                      [&](const Attachment& a) { return a.body == c.body; });
    if (attached || !c.anchored) continue;
    bool opposing = false;
    if (gripForce(w, c.hand, c.body, opposing) >= def.kinematicGripForce && opposing) {
      const Transform palm = hands[c.hand].tracked.bones[kPalmBone];
      attachments.push_back({c.body, c.hand, palm.inverse() * w.pose(c.body)});
    }
  }
  // Attached bodies follow the palm exactly; their velocity is the hand's, so that a release
  // leaves them moving with it, and gravity is cancelled while held.
  for (const Attachment& a : attachments) {
    const Hand& h = hands[a.hand];
    const Transform target = h.tracked.bones[kPalmBone] * a.bodyInPalm;
    w.setPose(a.body, target.p, target.q);
    const Vec3 r = w.centerOfMass(a.body) - h.tracked.bones[kPalmBone].p;
    w.setLinearVelocity(a.body, h.palmVelocity + h.palmAngularVelocity.cross(r));
    w.setAngularVelocity(a.body, h.palmAngularVelocity);
    w.addForce(a.body, -w.gravity(), ForceMode::Acceleration);
  }
}

// The visual hand (3.6): a bone pressing on a body is drawn where it was at contact time,
// carried along by the body; free bones follow tracking.
void Interaction::Impl::updateVisualHands(const World& w) {
  for (Hand& h : hands) {
    if (h.alive) h.visual = h.tracked;
  }
  for (const Contact& c : contacts) {
    if (!c.anchored || c.passive) continue;
    Hand& h = hands[c.hand];
    const Transform drawn = w.pose(c.body) * c.boneInBody;
    if (h.visual.bones[c.bone].p == h.tracked.bones[c.bone].p) h.visual.bones[c.bone] = drawn;
  }
}

void Interaction::Impl::updateStats() {
  const int dropped = stats.droppedFrames;
  stats = InteractionStats{};
  stats.droppedFrames = dropped;
  for (const Hand& h : hands) stats.trackedHands += h.alive && h.active;
  stats.contacts = static_cast<int>(contacts.size());
  for (const Contact& c : contacts) {
    if (c.anchored && !c.passive) {
      ++stats.pressingContacts;
      stats.samples += c.sampleCount;
    }
  }
  stats.touchedBodies = static_cast<int>(applied.size());
  stats.attachedBodies = static_cast<int>(attachments.size());
  stats.springEnergy = springEnergy;
  stats.slippingSamples = slippingSamples;
}

// ---- public API ---------------------------------------------------------------------------

Interaction::Interaction(const InteractionDef& def) : impl_(std::make_unique<Impl>()) {
  requirePositive(def.gamma, "InteractionDef.gamma");
  requirePositive(def.contactOffset, "InteractionDef.contactOffset");
  requireNonNegative(def.releaseMargin, "InteractionDef.releaseMargin");
  if (def.patchSamples != 1 && def.patchSamples != 5 && def.patchSamples != 9) {
    throw Error("InteractionDef.patchSamples", "must be 1, 5 or 9");
  }
  requirePositive(def.patchRadius, "InteractionDef.patchRadius");
  requirePositive(def.widePatchRadius, "InteractionDef.widePatchRadius");
  requirePositive(def.palmPatchRadius, "InteractionDef.palmPatchRadius");
  requirePositive(def.skin.staticFriction, "InteractionDef.skin.staticFriction");
  requireNonNegative(def.skin.dynamicFriction, "InteractionDef.skin.dynamicFriction");
  if (def.skin.dynamicFriction > def.skin.staticFriction) {
    throw Error("InteractionDef.skin.dynamicFriction", "must not exceed staticFriction");
  }
  requirePositive(def.resumeDepth, "InteractionDef.resumeDepth");
  requireNonNegative(def.trackingGrace, "InteractionDef.trackingGrace");
  requirePositive(def.teleportDistance, "InteractionDef.teleportDistance");
  requirePositive(def.kinematicGripForce, "InteractionDef.kinematicGripForce");
  impl_->def = def;
}

Interaction::~Interaction() = default;

HandId Interaction::addHand(const HandDef& def) {
  HandShapes shapes = makeHandShapes(def);  // validates
  uint32_t slot = 0;
  while (slot < impl_->hands.size() && impl_->hands[slot].alive) ++slot;
  if (slot == impl_->hands.size()) impl_->hands.emplace_back();
  Hand& h = impl_->hands[slot];
  const uint32_t generation = h.generation + 1;
  h = Hand{};
  h.generation = generation;
  h.alive = true;
  h.def = def;
  h.shapes = std::move(shapes);
  return HandId{slot, generation};
}

void Interaction::removeHand(HandId id) {
  Hand& h = impl_->hand(id, "HandId");
  h.alive = false;  // its contacts end at the next update (dropDeadContacts)
}

bool Interaction::isValid(HandId id) const {
  return id.index < impl_->hands.size() && impl_->hands[id.index].alive &&
         impl_->hands[id.index].generation == id.generation;
}

std::vector<HandId> Interaction::hands() const {
  std::vector<HandId> out;
  for (uint32_t i = 0; i < impl_->hands.size(); ++i) {
    if (impl_->hands[i].alive) out.push_back(impl_->idOf(i));
  }
  return out;
}

FrameStatus Interaction::setHandPose(HandId id, const HandPose& pose) {
  Hand& h = impl_->hand(id, "HandId");
  if (!pose.tracked) return FrameStatus::NotTracked;
  if (!isFinite(pose)) {
    ++impl_->stats.droppedFrames;
    return FrameStatus::RejectedNonFinite;
  }
  // A finite quaternion can still be useless: zero, or so large or small that its norm
  // overflows or vanishes. Such a frame is dropped like a non-finite one.
  for (const Transform& t : pose.bones) {
    const double n = t.q.norm();
    if (!(n > 1e-6 && n < 1e6)) {
      ++impl_->stats.droppedFrames;
      return FrameStatus::RejectedNonFinite;
    }
  }
  HandPose p = pose;
  for (Transform& t : p.bones) t.q.normalize();
  FrameStatus status = FrameStatus::Accepted;
  if (h.active && maxBoneJump(h.tracked, p) > impl_->def.teleportDistance) {
    h.release = true;  // let go rather than yank what the hand held
    h.hasPreviousPalm = false;
    status = FrameStatus::Teleported;
  }
  h.pending = p;
  h.hasPending = true;
  return status;
}

void Interaction::setBodyOverrides(BodyId body, const BodyInteractionDef& def) {
  requireNonNegative(def.gamma, "BodyInteractionDef.gamma");
  requireNonNegative(def.staticFriction, "BodyInteractionDef.staticFriction");
  requireNonNegative(def.dynamicFriction, "BodyInteractionDef.dynamicFriction");
  if (body.isNull()) throw Error("BodyId", "null body id");
  auto& o = impl_->overrides;
  auto it = std::lower_bound(o.begin(), o.end(), body,
                             [](const auto& e, BodyId k) { return e.first < k; });
  if (it != o.end() && it->first == body) {
    it->second = def;
  } else {
    o.insert(it, {body, def});
  }
}

void Interaction::clearBodyOverrides(BodyId body) {
  std::erase_if(impl_->overrides, [&](const auto& e) { return e.first == body; });
}

void Interaction::update(World& world, double dt) {
  requirePositive(dt, "dt");
  Impl& m = *impl_;
  m.beginEvents.clear();
  m.endEvents.clear();
  m.applied.clear();
  m.springEnergy = 0.0;
  m.slippingSamples = 0;
  m.takeFrames(dt);
  m.dropDeadContacts(world);
  m.findContacts(world);
  m.placeContactPoints(world);
  if (!std::is_sorted(m.contacts.begin(), m.contacts.end(), contactLess)) {
    std::sort(m.contacts.begin(), m.contacts.end(), contactLess);
  }
  if (m.def.method == InteractionMethod::Kinematic) {
    m.updateAttachments(world);
  } else {
    m.applyFrictionForces(world, dt);
  }
  m.updateVisualHands(world);
  m.updateStats();
}

void Interaction::step(World& world, double dt) {
  update(world, dt);
  world.step(dt);
}

const std::vector<HandContactEvent>& Interaction::contactBeginEvents() const {
  return impl_->beginEvents;
}
const std::vector<HandContactEvent>& Interaction::contactEndEvents() const {
  return impl_->endEvents;
}

std::vector<HandContactInfo> Interaction::contacts() const {
  std::vector<HandContactInfo> out;
  for (const Contact& c : impl_->contacts) {
    out.push_back({impl_->idOf(c.hand), c.bone, c.body, c.point, c.normal, c.anchored && !c.passive,
                   c.slipping, c.force});
  }
  return out;
}

const HandPose& Interaction::trackedPose(HandId id) const {
  return impl_->hand(id, "HandId").tracked;
}
const HandPose& Interaction::visualPose(HandId id) const {
  return impl_->hand(id, "HandId").visual;
}
const HandDef& Interaction::handDef(HandId id) const {
  return impl_->hand(id, "HandId").def;
}

bool Interaction::isAttached(BodyId body) const {
  return std::any_of(impl_->attachments.begin(), impl_->attachments.end(),
                     [&](const Attachment& a) { return a.body == body; });
}

Vec3 Interaction::appliedForce(BodyId body) const {
  for (const auto& [b, f] : impl_->applied) {
    if (b == body) return f;
  }
  return Vec3::Zero();
}

const InteractionStats& Interaction::stats() const {
  return impl_->stats;
}
const InteractionDef& Interaction::def() const {
  return impl_->def;
}

}  // namespace grip
