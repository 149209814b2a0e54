// Narrowphase: analytic fast paths for the common pairs, GJK + libccd + feature clipping for
// the rest, and compound iteration. Conventions: the normal points from A to B, separation
// is negative when overlapping, positions lie midway between the two surfaces.
#include "collision/narrowphase.hpp"

#include <algorithm>
#include <limits>

#include "collision/detail/convex.hpp"
#include "collision/detail/manifold.hpp"

namespace grip {
namespace {

using detail::Core;
using detail::Feature;

// Face axes win ties with edge axes (and A's faces with B's) unless clearly better: this keeps
// resting boxes on stable face manifolds instead of flickering to edge contacts. `slop` is an
// absolute tolerance that scales down for small boxes.
bool clearlyBetter(double candidate, double best, double slop) {
  return candidate > best + 0.05 * std::abs(best) + slop;
}

void flip(Manifold& m) {
  m.normal = -m.normal;
}

// A single point between two spheres (cores cA, cB grown by rA, rB). `fallback` is the
// normal used when the centres coincide.
bool pointContact(const Vec3& cA, double rA, const Vec3& cB, double rB, double margin,
                  const Vec3& fallback, Manifold& m) {
  const Vec3 d = cB - cA;
  const double dist = d.norm();
  const double sep = dist - rA - rB;
  if (sep >= margin) return false;
  const Vec3 n = dist > 1e-12 ? Vec3(d / dist) : fallback;
  m.normal = n;
  m.points[0].position = 0.5 * ((cA + rA * n) + (cB - rB * n));
  m.points[0].separation = sep;
  m.points[0].featureId = 0;
  m.pointCount = 1;
  return true;
}

// Squared length (m^2) below which a segment is a point: 1e-12 m, far below any contact
// tolerance, and well above where 0/0 would make NaN.
constexpr double kPointSegment = 1e-24;

Vec3 closestOnSegment(const Vec3& a, const Vec3& b, const Vec3& x) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= kPointSegment) return a;  // a capsule of (almost) no length is a sphere
  const double t = std::clamp((x - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

// Closest points of segments p1q1 and p2q2 (Ericson 5.1.9, with his degenerate cases).
void closestSegments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, Vec3& c1,
                     Vec3& c2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  if (a <= kPointSegment || e <= kPointSegment) {  // one or both are points
    c1 = a <= kPointSegment ? p1 : closestOnSegment(p1, q1, p2);
    c2 = closestOnSegment(p2, q2, c1);
    if (a > kPointSegment) c1 = closestOnSegment(p1, q1, c2);
    return;
  }
  const double c = d1.dot(r), b = d1.dot(d2);
  const double denom = a * e - b * b;
  double s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  c1 = p1 + d1 * s;
  c2 = p2 + d2 * t;
}

Vec3 anyPerpendicular(const Vec3& v) {
  Vec3 t1, t2;
  tangentBasis(v.normalized(), t1, t2);
  return t1;
}

void capsuleEnds(const Shape& s, const Transform& t, Vec3& a, Vec3& b) {
  const Vec3 axis = t.rotate(Vec3(0.0, s.halfHeight(), 0.0));
  a = t.p - axis;
  b = t.p + axis;
}

bool sphereSphere(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                  double margin, Manifold& m) {
  return pointContact(ta.p, a.radius(), tb.p, b.radius(), margin, Vec3::UnitY(), m);
}

bool sphereCapsule(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                   double margin, Manifold& m) {
  Vec3 b0, b1;
  capsuleEnds(b, tb, b0, b1);
  const Vec3 q = closestOnSegment(b0, b1, ta.p);
  return pointContact(ta.p, a.radius(), q, b.radius(), margin, -tb.rotate(Vec3::UnitX()), m);
}

bool capsuleCapsule(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                    double margin, Manifold& m) {
  Vec3 a0, a1, b0, b1;
  capsuleEnds(a, ta, a0, a1);
  capsuleEnds(b, tb, b0, b1);
  const Vec3 da = a1 - a0, db = b1 - b0;
  const double rA = a.radius(), rB = b.radius();
  // (Nearly) parallel: B's segment clipped to A's extent gives two points, so a capsule
  // lying on another does not roll about a single point.
  if (da.cross(db).squaredNorm() < 1e-6 * da.squaredNorm() * db.squaredNorm()) {
    const Vec3 u = da.normalized();
    const double lo = 0.0, hi = da.norm();
    double t0 = (b0 - a0).dot(u), t1 = (b1 - a0).dot(u);
    const Vec3 bDir = db / db.dot(u);  // step along B per unit of A's axis
    const double s0 = std::max(std::min(t0, t1), lo), s1 = std::min(std::max(t0, t1), hi);
    if (s1 - s0 > 1e-9 * hi) {
      const Vec3 q0 = b0 + bDir * (s0 - t0), q1 = b0 + bDir * (s1 - t0);
      const Vec3 p0 = a0 + u * s0, p1 = a0 + u * s1;
      Vec3 n = 0.5 * ((q0 - p0) + (q1 - p1));
      n -= u * n.dot(u);
      const double len = n.norm();
      n = len > 1e-12 ? Vec3(n / len) : anyPerpendicular(u);
      const std::array<Vec3, 2> ps = {p0, p1}, qs = {q0, q1};
      int k = 0;
      for (int i = 0; i < 2; ++i) {
        const double sep = (qs[i] - ps[i]).dot(n) - rA - rB;
        if (sep >= margin) continue;
        m.points[k].position = 0.5 * ((ps[i] + rA * n) + (qs[i] - rB * n));
        m.points[k].separation = sep;
        m.points[k].featureId = static_cast<uint32_t>(i + 1);
        ++k;
      }
      m.normal = n;
      m.pointCount = k;
      return k > 0;
    }
  }
  Vec3 c1, c2;
  closestSegments(a0, a1, b0, b1, c1, c2);
  Vec3 fallback = da.cross(db);
  fallback = fallback.squaredNorm() > 0.0 ? Vec3(fallback.normalized()) : anyPerpendicular(da);
  return pointContact(c1, rA, c2, rB, margin, fallback, m);
}

// Sphere A against (possibly rounded) box B.
bool sphereBox(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
               double margin, Manifold& m) {
  const Vec3& h = b.halfExtents();
  const Vec3 c = tb.applyInverse(ta.p);
  const Vec3 q = c.cwiseMax(-h).cwiseMin(h);
  if (q != c)
    return pointContact(ta.p, a.radius(), tb.apply(q), b.radius(), margin, Vec3::UnitY(), m);
  // Centre inside the core box: push out through the nearest face.
  int axis = 0;
  double depth = h.x() - std::abs(c.x());
  for (int k = 1; k < 3; ++k) {
    const double dk = h[k] - std::abs(c[k]);
    if (dk < depth) depth = dk, axis = k;
  }
  const double sign = c[axis] >= 0.0 ? 1.0 : -1.0;
  const Vec3 out = tb.rotate(Vec3::Unit(axis) * sign);  // box face normal, towards the sphere
  const double sep = -depth - a.radius() - b.radius();
  if (sep >= margin) return false;
  Vec3 face = c;
  face[axis] = sign * h[axis];
  const Vec3 boxSurface = tb.apply(face) + b.radius() * out;
  const Vec3 sphereSurface = ta.p - a.radius() * out;
  m.normal = -out;
  m.points[0] = {0.5 * (boxSurface + sphereSurface), sep, 0};
  m.pointCount = 1;
  return true;
}

// Box-box by the separating axis test over 15 axes, then face clipping or an edge pair.
bool boxBox(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double margin,
            Manifold& m) {
  const Mat3 RA = ta.q.toRotationMatrix(), RB = tb.q.toRotationMatrix();
  const Vec3 &hA = a.halfExtents(), &hB = b.halfExtents();
  const Mat3 C = RA.transpose() * RB;  // B's axes in A's frame (columns)
  const Mat3 absC = C.cwiseAbs();
  const Vec3 d = RA.transpose() * (tb.p - ta.p);  // B's centre in A's frame

  double sepA = -std::numeric_limits<double>::infinity(), sepB = sepA, sepE = sepA;
  int axisA = 0, axisB = 0, edgeI = 0, edgeJ = 0;
  for (int i = 0; i < 3; ++i) {
    const double s = std::abs(d[i]) - (hA[i] + absC.row(i).dot(hB));
    if (s > margin) return false;
    if (s > sepA) sepA = s, axisA = i;
  }
  for (int j = 0; j < 3; ++j) {
    const double s = std::abs(d.dot(C.col(j))) - (absC.col(j).dot(hA) + hB[j]);
    if (s > margin) return false;
    if (s > sepB) sepB = s, axisB = j;
  }
  // Edge axes a_i x b_j, written out (Gottschalk's OBB test): no matrix products per axis.
  Vec3 edgeAxis = Vec3::UnitX();
  for (int i = 0; i < 3; ++i) {
    const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
    for (int j = 0; j < 3; ++j) {
      const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      const double len2 = C(i1, j) * C(i1, j) + C(i2, j) * C(i2, j);
      if (len2 < 1e-12) continue;  // parallel edges: covered by the face axes
      const double len = std::sqrt(len2);
      const double rA = hA[i1] * absC(i2, j) + hA[i2] * absC(i1, j);
      const double rB = hB[j1] * absC(i, j2) + hB[j2] * absC(i, j1);
      const double dist = d[i2] * C(i1, j) - d[i1] * C(i2, j);
      const double s = (std::abs(dist) - (rA + rB)) / len;
      if (s > margin) return false;
      if (s > sepE) {
        sepE = s, edgeI = i, edgeJ = j;
        edgeAxis = Vec3::Zero();
        edgeAxis[i1] = -C(i2, j) / len;
        edgeAxis[i2] = C(i1, j) / len;
      }
    }
  }

  const double slop = std::min(5e-4, 0.02 * std::min(hA.minCoeff(), hB.minCoeff()));
  const bool useB = clearlyBetter(sepB, sepA, slop);
  const double faceSep = useB ? sepB : sepA;
  if (!clearlyBetter(sepE, faceSep, slop)) {
    if (!useB) {
      const bool positive = d[axisA] >= 0.0;
      m.normal = RA.col(axisA) * (positive ? 1.0 : -1.0);
      return detail::clipBoxFaces(hA, RA, ta.p, axisA, positive, hB, C, d, true, margin, m) > 0;
    }
    const bool towardsB = d.dot(C.col(axisB)) >= 0.0;
    m.normal = RB.col(axisB) * (towardsB ? 1.0 : -1.0);  // A to B; B's face points against it
    const Mat3 CT = C.transpose();
    return detail::clipBoxFaces(hB, RB, tb.p, axisB, !towardsB, hA, CT, -(CT * d), false, margin,
                                m) > 0;
  }

  // Edge against edge: the two supporting edges' closest points (in A's frame).
  const Vec3 n = d.dot(edgeAxis) >= 0.0 ? edgeAxis : Vec3(-edgeAxis);
  Vec3 ca = Vec3::Zero(), cb = d;
  uint32_t codeA = static_cast<uint32_t>(edgeI) << 4, codeB = static_cast<uint32_t>(edgeJ) << 4;
  for (int k = 0; k < 3; ++k) {
    if (k != edgeI) {
      const bool pos = n[k] >= 0.0;
      ca[k] = pos ? hA[k] : -hA[k];
      codeA |= (pos ? 1u : 0u) << k;
    }
    if (k != edgeJ) {
      const bool pos = n.dot(C.col(k)) <= 0.0;
      cb += C.col(k) * (pos ? hB[k] : -hB[k]);
      codeB |= (pos ? 1u : 0u) << k;
    }
  }
  const Vec3 ea = Vec3::Unit(edgeI) * hA[edgeI], eb = C.col(edgeJ) * hB[edgeJ];
  Vec3 pa, pb;
  closestSegments(ca - ea, ca + ea, cb - eb, cb + eb, pa, pb);
  const double sep = (pb - pa).dot(n);
  if (sep >= margin) return false;
  m.normal = RA * n;
  m.points[0] = {ta.apply(0.5 * (pa + pb)), sep, 0x40000000u | (codeA << 8) | codeB};
  m.pointCount = 1;
  return true;
}

// Plane A against a convex shape B: every core vertex within the margin, reduced to 4.
bool planeConvex(const Shape& plane, const Transform& tp, const Shape& s, const Transform& ts,
                 double margin, Manifold& m) {
  const Vec3 n = tp.rotate(plane.planeNormal());
  const double offset = plane.planeOffset() + n.dot(tp.p);
  const double r = s.radius();
  m.normal = n;
  m.pointCount = 0;
  // Core points (fixed storage up to a box's 8 corners; hulls use reused scratch).
  std::array<Vec3, 8> fixedPts, fixedCand;
  std::array<double, 8> fixedSeps;
  std::array<uint32_t, 8> fixedIds;
  Vec3* pts = fixedPts.data();
  Vec3* cand = fixedCand.data();
  double* seps = fixedSeps.data();
  uint32_t* ids = fixedIds.data();
  int count = 0;
  switch (s.type()) {
    case ShapeType::Sphere:
      fixedPts[count++] = ts.p;
      break;
    case ShapeType::Capsule:
      capsuleEnds(s, ts, fixedPts[0], fixedPts[1]);
      count = 2;
      break;
    case ShapeType::Box: {
      // Corner i = centre +- the three rotated half axes (bit k of i set: + along axis k).
      const Mat3 R = ts.q.toRotationMatrix();
      const Vec3& h = s.halfExtents();
      const Vec3 ex = R.col(0) * h.x(), ey = R.col(1) * h.y(), ez = R.col(2) * h.z();
      for (int i = 0; i < 8; ++i)
        fixedPts[i] = ts.p + ((i & 1) ? ex : Vec3(-ex)) + ((i & 2) ? ey : Vec3(-ey)) +
                      ((i & 4) ? ez : Vec3(-ez));
      count = 8;
      break;
    }
    case ShapeType::ConvexHull: {
      thread_local std::vector<Vec3> hullPts, hullCand;
      thread_local std::vector<double> hullSeps;
      thread_local std::vector<uint32_t> hullIds;
      const auto& v = s.hull().vertices;
      count = static_cast<int>(v.size());
      hullPts.resize(v.size()), hullCand.resize(v.size());
      hullSeps.resize(v.size()), hullIds.resize(v.size());
      for (int i = 0; i < count; ++i) hullPts[i] = ts.apply(v[i]);
      pts = hullPts.data(), cand = hullCand.data(), seps = hullSeps.data(), ids = hullIds.data();
      break;
    }
    default:
      return false;
  }
  // Only the half of a box or hull that faces the plane can touch it. The far half's
  // corners of a thin block lie within the speculative margin and, kept, crowd the four
  // points the manifold keeps with corners that never carry load (a Jenga block sank 4 mm).
  Vec3 centre = ts.p;
  if (s.type() == ShapeType::ConvexHull) {
    centre.setZero();
    for (int i = 0; i < count; ++i) centre += pts[i];
    centre /= count;
  }
  const bool halfOnly = s.type() == ShapeType::Box || s.type() == ShapeType::ConvexHull;
  int found = 0;
  for (int i = 0; i < count; ++i) {
    if (halfOnly && n.dot(pts[i] - centre) > 0.0) continue;
    const double h = n.dot(pts[i]) - offset;
    const double sep = h - r;
    if (sep >= margin) continue;
    cand[found] = pts[i] - n * (0.5 * (h + r));  // midway: plane point and shape surface
    seps[found] = sep;
    ids[found] = static_cast<uint32_t>(i);
    ++found;
  }
  std::array<int, 4> keep;
  const int k = detail::reducePoints(cand, seps, found, n, keep, true);
  for (int i = 0; i < k; ++i) m.points[i] = {cand[keep[i]], seps[keep[i]], ids[keep[i]]};
  m.pointCount = k;
  return k > 0;
}

// Calls consider(k) for each outward face normal k of a box or hull, times `sign`.
template <class F>
void faceAxes(const Shape& s, const Transform& t, double sign, F&& consider) {
  if (s.type() == ShapeType::Box) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 axis = t.rotate(Vec3::Unit(k)) * sign;
      consider(axis);
      consider(-axis);
    }
  } else if (s.type() == ShapeType::ConvexHull) {
    for (const auto& f : s.hull().faces) consider(t.rotate(f.normal) * sign);
  }
}

// The smallest separation among a manifold's points (infinity when it has none).
double deepestSeparation(const Manifold& m) {
  double deepest = std::numeric_limits<double>::infinity();
  for (int i = 0; i < m.pointCount; ++i) deepest = std::min(deepest, m.points[i].separation);
  return deepest;
}

// Any two convex shapes: GJK distance between the cores (or libccd penetration when they
// overlap) gives the normal; the supporting features are then clipped into a manifold when a
// face is the separating axis, else the single closest-point pair is used.
bool convexGeneric(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                   double margin, Manifold& m) {
  const Core ca(a, ta), cb(b, tb);
  const double rA = ca.radius, rB = cb.radius;
  const detail::CoreDistance dist = detail::coreDistance(ca, cb);
  Vec3 n, pos;
  double sep;
  if (!dist.overlap) {
    sep = dist.distance - rA - rB;
    if (sep >= margin) return false;
    n = (dist.pointB - dist.pointA) / dist.distance;
    pos = 0.5 * ((dist.pointA + rA * n) + (dist.pointB - rB * n));
  } else {
    const detail::CorePenetration pen = detail::corePenetration(ca, cb);
    // Keep the candidate axis along which the cores overlap least. libccd's answer is used
    // when it is self-consistent; when the cores merely touch EPA returns an arbitrary
    // direction, and the GJK direction or a face normal is the right axis.
    double best = -std::numeric_limits<double>::infinity();
    n = Vec3::UnitY();
    auto consider = [&](const Vec3& k) {
      const double s = k.dot(cb.support(-k) - ca.support(k));
      if (s > best) best = s, n = k;
    };
    if (pen.ok) consider(pen.normal);
    if (!pen.ok || std::abs(best + pen.depth) > 1e-6 + 1e-3 * pen.depth) {
      if (dist.direction.squaredNorm() > 0.0) consider(dist.direction);
      faceAxes(a, ta, 1.0, consider);
      faceAxes(b, tb, -1.0, consider);
    }
    if (best == -std::numeric_limits<double>::infinity()) {  // nothing usable: centre line
      const Vec3 d = cb.center() - ca.center();
      n = d.squaredNorm() > 0.0 ? Vec3(d.normalized()) : Vec3(Vec3::UnitY());
      best = 0.0;
    }
    sep = std::min(best, 0.0) - rA - rB;
    pos = pen.ok ? pen.point : Vec3(0.5 * (ca.center() + cb.center()));
    if (sep >= margin) return false;  // exactly touching with a zero margin
  }
  m.normal = n;

  Feature fa, fb;
  detail::supportingFeature(a, ta, n, fa);
  detail::supportingFeature(b, tb, -n, fb);
  const double alignA = fa.count >= 3 ? fa.normal.dot(n) : -1.0;
  const double alignB = fb.count >= 3 ? -fb.normal.dot(n) : -1.0;
  const bool refIsA = alignA >= alignB;
  const Feature& ref = refIsA ? fa : fb;
  const Feature& inc = refIsA ? fb : fa;
  if (std::max(alignA, alignB) > 0.7 && inc.count >= 2) {
    // Use the face only if its axis separates nearly as well as the true normal does, judged
    // by the incident feature's support along the face normal...
    const Vec3 faceN = ref.normal;
    const Vec3 incSupport = refIsA ? cb.support(-faceN) : ca.support(-faceN);
    const double faceSep = (incSupport - ref.p[0]).dot(faceN) - rA - rB;
    const bool supportAgrees = faceSep >= sep - (1e-4 + 1e-3 * std::abs(sep));
    // ...or, where the support lies beyond the face (a capsule longer than the face it lies
    // on dips outside it by a tiny tilt; the face then failed, and one GJK point on the edge
    // the tilt chose was left), by the clipped points themselves: the deepest of them reaching
    // the true separation, not beyond it. Only for a capsule's segment, with the cores apart
    // (the separation is then GJK's exact distance) and the face within 5 degrees of GJK's
    // normal. (A hull plank across a narrow face has the same problem; for hulls the test is
    // not enough: random hull pairs found other contacts that pass it. They are clipped along
    // the normal below.)
    const Shape& incShape = refIsA ? b : a;
    const bool mayOverhang = !supportAgrees && faceSep < sep && !dist.overlap &&
                             incShape.type() == ShapeType::Capsule &&
                             std::max(alignA, alignB) > 0.996;
    if (supportAgrees || mayOverhang) {
      Manifold trial = m;
      trial.normal = refIsA ? faceN : Vec3(-faceN);
      const int count = detail::clipFeatures(ref, inc, refIsA, refIsA ? rA : rB, refIsA ? rB : rA,
                                             margin, trial, faceN, true);
      const double deepest = deepestSeparation(trial);
      // Accept only if the clipped polygon keeps the deepest point (it always should; this
      // guards against a degenerate incident face).
      const bool keepsDeepest =
          supportAgrees ? deepest <= faceSep + 1e-6 + 1e-3 * std::abs(faceSep)
                        : deepest >= sep - 1e-9 && deepest <= sep + 1e-4 + 1e-3 * std::abs(sep);
      if (count > 0 && keepsDeepest) {
        m = trial;
        return true;
      }
    }
  }
  // The face does not separate as well as the normal does (a plank across a narrow beam, tilted
  // both ways a little: the best axis is an edge pair's, and the support beyond the face dips
  // deeper). Clipping along the normal itself still gives the patch: each clipped point pairs
  // with the point of the face it faces along the normal, and none is deeper than the normal's
  // separation, which the deepest reaches when the clip holds the closest pair.
  if (std::max(alignA, alignB) > 0.7 && inc.count >= 2) {
    Manifold trial = m;
    const int count = detail::clipFeatures(ref, inc, refIsA, refIsA ? rA : rB, refIsA ? rB : rA,
                                           margin, trial, refIsA ? n : Vec3(-n), true);
    const double deepest = deepestSeparation(trial);
    const double tolerance = 1e-6 + 1e-3 * std::abs(sep);
    if (count > 0 && std::abs(deepest - sep) <= tolerance) {
      m = trial;
      return true;
    }
  }
  if (dist.overlap && (fa.count == 1 || fb.count == 1)) {
    // libccd's point is only roughly inside the overlap: when one side touches with a single
    // point (sphere centre, capsule end, vertex) the witness pair follows from it exactly.
    const double coreSep = sep + rA + rB;
    const Vec3 pA = fa.count == 1 ? fa.p[0] : Vec3(fb.p[0] - coreSep * n);
    const Vec3 pB = pA + coreSep * n;
    pos = 0.5 * ((pA + rA * n) + (pB - rB * n));
  }
  m.points[0] = {pos, sep, ((fa.face & 0xFFFFu) << 16) | (fb.face & 0xFFFFu)};
  m.pointCount = 1;
  return true;
}

// Convex pairs with type(a) <= type(b) (Sphere < Box < Capsule < ConvexHull).
bool collideOrdered(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                    double margin, Manifold& m) {
  const ShapeType A = a.type(), B = b.type();
  if (A == ShapeType::Sphere) {
    if (B == ShapeType::Sphere) return sphereSphere(a, ta, b, tb, margin, m);
    if (B == ShapeType::Box) return sphereBox(a, ta, b, tb, margin, m);
    if (B == ShapeType::Capsule) return sphereCapsule(a, ta, b, tb, margin, m);
  }
  if (A == ShapeType::Box && B == ShapeType::Box && a.radius() == 0.0 && b.radius() == 0.0)
    return boxBox(a, ta, b, tb, margin, m);
  if (A == ShapeType::Capsule && B == ShapeType::Capsule)
    return capsuleCapsule(a, ta, b, tb, margin, m);
  return convexGeneric(a, ta, b, tb, margin, m);
}

// Children of compound `c` whose bounds overlap `box` (in c's frame), in index order.
void overlappingChildren(const Shape& c, const Aabb& box, std::vector<uint32_t>& out) {
  out.clear();
  c.tree().query(box, [&](int32_t i) { out.push_back(static_cast<uint32_t>(i)); });
  std::sort(out.begin(), out.end());
}

}  // namespace

bool collideConvex(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb,
                   double margin, Manifold& out) {
  out = Manifold{};
  const ShapeType A = a.type(), B = b.type();
  if (A == ShapeType::Compound || B == ShapeType::Compound) return false;
  if (A == ShapeType::Plane && B == ShapeType::Plane) return false;
  if (A == ShapeType::Plane) return planeConvex(a, ta, b, tb, margin, out);
  bool hit;
  if (B == ShapeType::Plane || A > B) {
    hit = B == ShapeType::Plane ? planeConvex(b, tb, a, ta, margin, out)
                                : collideOrdered(b, tb, a, ta, margin, out);
    if (hit) flip(out);
  } else {
    hit = collideOrdered(a, ta, b, tb, margin, out);
  }
  if (!hit) out.pointCount = 0;
  return hit;
}

int collide(const Shape& a, const Transform& ta, const Shape& b, const Transform& tb, double margin,
            std::vector<Manifold>& out) {
  if (a.type() == ShapeType::Compound) {
    // Each overlapping child of A against all of B (B may be a compound too).
    // Scratch reused across calls (no allocation once warm); never re-entered, as children
    // are not compounds.
    thread_local std::vector<uint32_t> kids;
    overlappingChildren(a, b.bounds(ta.inverse() * tb).inflated(margin), kids);
    int total = 0;
    for (uint32_t i : kids) {
      const CompoundChild& c = a.children()[i];
      const size_t first = out.size();
      total += collide(*c.shape, ta * c.local, b, tb, margin, out);
      for (size_t k = first; k < out.size(); ++k) out[k].childA = i;
    }
    return total;
  }
  if (b.type() == ShapeType::Compound) {
    thread_local std::vector<uint32_t> kids;
    overlappingChildren(b, a.bounds(tb.inverse() * ta).inflated(margin), kids);
    int total = 0;
    for (uint32_t i : kids) {
      const CompoundChild& c = b.children()[i];
      Manifold m;
      if (!collideConvex(a, ta, *c.shape, tb * c.local, margin, m)) continue;
      m.childB = i;
      out.push_back(m);
      ++total;
    }
    return total;
  }
  Manifold m;
  if (!collideConvex(a, ta, b, tb, margin, m)) return 0;
  out.push_back(m);
  return 1;
}

}  // namespace grip
