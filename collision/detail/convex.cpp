// GJK distance (closest points of two convex cores) and the libccd bridge for penetration.
#include "collision/detail/convex.hpp"

#include <ccd/ccd.h>

#include <array>
#include <limits>

namespace grip::detail {

Vec3 Core::support(const Vec3& dir) const {
  const Vec3 d = t.rotateInverse(dir);
  auto sgn = [](double x) { return x >= 0.0 ? 1.0 : -1.0; };
  switch (shape->type()) {
    case ShapeType::Box: {
      const Vec3& h = shape->halfExtents();
      return t.apply(Vec3(sgn(d.x()) * h.x(), sgn(d.y()) * h.y(), sgn(d.z()) * h.z()));
    }
    case ShapeType::Capsule:
      return t.apply(Vec3(0.0, sgn(d.y()) * shape->halfHeight(), 0.0));
    case ShapeType::ConvexHull: {
      const auto& v = shape->hull().vertices;
      int best = 0;
      double bestD = v[0].dot(d);
      for (int i = 1; i < static_cast<int>(v.size()); ++i) {
        const double x = v[i].dot(d);
        if (x > bestD) bestD = x, best = i;
      }
      return t.apply(v[best]);
    }
    default:
      return t.p;  // sphere: the centre
  }
}

namespace {

struct Vertex {
  Vec3 w = Vec3::Zero(), a = Vec3::Zero(), b = Vec3::Zero();  // w = b - a
};

// Closest point to the origin on a simplex of 1-4 vertices. Keeps only the vertices that
// support it (in their original order) and their barycentric weights.
struct Simplex {
  std::array<Vertex, 4> v;
  std::array<double, 4> lambda{};
  int n = 0;

  void keep(std::initializer_list<std::pair<int, double>> parts) {
    std::array<Vertex, 4> nv;
    int k = 0;
    for (const auto& [i, l] : parts) {
      nv[k] = v[i];
      lambda[k] = l;
      ++k;
    }
    v = nv;
    n = k;
  }

  void solveSegment(int ia, int ib) {
    const Vec3 a = v[ia].w, ab = v[ib].w - v[ia].w;
    const double den = ab.squaredNorm();
    const double t = den > 0.0 ? -a.dot(ab) / den : 0.0;
    if (t <= 0.0) return keep({{ia, 1.0}});
    if (t >= 1.0) return keep({{ib, 1.0}});
    keep({{ia, 1.0 - t}, {ib, t}});
  }

  // Ericson, Real-Time Collision Detection 5.1.5, with p = origin.
  void solveTriangle(int ia, int ib, int ic) {
    const Vec3 a = v[ia].w, b = v[ib].w, c = v[ic].w;
    const Vec3 ab = b - a, ac = c - a;
    const double d1 = -ab.dot(a), d2 = -ac.dot(a);
    if (d1 <= 0.0 && d2 <= 0.0) return keep({{ia, 1.0}});
    const double d3 = -ab.dot(b), d4 = -ac.dot(b);
    if (d3 >= 0.0 && d4 <= d3) return keep({{ib, 1.0}});
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
      const double t = d1 / (d1 - d3);
      return keep({{ia, 1.0 - t}, {ib, t}});
    }
    const double d5 = -ab.dot(c), d6 = -ac.dot(c);
    if (d6 >= 0.0 && d5 <= d6) return keep({{ic, 1.0}});
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
      const double t = d2 / (d2 - d6);
      return keep({{ia, 1.0 - t}, {ic, t}});
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
      const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      return keep({{ib, 1.0 - t}, {ic, t}});
    }
    const double den = va + vb + vc;
    if (!(den > 0.0)) return solveSegment(ia, ib);  // degenerate (zero area)
    const double l1 = vb / den, l2 = vc / den;
    keep({{ia, 1.0 - l1 - l2}, {ib, l1}, {ic, l2}});
  }

  // Returns false when the origin is inside the tetrahedron (the shapes overlap).
  bool solveTetra() {
    static constexpr int faces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
    double best = std::numeric_limits<double>::infinity();
    Simplex bestS;
    bool outsideAny = false;
    for (const auto& f : faces) {
      const Vec3 a = v[f[0]].w;
      const Vec3 nrm = (v[f[1]].w - a).cross(v[f[2]].w - a);
      const double sO = -a.dot(nrm), sD = (v[f[3]].w - a).dot(nrm);
      if (sO * sD > 0.0) continue;  // origin on the inner side of this face
      outsideAny = true;
      Simplex s = *this;
      s.solveTriangle(f[0], f[1], f[2]);
      const double d = s.point().squaredNorm();
      if (d < best) best = d, bestS = s;
    }
    if (!outsideAny) return false;
    *this = bestS;
    return true;
  }

  Vec3 point() const {
    Vec3 p = Vec3::Zero();
    for (int i = 0; i < n; ++i) p += lambda[i] * v[i].w;
    return p;
  }

  bool solve() {
    switch (n) {
      case 1:
        lambda[0] = 1.0;
        return true;
      case 2:
        solveSegment(0, 1);
        return true;
      case 3:
        solveTriangle(0, 1, 2);
        return true;
      default:
        return solveTetra();
    }
  }
};

}  // namespace

namespace {

// GJK on two support mappings (world space). `d` is the first search direction (A to B).
template <class SupportA, class SupportB>
CoreDistance gjk(const SupportA& supportA, const SupportB& supportB, Vec3 d) {
  CoreDistance out;
  if (d.squaredNorm() < 1e-30) d = Vec3::UnitX();
  Simplex s;
  Vec3 v = supportB(-d) - supportA(d);
  double vv = v.squaredNorm();
  if (vv > 0.0) out.direction = v / std::sqrt(vv);
  for (int iter = 0; iter < 64; ++iter) {
    Vertex w;
    w.a = supportA(v);
    w.b = supportB(-v);
    w.w = w.b - w.a;
    // No progress possible: v is (to rounding) the closest point.
    if (s.n > 0 && vv - v.dot(w.w) <= 1e-12 * vv) break;
    bool duplicate = false;
    for (int i = 0; i < s.n; ++i) duplicate = duplicate || s.v[i].w == w.w;
    if (duplicate) break;
    const Simplex best = s;
    s.v[s.n++] = w;
    if (!s.solve()) {
      out.overlap = true;
      return out;
    }
    const Vec3 nv = s.point();
    const double nvv = nv.squaredNorm();
    if (nvv <= 1e-24) {
      out.overlap = true;
      return out;
    }
    // No closer: rounding, or a degenerate simplex (a vertex tying with the face it lies on,
    // as flat faces of the two shapes give) whose sub-simplex picked is farther. Stop at the
    // best so far; the farther one once put a resting plank 39 mm from a beam it touched.
    if (nvv >= vv && s.n > 1) {
      s = best;
      break;
    }
    out.direction = nv / std::sqrt(nvv);
    v = nv;
    vv = nvv;
  }
  out.pointA = Vec3::Zero();
  out.pointB = Vec3::Zero();
  if (s.n == 0) {  // converged on the very first guess
    out.pointA = supportA(d);
    out.pointB = supportB(-d);
  }
  for (int i = 0; i < s.n; ++i) {
    out.pointA += s.lambda[i] * s.v[i].a;
    out.pointB += s.lambda[i] * s.v[i].b;
  }
  out.distance = (out.pointB - out.pointA).norm();
  if (out.distance <= 1e-12) out.overlap = true;
  return out;
}

}  // namespace

CoreDistance coreDistance(const Core& a, const Core& b) {
  return gjk([&](const Vec3& v) { return a.support(v); },
             [&](const Vec3& v) { return b.support(v); }, b.center() - a.center());
}

CoreDistance pointDistance(const Core& a, const Vec3& x) {
  return gjk([&](const Vec3& v) { return a.support(v); }, [&](const Vec3&) { return x; },
             x - a.center());
}

bool convexRayCast(const Shape& s, const Vec3& origin, const Vec3& dir, double maxDistance,
                   double& t, Vec3& normal) {
  // Van den Bergen's GJK ray cast: advance x along the ray by the support-plane distance
  // and keep a simplex of support points p_i; the simplex vertices are x - p_i.
  t = 0.0;
  normal = Vec3::Zero();
  Vec3 x = origin;
  Vec3 v = x - s.localCenter();
  std::array<Vec3, 4> pts;
  int n = 0;
  Simplex simplex;
  const double eps = 1e-10 * std::max(1.0, s.localBounds().extent().norm());
  for (int iter = 0; iter < 64 && v.squaredNorm() > eps * eps; ++iter) {
    const Vec3 p = s.support(v);
    const Vec3 w = x - p;
    if (v.dot(w) > 0.0) {
      if (v.dot(dir) >= 0.0) return false;  // moving away from the support plane
      t -= v.dot(w) / v.dot(dir);
      if (t > maxDistance) return false;
      x = origin + t * dir;
      normal = v;
    }
    bool duplicate = false;
    for (int i = 0; i < n; ++i) duplicate = duplicate || pts[i] == p;
    if (!duplicate) {
      if (n == 4) break;
      pts[n++] = p;
    }
    simplex.n = n;
    for (int i = 0; i < n; ++i) {
      simplex.v[i].a = pts[i];
      simplex.v[i].w = x - pts[i];
    }
    if (!simplex.solve()) break;  // x inside the simplex: on the surface (to tolerance)
    n = simplex.n;
    for (int i = 0; i < n; ++i) pts[i] = simplex.v[i].a;
    v = simplex.point();
  }
  if (normal.squaredNorm() > 0.0) normal.normalize();
  return true;
}

// Conservative advancement on the cores (as Box2D's b2ShapeCast): the plane through the cores'
// closest points separates them until the moving shape has closed the gap across it, so it
// may advance that far at least; flat faces meet in one step, round ones converge fast.
bool convexShapeCast(const Shape& target, const Shape& moving, const Transform& movingPose,
                     const Vec3& dir, double maxDistance, double& t, Vec3& normal, Vec3& point) {
  const Core a(target, Transform{});
  const double radius = target.radius() + moving.radius();
  const double size = target.localBounds().extent().norm() + moving.localBounds().extent().norm();
  const double tolerance = 1e-10 * std::max(1.0, size);
  t = 0.0;
  normal = Vec3::Zero();
  Vec3 lastNormal = Vec3::Zero(), lastPoint = Vec3::Zero();
  for (int iter = 0; iter < 50; ++iter) {
    const Core b(moving, Transform{movingPose.p + t * dir, movingPose.q});
    const CoreDistance d = coreDistance(a, b);
    if (d.overlap || !(d.distance > 0.0)) {  // the cores touch: where the cast began, or by
      if (t > 0.0) normal = lastNormal;      // rounding just short of it (the last step's)
      point = t > 0.0 ? lastPoint : d.pointA;
      return true;
    }
    const Vec3 n = (d.pointB - d.pointA) / d.distance;  // the target's outward normal
    const double gap = d.distance - radius;
    lastNormal = n, lastPoint = d.pointA + target.radius() * n;
    if (gap <= tolerance) {
      if (t > 0.0) normal = n;
      point = lastPoint;
      return true;
    }
    const double closing = -n.dot(dir);
    if (!(closing > 0.0)) return false;      // the plane stays between them
    t += (gap - 0.5 * tolerance) / closing;  // short of touching: the closest points stay known
    if (t > maxDistance) return false;
  }
  return false;  // not converged (grazing): no hit reported
}

namespace {

void ccdSupport(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* vec) {
  const Core* c = static_cast<const Core*>(obj);
  const Vec3 p = c->support(Vec3(dir->v[0], dir->v[1], dir->v[2]));
  ccdVec3Set(vec, p.x(), p.y(), p.z());
}

void ccdCenter(const void* obj, ccd_vec3_t* center) {
  const Vec3 p = static_cast<const Core*>(obj)->center();
  ccdVec3Set(center, p.x(), p.y(), p.z());
}

}  // namespace

CorePenetration corePenetration(const Core& a, const Core& b) {
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = ccdSupport;
  ccd.support2 = ccdSupport;
  ccd.center1 = ccdCenter;
  ccd.center2 = ccdCenter;
  ccd.first_dir = ccdFirstDirDefault;
  ccd.max_iterations = 100;
  ccd.epa_tolerance = 1e-9;
  ccd.mpr_tolerance = 1e-9;
  ccd.dist_tolerance = 1e-9;
  ccd_real_t depth = 0.0;
  ccd_vec3_t dir, pos;
  CorePenetration out;
  // libccd reports "penetration of obj2 into obj1": translating obj2 by depth*dir separates
  // them, so dir points from A to B (pinned down by a test).
  int rc = ccdGJKPenetration(&a, &b, &ccd, &depth, &dir, &pos);
  if (rc != 0) rc = ccdMPRPenetration(&a, &b, &ccd, &depth, &dir, &pos);
  if (rc != 0) return out;
  const Vec3 n(dir.v[0], dir.v[1], dir.v[2]);
  if (!(n.squaredNorm() > 0.0) || !n.allFinite()) return out;
  out.ok = true;
  out.depth = std::max(0.0, static_cast<double>(depth));
  out.normal = n.normalized();
  out.point = Vec3(pos.v[0], pos.v[1], pos.v[2]);
  return out;
}

}  // namespace grip::detail
