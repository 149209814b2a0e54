// Ray casts and closest points. Each shape answers in its own frame; compounds walk their tree
// (ray casts) or all children (closest points).
#include "collision/query.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "collision/detail/convex.hpp"
#include "collision/sdf.hpp"
#include "core/error.hpp"

namespace grip {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct LocalHit {
  double t = 0.0;
  Vec3 normal = Vec3::Zero();  // zero: the ray starts inside (the caller uses -dir)
};

// First t >= 0 with |o + t d| = r (o outside the sphere).
bool raySphere(const Vec3& o, const Vec3& d, double r, double maxT, LocalHit& h) {
  const double b = o.dot(d), c = o.squaredNorm() - r * r;
  if (c <= 0.0) return h = {}, true;
  const double disc = b * b - c;
  if (disc < 0.0 || b > 0.0) return false;
  const double t = -b - std::sqrt(disc);
  if (t > maxT) return false;
  h = {std::max(t, 0.0), (o + t * d) / r};
  return true;
}

// Slab test against the box [-e, e].
bool rayBox(const Vec3& o, const Vec3& d, const Vec3& e, double maxT, LocalHit& h) {
  double tEnter = -kInf, tExit = kInf;
  int enterAxis = -1;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (std::abs(o[k]) > e[k]) return false;
      continue;
    }
    double t0 = (-e[k] - o[k]) / d[k], t1 = (e[k] - o[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tEnter) tEnter = t0, enterAxis = k;
    tExit = std::min(tExit, t1);
  }
  if (tEnter > tExit || tExit < 0.0 || tEnter > maxT) return false;
  if (tEnter <= 0.0) return h = {}, true;  // the origin is inside
  Vec3 n = Vec3::Zero();
  n[enterAxis] = d[enterAxis] > 0.0 ? -1.0 : 1.0;
  h = {tEnter, n};
  return true;
}

// Capsule along y: the side cylinder, then the two end spheres.
bool rayCapsule(const Vec3& o, const Vec3& d, double r, double hh, double maxT, LocalHit& h) {
  const Vec3 onAxis(0.0, std::clamp(o.y(), -hh, hh), 0.0);
  if ((o - onAxis).squaredNorm() <= r * r) return h = {}, true;
  bool hit = false;
  // Infinite cylinder x^2 + z^2 = r^2.
  const double a = d.x() * d.x() + d.z() * d.z();
  if (a > 0.0) {
    const double b = o.x() * d.x() + o.z() * d.z();
    const double c = o.x() * o.x() + o.z() * o.z() - r * r;
    const double disc = b * b - a * c;
    if (disc >= 0.0) {
      const double t = (-b - std::sqrt(disc)) / a;
      const double y = o.y() + t * d.y();
      if (t >= 0.0 && t <= maxT && std::abs(y) <= hh) {
        const Vec3 p = o + t * d;
        h = {t, Vec3(p.x(), 0.0, p.z()) / r};
        hit = true;
        maxT = t;
      }
    }
  }
  for (double s : {-hh, hh}) {
    LocalHit hs;
    const Vec3 c(0.0, s, 0.0);
    if (raySphere(o - c, d, r, maxT, hs) && (!hit || hs.t < h.t)) h = hs, hit = true, maxT = hs.t;
  }
  return hit;
}

// Clips the ray against every face plane of the hull.
bool rayHull(const ConvexHullData& hull, const Vec3& o, const Vec3& d, double maxT, LocalHit& h) {
  double tEnter = 0.0, tExit = maxT;
  int enterFace = -1;
  for (int f = 0; f < static_cast<int>(hull.faces.size()); ++f) {
    const auto& face = hull.faces[f];
    const double dist = face.normal.dot(o) - face.offset, den = face.normal.dot(d);
    if (den == 0.0) {
      if (dist > 0.0) return false;
      continue;
    }
    const double t = -dist / den;
    if (den < 0.0) {
      if (t > tEnter) tEnter = t, enterFace = f;
    } else if (dist > 0.0) {
      return false;  // outside this face and moving away from it
    } else {
      tExit = std::min(tExit, t);
    }
    if (tEnter > tExit) return false;
  }
  if (enterFace < 0) {
    // Inside every plane at t = 0 (or the ray entered before the origin).
    for (const auto& face : hull.faces)
      if (face.normal.dot(o) - face.offset > 0.0) return false;
    return h = {}, true;
  }
  h = {tEnter, hull.faces[enterFace].normal};
  return true;
}

bool rayPlane(const Shape& s, const Vec3& o, const Vec3& d, double maxT, LocalHit& h) {
  const Vec3& n = s.planeNormal();
  const double dist = n.dot(o) - s.planeOffset();
  if (dist <= 0.0) return h = {}, true;
  const double den = n.dot(d);
  if (den >= 0.0) return false;
  const double t = -dist / den;
  if (t > maxT) return false;
  h = {t, n};
  return true;
}

// Any non-compound shape, in its own frame.
bool rayLocal(const Shape& s, const Vec3& o, const Vec3& d, double maxT, LocalHit& h) {
  const bool rounded = s.radius() > 0.0;
  switch (s.type()) {
    case ShapeType::Sphere:
      return raySphere(o, d, s.radius(), maxT, h);
    case ShapeType::Capsule:
      return rayCapsule(o, d, s.radius(), s.halfHeight(), maxT, h);
    case ShapeType::Plane:
      return rayPlane(s, o, d, maxT, h);
    case ShapeType::Box:
      if (!rounded) return rayBox(o, d, s.halfExtents(), maxT, h);
      break;
    case ShapeType::ConvexHull:
      if (!rounded) return rayHull(s.hull(), o, d, maxT, h);
      break;
    case ShapeType::Compound:
      return false;
  }
  // Rounded boxes and hulls: conservative advancement on the support function.
  return detail::convexRayCast(s, o, d, maxT, h.t, h.normal);
}

bool rayShape(const Shape& s, const Transform& t, const Vec3& origin, const Vec3& dir,
              double maxDistance, RayHit& hit) {
  LocalHit h;
  if (!rayLocal(s, t.applyInverse(origin), t.rotateInverse(dir), maxDistance, h)) return false;
  hit.distance = h.t;
  hit.point = origin + h.t * dir;
  hit.normal = h.normal.squaredNorm() > 0.0 ? Vec3(t.rotate(h.normal)) : Vec3(-dir);
  return true;
}

// Slab test of a ray against a box, for tree traversal: entry distance or +inf.
double rayAabb(const Vec3& o, const Vec3& invD, const Aabb& b, double maxT) {
  double t0 = 0.0, t1 = maxT;
  for (int k = 0; k < 3; ++k) {
    double a = (b.min[k] - o[k]) * invD[k], c = (b.max[k] - o[k]) * invD[k];
    if (std::isnan(a) || std::isnan(c)) {  // zero direction component exactly on a slab face
      if (o[k] < b.min[k] || o[k] > b.max[k]) return kInf;
      continue;
    }
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1) return kInf;
  }
  return t0;
}

void checkRay(const Vec3& origin, const Vec3& dir, double maxDistance) {
  requireFinite(origin, "rayCast.origin");
  requireFinite(dir, "rayCast.dir");
  if (std::abs(dir.norm() - 1.0) > 1e-6) throw Error("rayCast.dir", "must be unit length");
  if (std::isnan(maxDistance) || maxDistance < 0.0)
    throw Error("rayCast.maxDistance", "must not be negative");
}

// Keeps h, a hit on compound child `child`, if it is the first or nearer than the best so far
// (ties go to the lower child index).
void keepNearest(const RayHit& h, uint32_t child, bool& found, double& best, RayHit& hit) {
  if (found && !(h.distance < best || (h.distance == best && child < hit.child))) return;
  hit = h;
  hit.child = child;
  best = h.distance;
  found = true;
}

void checkChild(const Shape& s, uint32_t child, const char* field) {
  if (s.type() == ShapeType::Compound && child >= s.children().size())
    throw Error(field, "no such compound child (" + std::to_string(child) + ")");
}

}  // namespace

bool rayCast(const Shape& s, const Transform& t, const Vec3& origin, const Vec3& dir,
             double maxDistance, RayHit& hit) {
  checkRay(origin, dir, maxDistance);
  if (s.type() != ShapeType::Compound) {
    hit.child = 0;
    return rayShape(s, t, origin, dir, maxDistance, hit);
  }
  // Walk the tree nearest-box-first is not needed for correctness; a plain stack with the
  // best distance so far prunes enough. Ties go to the lower child index.
  const Vec3 o = t.applyInverse(origin), d = t.rotateInverse(dir);
  const Vec3 invD = d.cwiseInverse();
  const auto& nodes = s.tree().nodes;
  double best = maxDistance;
  bool found = false;
  int32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const CompoundTree::Node& n = nodes[stack[--top]];
    if (rayAabb(o, invD, n.box, best) == kInf) continue;
    if (n.child < 0) {
      if (top + 2 <= 64) stack[top++] = n.right, stack[top++] = n.left;
      continue;
    }
    const CompoundChild& c = s.children()[n.child];
    RayHit h;
    if (!rayShape(*c.shape, t * c.local, origin, dir, best, h)) continue;
    keepNearest(h, static_cast<uint32_t>(n.child), found, best, hit);
  }
  return found;
}

bool rayCastChild(const Shape& s, const Transform& t, uint32_t child, const Vec3& origin,
                  const Vec3& dir, double maxDistance, RayHit& hit) {
  checkRay(origin, dir, maxDistance);
  checkChild(s, child, "rayCastChild.child");
  if (s.type() != ShapeType::Compound) {
    hit.child = 0;
    return rayShape(s, t, origin, dir, maxDistance, hit);
  }
  const CompoundChild& c = s.children()[child];
  if (!rayShape(*c.shape, t * c.local, origin, dir, maxDistance, hit)) return false;
  hit.child = child;
  return true;
}

namespace {

// The moving shape against a non-compound shape s, both in the world. False if it misses.
bool castAgainst(const Shape& s, const Transform& t, const Shape& moving, const Transform& tm,
                 const Vec3& dir, double maxT, RayHit& hit) {
  const Transform m = t.inverse() * tm;  // the moving shape in s's frame
  const Vec3 d = t.rotateInverse(dir);
  double at = 0.0;
  Vec3 n = Vec3::Zero(), p = Vec3::Zero();
  if (s.type() == ShapeType::Plane) {
    const Vec3 up = s.planeNormal();
    p = m.apply(moving.support(m.rotateInverse(-up)));  // the moving shape's lowest point
    const double gap = up.dot(p) - s.planeOffset();
    if (gap > 0.0) {
      const double closing = up.dot(d);
      if (closing >= 0.0 || -gap / closing > maxT) return false;
      at = -gap / closing;
      n = up;
    }
    p += at * d;
  } else if (!detail::convexShapeCast(s, moving, m, d, maxT, at, n, p)) {
    return false;
  }
  hit.distance = at;
  hit.normal = n.squaredNorm() > 0.0 ? Vec3(t.rotate(n)) : Vec3(-dir);
  hit.point = t.apply(p);
  return true;
}

}  // namespace

bool shapeCast(const Shape& s, const Transform& t, const Shape& moving, const Transform& tm,
               const Vec3& dir, double maxDistance, RayHit& hit) {
  requireFinite(tm.p, "shapeCast.pose.position");
  requireFinite(tm.q, "shapeCast.pose.orientation");
  requireFinite(dir, "shapeCast.dir");
  if (std::abs(dir.norm() - 1.0) > 1e-6) throw Error("shapeCast.dir", "must be unit length");
  if (std::isnan(maxDistance) || maxDistance < 0.0)
    throw Error("shapeCast.maxDistance", "must not be negative");
  if (!moving.isConvex())
    throw Error("shapeCast.shape", "must be convex (a sphere, capsule, box or hull)");
  if (s.type() != ShapeType::Compound) {
    hit.child = 0;
    return castAgainst(s, t, moving, tm, dir, maxDistance, hit);
  }
  // The children whose boxes the swept shape's box overlaps (in the compound's frame), nearest
  // hit first; ties go to the lower child index.
  const Aabb swept = moving.bounds(t.inverse() * tm).sweptAlong(t.rotateInverse(dir), maxDistance);
  double best = maxDistance;
  bool found = false;
  s.tree().query(swept, [&](int32_t index) {
    const CompoundChild& c = s.children()[static_cast<size_t>(index)];
    RayHit h;
    if (!castAgainst(*c.shape, t * c.local, moving, tm, dir, best, h)) return;
    keepNearest(h, static_cast<uint32_t>(index), found, best, hit);
  });
  return found;
}

namespace {

// Closest surface point of a non-compound shape, in its own frame.
SurfacePoint closestLocal(const Shape& s, const Vec3& x) {
  SurfacePoint sp;
  const double r = s.radius();
  // Outside a core point q (distance d > 0): the surface is r farther along the direction.
  auto fromCore = [&](const Vec3& q, const Vec3& fallback) {
    const Vec3 dv = x - q;
    const double d = dv.norm();
    sp.normal = d > 1e-300 ? Vec3(dv / d) : fallback;
    sp.point = q + r * sp.normal;
    sp.distance = d - r;
  };
  switch (s.type()) {
    case ShapeType::Sphere:
      fromCore(Vec3::Zero(), Vec3::UnitY());
      break;
    case ShapeType::Capsule: {
      const Vec3 q(0.0, std::clamp(x.y(), -s.halfHeight(), s.halfHeight()), 0.0);
      fromCore(q, Vec3::UnitX());
      break;
    }
    case ShapeType::Box: {
      const Vec3& h = s.halfExtents();
      const Vec3 q = x.cwiseMax(-h).cwiseMin(h);
      if (q != x) {
        fromCore(q, Vec3::UnitY());
        break;
      }
      int axis = 0;  // inside the core: leave through the nearest face
      for (int k = 1; k < 3; ++k)
        if (h[k] - std::abs(x[k]) < h[axis] - std::abs(x[axis])) axis = k;
      const double sign = x[axis] >= 0.0 ? 1.0 : -1.0;
      sp.normal = Vec3::Unit(axis) * sign;
      sp.point = x;
      sp.point[axis] = sign * (h[axis] + r);
      sp.distance = std::abs(x[axis]) - h[axis] - r;
      break;
    }
    case ShapeType::ConvexHull: {
      const ConvexHullData& hull = s.hull();
      int face = 0;
      double maxDist = -kInf;
      for (int f = 0; f < static_cast<int>(hull.faces.size()); ++f) {
        const double dist = hull.faces[f].normal.dot(x) - hull.faces[f].offset;
        if (dist > maxDist) maxDist = dist, face = f;
      }
      if (maxDist > 0.0) {  // outside: GJK against the point
        const detail::CoreDistance cd = detail::pointDistance(detail::Core(s, Transform{}), x);
        if (!cd.overlap) {
          fromCore(cd.pointA, hull.faces[face].normal);
          break;
        }
      }
      sp.normal = hull.faces[face].normal;  // inside: the nearest face plane
      sp.point = x + (r - maxDist) * sp.normal;
      sp.distance = maxDist - r;
      break;
    }
    case ShapeType::Plane: {
      sp.normal = s.planeNormal();
      sp.distance = sp.normal.dot(x) - s.planeOffset();
      sp.point = x - sp.distance * sp.normal;
      break;
    }
    case ShapeType::Compound:
      break;
  }
  return sp;
}

SurfacePoint closestShape(const Shape& s, const Transform& t, const Vec3& x) {
  SurfacePoint sp = closestLocal(s, t.applyInverse(x));
  sp.point = t.apply(sp.point);
  sp.normal = t.rotate(sp.normal);
  return sp;
}

// True when `p` (compound space, on child `skip`'s surface with outward normal `n`) is not on
// the union's surface: strictly inside another child, or on another child's face that
// opposes n (a face shared between voxel boxes).
bool buried(const Shape& s, const Vec3& p, const Vec3& n, uint32_t skip) {
  bool hidden = false;
  s.tree().query(Aabb{p, p}.inflated(1e-9), [&](int32_t j) {
    if (hidden || static_cast<uint32_t>(j) == skip) return;
    const CompoundChild& c = s.children()[j];
    const SurfacePoint sp = closestShape(*c.shape, c.local, p);
    hidden = sp.distance < -1e-9 || (sp.distance < 1e-9 && sp.normal.dot(n) < 0.0);
  });
  return hidden;
}

// For x inside child i (compound space): its face planes as candidate exits, nearest first
// among those that are on the union's surface. Boxes and hulls only; false if none qualifies.
bool exposedExit(const Shape& s, uint32_t i, const Vec3& x, SurfacePoint& out) {
  const CompoundChild& c = s.children()[i];
  const Shape& shape = *c.shape;
  const Vec3 xl = c.local.applyInverse(x);
  bool found = false;
  auto consider = [&](const Vec3& nl, double offset) {
    const double depth = offset + shape.radius() - nl.dot(xl);
    if (found && depth >= -out.distance) return;
    const Vec3 n = c.local.rotate(nl);
    const Vec3 p = c.local.apply(xl + depth * nl);
    if (buried(s, p, n, i)) return;
    out = {p, n, -depth, i};
    found = true;
  };
  if (shape.type() == ShapeType::Box) {
    for (int k = 0; k < 3; ++k) {
      consider(Vec3::Unit(k), shape.halfExtents()[k]);
      consider(-Vec3::Unit(k), shape.halfExtents()[k]);
    }
  } else if (shape.type() == ShapeType::ConvexHull) {
    for (const auto& f : shape.hull().faces) consider(f.normal, f.offset);
  }
  return found;
}

// A compound baked by the voxel tool answers from its signed-distance field: the exact surface
// (not the boxes' staircase) and a smooth normal. The child is the box nearest that point.
SurfacePoint closestFromSdf(const Shape& s, const SignedDistanceField& f, const Transform& t,
                            const Vec3& xl) {
  SurfacePoint out;
  out.distance = f.distance(xl);
  const Vec3 p = f.closestPoint(xl);
  out.point = t.apply(p);
  out.normal = t.rotate(f.normal(p));
  double nearest = kInf;
  const double reach = 2.0 * f.spacing();
  s.tree().query(Aabb{p, p}.inflated(reach), [&](int32_t i) {
    const CompoundChild& c = s.children()[static_cast<size_t>(i)];
    const double d = std::abs(closestShape(*c.shape, c.local, p).distance);
    if (d < nearest) nearest = d, out.child = static_cast<uint32_t>(i);
  });
  return out;
}

}  // namespace

SurfacePoint closestPoint(const Shape& s, const Transform& t, const Vec3& x) {
  requireFinite(x, "closestPoint.x");
  if (s.type() != ShapeType::Compound) return closestShape(s, t, x);
  // The union's signed distance is the smallest of the children's (exact outside them).
  // Inside, a child's nearest face may be shared with a neighbour (voxel boxes) and so not
  // on the union's surface: then the nearest exposed face plane of the containing children
  // is used (an approximation; a baked SDF gives exact answers).
  const Vec3 xl = t.applyInverse(x);
  if (const SignedDistanceField* f = s.sdf()) return closestFromSdf(s, *f, t, xl);
  SurfacePoint best;
  best.distance = kInf;
  for (uint32_t i = 0; i < s.children().size(); ++i) {
    const CompoundChild& c = s.children()[i];
    SurfacePoint sp = closestShape(*c.shape, c.local, xl);  // compound space
    sp.child = i;
    if (sp.distance < best.distance) best = sp;
  }
  if (best.distance < 0.0 && buried(s, best.point, best.normal, best.child)) {
    SurfacePoint exit, candidate;
    exit.distance = -kInf;
    for (uint32_t i = 0; i < s.children().size(); ++i) {
      if (!s.children()[i].shape->bounds(s.children()[i].local).contains(xl)) continue;
      if (exposedExit(s, i, xl, candidate) && candidate.distance > exit.distance) exit = candidate;
    }
    if (exit.distance > -kInf) best = exit;
  }
  best.point = t.apply(best.point);
  best.normal = t.rotate(best.normal);
  return best;
}

Vec3 childCenter(const Shape& s, const Transform& t, uint32_t child) {
  checkChild(s, child, "childCenter.child");
  if (s.type() != ShapeType::Compound) return t.apply(s.localCenter());
  const CompoundChild& c = s.children()[child];
  return t.apply(c.local.apply(c.shape->localCenter()));
}

}  // namespace grip
