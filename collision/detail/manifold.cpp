#include "collision/detail/manifold.hpp"

#include <algorithm>
#include <limits>

namespace grip::detail {
namespace {

// The signs of a face's four corners along its two edge axes u and w, in loop order.
constexpr int kCornerU[4] = {-1, 1, 1, -1}, kCornerW[4] = {-1, -1, 1, 1};

// A box face's corners from its centre c and half-edge vectors eu, ew (along the axes after
// `axis`), CCW seen from outside, each with its vertex id: bit k set where the corner lies on
// the + side of box axis k. CCW about +axis because e_u x e_w = e_axis.
template <class Add>
void faceCorners(int axis, bool positive, const Vec3& c, const Vec3& eu, const Vec3& ew, Add add) {
  const int u = (axis + 1) % 3, w = (axis + 2) % 3;
  for (int corner = 0; corner < 4; ++corner) {
    const int k = positive ? corner : 3 - corner;
    uint32_t bits = positive ? (1u << axis) : 0u;
    if (kCornerU[k] > 0) bits |= 1u << u;
    if (kCornerW[k] > 0) bits |= 1u << w;
    add(c + eu * kCornerU[k] + ew * kCornerW[k], bits);
  }
}

// Faces of a box as vertex loops. Face 2k is +axis k, 2k+1 is -axis k. Built from the face
// centre and two edge vectors: no per-corner rotation.
void boxFace(const Shape& s, const Transform& t, const Mat3& R, int axis, bool positive,
             Feature& out) {
  const Vec3& h = s.halfExtents();
  const int u = (axis + 1) % 3, w = (axis + 2) % 3;
  const double sign = positive ? 1.0 : -1.0;
  out.normal = R.col(axis) * sign;
  const Vec3 c = t.p + out.normal * h[axis];
  out.count = 0;
  faceCorners(axis, positive, c, R.col(u) * h[u], R.col(w) * h[w],
              [&](const Vec3& p, uint32_t id) { out.add(p, id); });
  out.face = static_cast<uint32_t>(2 * axis + (positive ? 0 : 1));
}

}  // namespace

void supportingFeature(const Shape& s, const Transform& t, const Vec3& dir, Feature& out) {
  out.count = 0;
  out.face = 0;
  switch (s.type()) {
    case ShapeType::Box: {
      const Mat3 R = t.q.toRotationMatrix();
      const Vec3 dl = R.transpose() * dir;
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (std::abs(dl[k]) > std::abs(dl[axis])) axis = k;
      boxFace(s, t, R, axis, dl[axis] >= 0.0, out);
      return;
    }
    case ShapeType::Capsule: {
      const Vec3 d = t.rotateInverse(dir);
      // The whole segment when it lies (nearly) flat to the direction, else one end.
      const double c = d.y() / std::max(d.norm(), 1e-300);
      const Vec3 top = t.apply(Vec3(0.0, s.halfHeight(), 0.0));
      const Vec3 bottom = t.apply(Vec3(0.0, -s.halfHeight(), 0.0));
      if (std::abs(c) < 0.05) {
        out.add(bottom, 0);
        out.add(top, 1);
      } else if (c > 0.0) {
        out.add(top, 1);
      } else {
        out.add(bottom, 0);
      }
      return;
    }
    case ShapeType::ConvexHull: {
      const Vec3 d = t.rotateInverse(dir);
      const ConvexHullData& h = s.hull();
      // The face must contain the extreme vertex (the deepest point): among the faces around
      // that vertex take the one most aligned with d. The globally most aligned face can miss
      // it on irregular hulls.
      int sv = 0;
      for (int i = 1; i < static_cast<int>(h.vertices.size()); ++i)
        if (h.vertices[i].dot(d) > h.vertices[sv].dot(d)) sv = i;
      int best = -1;
      double bestD = -std::numeric_limits<double>::infinity();
      for (int f = 0; f < static_cast<int>(h.faces.size()); ++f) {
        const double x = h.faces[f].normal.dot(d);
        if (x <= bestD) continue;
        const auto& fv = h.faces[f].vertices;
        if (std::find(fv.begin(), fv.end(), sv) != fv.end()) bestD = x, best = f;
      }
      const auto& face = h.faces[best];
      // A face with more corners than the clipper holds (a finely tessellated cylinder cap)
      // is represented by evenly spaced corners: still convex, nearly the same area.
      const int nv = static_cast<int>(face.vertices.size());
      const int step = (nv + Feature::kMax - 1) / Feature::kMax;
      for (int i = 0; i < nv; i += step) {
        const int v = face.vertices[i];
        out.add(t.apply(h.vertices[v]), static_cast<uint32_t>(v));
      }
      out.normal = t.rotate(face.normal);
      out.face = static_cast<uint32_t>(best);
      return;
    }
    default:
      out.add(t.p, 0);
      return;  // sphere: its centre
  }
}

namespace {

struct ClipVertex {
  Vec3 p;
  uint32_t id;  // incident vertex id << 8 | (clipping side + 1, or 0)
};

constexpr int kMaxClip = 2 * Feature::kMax + 4;
constexpr double kTouchingBand = 1e-3;  // m: a point this close counts as touching
constexpr double kSamePoint = 1e-5;     // m: clipped points closer than this are one point

struct ClipList {
  int n = 0;
  std::array<ClipVertex, kMaxClip> v;
  void add(const Vec3& p, uint32_t id) {
    if (n < kMaxClip) v[n++] = {p, id};
  }
};

uint32_t crossingId(uint32_t from, int side) {
  return (from & ~0xFFu) | static_cast<uint32_t>((side + 1) & 0xFF);
}

// Sutherland-Hodgman against one side, keeping the points where dist(p) <= 0. A segment
// (2 points) is clipped as a segment, not as a closed loop.
template <class Dist>
void clipAgainst(const ClipList& in, Dist dist, int side, ClipList& out) {
  out.n = 0;
  if (in.n == 1) {
    if (dist(in.v[0].p) <= 0.0) out.add(in.v[0].p, in.v[0].id);
    return;
  }
  if (in.n == 2) {
    const double d0 = dist(in.v[0].p), d1 = dist(in.v[1].p);
    if (d0 > 0.0 && d1 > 0.0) return;
    // The crossing point is only formed when one end is outside (then d0 != d1).
    const Vec3 x = (d0 > 0.0 || d1 > 0.0)
                       ? Vec3(in.v[0].p + (in.v[1].p - in.v[0].p) * (d0 / (d0 - d1)))
                       : in.v[0].p;
    out.add(d0 <= 0.0 ? in.v[0].p : x, d0 <= 0.0 ? in.v[0].id : crossingId(in.v[0].id, side));
    out.add(d1 <= 0.0 ? in.v[1].p : x, d1 <= 0.0 ? in.v[1].id : crossingId(in.v[0].id, side));
    return;
  }
  std::array<double, kMaxClip> d;
  for (int i = 0; i < in.n; ++i) d[i] = dist(in.v[i].p);
  for (int i = 0, next = 1; i < in.n; ++i, ++next) {
    if (next == in.n) next = 0;
    const double da = d[i], db = d[next];
    if (da <= 0.0) out.add(in.v[i].p, in.v[i].id);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))
      out.add(in.v[i].p + (in.v[next].p - in.v[i].p) * (da / (da - db)),
              crossingId(in.v[i].id, side));
  }
}

// Signed area of triangle (a, b, c) projected on the plane normal to n.
double area(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n) {
  return (b - a).cross(c - a).dot(n);
}

}  // namespace

int reducePoints(const Vec3* p, const double* sep, int count, const Vec3& n,
                 std::array<int, 4>& keep, bool touchingFirst) {
  if (count <= 4) {
    for (int i = 0; i < count; ++i) keep[i] = i;
    return count;
  }
  // 1: deepest. 2: farthest from it. 3: largest triangle. 4: largest growth of the quad.
  // touchingFirst: each pick among the touching points (within kTouchingBand of contact)
  // while any are left, so a vertex across a gap does not displace one that bears the load (a
  // hull on the ground kept a vertex 15 mm up for one 6 mm deep, and rocked forever).
  int i0 = 0;
  for (int i = 1; i < count; ++i)
    if (sep[i] < sep[i0]) i0 = i;
  int touching = 0;
  if (touchingFirst)
    for (int i = 0; i < count; ++i) touching += sep[i] < kTouchingBand;
  auto eligible = [&](int i, int picked) {
    return picked < touching ? sep[i] < kTouchingBand : true;
  };
  int i1 = -1;
  double best = -1.0;
  for (int i = 0; i < count; ++i) {
    const double d = (p[i] - p[i0]).squaredNorm();
    if (i != i0 && eligible(i, 1) && d > best) best = d, i1 = i;
  }
  int i2 = -1;
  best = -1.0;
  for (int i = 0; i < count; ++i) {
    const double a = std::abs(area(p[i0], p[i1], p[i], n));
    if (i != i0 && i != i1 && eligible(i, 2) && a > best) best = a, i2 = i;
  }
  if (area(p[i0], p[i1], p[i2], n) < 0.0) std::swap(i1, i2);  // CCW about n
  int i3 = -1;
  best = 0.0;
  for (int i = 0; i < count; ++i) {
    if (i == i0 || i == i1 || i == i2 || !eligible(i, 3)) continue;
    // Area added outside the triangle's edges (negative areas are outside).
    const double a = -std::min(
        {area(p[i0], p[i1], p[i], n), area(p[i1], p[i2], p[i], n), area(p[i2], p[i0], p[i], n)});
    if (a > best) best = a, i3 = i;
  }
  int k = 0;
  keep[k++] = i0, keep[k++] = i1, keep[k++] = i2;
  if (i3 >= 0) keep[k++] = i3;
  std::sort(keep.begin(), keep.begin() + k);
  return k;
}

int clipFeatures(const Feature& ref, const Feature& inc, bool refIsA, double rRef, double rInc,
                 double margin, Manifold& m, const Vec3& along, bool touchingFirst) {
  ClipList a, b;
  for (int i = 0; i < inc.count; ++i) a.add(inc.p[i], inc.id[i] << 8);
  ClipList* in = &a;
  ClipList* out = &b;
  for (int j = 0; j < ref.count && in->n > 0; ++j) {
    const Vec3& r0 = ref.p[j];
    const Vec3& r1 = ref.p[(j + 1) % ref.count];
    const Vec3 sideN = (r1 - r0).cross(along);
    clipAgainst(
        *in, [&](const Vec3& p) { return (p - r0).dot(sideN); }, j, *out);
    std::swap(in, out);
  }
  // Depth of each clipped point below the reference face, along `along`, then keep those
  // within the margin.
  const double cosine = along.dot(ref.normal);
  std::array<Vec3, kMaxClip> pts;
  std::array<double, kMaxClip> seps;
  std::array<uint32_t, kMaxClip> ids;
  int count = 0;
  const uint32_t flip = refIsA ? 0u : 0x80000000u;
  for (int i = 0; i < in->n; ++i) {
    const double s = (in->v[i].p - ref.p[0]).dot(ref.normal) / cosine;
    const double sep = s - rRef - rInc;
    if (sep >= margin) continue;
    // A clip that collapses to a sliver (an incident corner just over the reference face's
    // corner) repeats a point; two points at one place make the solver's point system singular.
    const Vec3 p = in->v[i].p + along * (0.5 * (rRef - s - rInc));
    bool repeated = false;
    for (int j = 0; j < count && !repeated; ++j)
      repeated = (p - pts[j]).squaredNorm() < kSamePoint * kSamePoint;
    if (repeated) continue;
    pts[count] = p;
    seps[count] = sep;
    ids[count] = flip | ((ref.face & 0x7FFu) << 20) | (in->v[i].id & 0xFFFFFu);
    ++count;
  }
  std::array<int, 4> keep;
  const int k = reducePoints(pts.data(), seps.data(), count, along, keep, touchingFirst);
  for (int i = 0; i < k; ++i) {
    m.points[i].position = pts[keep[i]];
    m.points[i].separation = seps[keep[i]];
    m.points[i].featureId = ids[keep[i]];
  }
  m.pointCount = k;
  return k;
}

// Face against face of two boxes, in the reference box's frame, where the reference face's
// sides are axis-aligned: each side test is one subtraction instead of a dot product with a
// side normal (the general path, clipFeatures, was a third of a pile's narrowphase). The same
// corners, sides, order and feature ids as supportingFeature + clipFeatures.
int clipBoxFaces(const Vec3& hRef, const Mat3& refToWorld, const Vec3& refCentre, int axis,
                 bool positive, const Vec3& hInc, const Mat3& incAxes, const Vec3& incCentre,
                 bool refIsA, double margin, Manifold& m) {
  const double sign = positive ? 1.0 : -1.0;
  // The incident face: the one facing most against the reference normal.
  int ia = 0;
  double dl[3];
  for (int k = 0; k < 3; ++k) dl[k] = -sign * incAxes(axis, k);
  for (int k = 1; k < 3; ++k)
    if (std::abs(dl[k]) > std::abs(dl[ia])) ia = k;
  const bool incPositive = dl[ia] >= 0.0;
  const int iu = (ia + 1) % 3, iw = (ia + 2) % 3;
  const Vec3 c = incCentre + incAxes.col(ia) * ((incPositive ? 1.0 : -1.0) * hInc[ia]);
  ClipList bufA, bufB;
  ClipList *in = &bufA, *out = &bufB;
  faceCorners(ia, incPositive, c, incAxes.col(iu) * hInc[iu], incAxes.col(iw) * hInc[iw],
              [&](const Vec3& p, uint32_t id) { in->add(p, id << 8); });
  // The reference face's sides in faceCorners' order: side j joins corners j and j + 1, along
  // which one coordinate stays at +-h; it keeps s q[coord] <= h[coord].
  const int u = (axis + 1) % 3, w = (axis + 2) % 3;
  for (int j = 0; j < 4 && in->n > 0; ++j) {
    const int k0 = positive ? j : 3 - j, k1 = positive ? (j + 1) % 4 : 3 - (j + 1) % 4;
    const int coord = kCornerU[k0] == kCornerU[k1] ? u : w;
    const double s = coord == u ? kCornerU[k0] : kCornerW[k0], limit = hRef[coord];
    clipAgainst(
        *in, [&](const Vec3& q) { return s * q[coord] - limit; }, j, *out);
    std::swap(in, out);
  }
  // Depth below the reference face; the point halfway between the two surfaces, in the world.
  std::array<Vec3, kMaxClip> pts;
  std::array<double, kMaxClip> seps;
  std::array<uint32_t, kMaxClip> ids;
  int count = 0;
  const uint32_t flip = refIsA ? 0u : 0x80000000u;
  const uint32_t face = static_cast<uint32_t>(2 * axis + (positive ? 0 : 1));
  for (int i = 0; i < in->n; ++i) {
    const double sep = sign * in->v[i].p[axis] - hRef[axis];
    if (sep >= margin) continue;
    Vec3 q = in->v[i].p;
    q[axis] -= sign * 0.5 * sep;
    pts[count] = refCentre + refToWorld * q;
    seps[count] = sep;
    ids[count] = flip | (face << 20) | (in->v[i].id & 0xFFFFFu);
    ++count;
  }
  std::array<int, 4> keep;
  const int k = reducePoints(pts.data(), seps.data(), count, refToWorld.col(axis) * sign, keep);
  for (int i = 0; i < k; ++i) m.points[i] = {pts[keep[i]], seps[keep[i]], ids[keep[i]]};
  m.pointCount = k;
  return k;
}

}  // namespace grip::detail
