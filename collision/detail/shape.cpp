// Shape factories (validated), inflation, mass properties, bounds and support mapping.
#include "collision/shape.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <string>

#include "collision/detail/convex_hull.hpp"
#include "core/error.hpp"

namespace grip {

// Bounds of a plane: effectively unbounded, except on the side its normal points to when
// that normal is an axis (the usual ground plane gets a finite top).
static constexpr double kHuge = 1e15;

const char* shapeTypeName(ShapeType t) {
  switch (t) {
    case ShapeType::Sphere:
      return "sphere";
    case ShapeType::Box:
      return "box";
    case ShapeType::Capsule:
      return "capsule";
    case ShapeType::ConvexHull:
      return "convex hull";
    case ShapeType::Plane:
      return "plane";
    case ShapeType::Compound:
      return "compound";
  }
  return "unknown";
}

struct ShapeBuilder {
  static std::shared_ptr<Shape> make(ShapeType type) {
    std::shared_ptr<Shape> s(new Shape());
    s->type_ = type;
    return s;
  }
  static std::shared_ptr<Shape> copy(const Shape& from) {
    return std::shared_ptr<Shape>(new Shape(from));
  }

  static void computeBounds(Shape& s) {
    const double r = s.radius_;
    switch (s.type_) {
      case ShapeType::Sphere:
        s.localBounds_ = {Vec3::Constant(-r), Vec3::Constant(r)};
        break;
      case ShapeType::Box:
        s.localBounds_ = {-s.halfExtents_, s.halfExtents_};
        break;
      case ShapeType::Capsule: {
        const Vec3 e(0.0, s.halfHeight_, 0.0);
        s.localBounds_ = {-e, e};
        break;
      }
      case ShapeType::ConvexHull: {
        Aabb b{s.hull_->vertices[0], s.hull_->vertices[0]};
        for (const Vec3& v : s.hull_->vertices)
          b.min = b.min.cwiseMin(v), b.max = b.max.cwiseMax(v);
        s.localBounds_ = b;
        break;
      }
      case ShapeType::Plane: {
        Aabb b{Vec3::Constant(-kHuge), Vec3::Constant(kHuge)};
        for (int k = 0; k < 3; ++k) {
          if (s.planeNormal_[k] == 1.0) b.max[k] = s.planeOffset_;
          if (s.planeNormal_[k] == -1.0) b.min[k] = -s.planeOffset_;
        }
        s.localBounds_ = b;
        return;
      }
      case ShapeType::Compound: {
        Aabb b = s.children_[0].shape->bounds(s.children_[0].local);
        for (const auto& c : s.children_) b = b.merged(c.shape->bounds(c.local));
        s.localBounds_ = b;
        return;
      }
    }
    if (s.type_ != ShapeType::Sphere) s.localBounds_ = s.localBounds_.inflated(r);
  }

  // Median split along the widest axis of the child centres: depth ~ log2(n), far below the
  // query's 64-entry stack.
  static int32_t buildTree(Shape& s, std::vector<int32_t>& idx, size_t lo, size_t hi,
                           const std::vector<Aabb>& boxes) {
    CompoundTree::Node node;
    node.box = boxes[idx[lo]];
    for (size_t i = lo + 1; i < hi; ++i) node.box = node.box.merged(boxes[idx[i]]);
    const int32_t self = static_cast<int32_t>(s.tree_.nodes.size());
    s.tree_.nodes.push_back(node);
    if (hi - lo == 1) {
      s.tree_.nodes[self].child = idx[lo];
      return self;
    }
    Aabb centres{boxes[idx[lo]].center(), boxes[idx[lo]].center()};
    for (size_t i = lo; i < hi; ++i)
      centres = centres.merged({boxes[idx[i]].center(), boxes[idx[i]].center()});
    int axis = 0;
    const Vec3 ext = centres.extent();
    if (ext.y() > ext[axis]) axis = 1;
    if (ext.z() > ext[axis]) axis = 2;
    const size_t mid = (lo + hi) / 2;
    // Ties broken by child index so the split never depends on the sort's internals.
    std::nth_element(idx.begin() + static_cast<long>(lo), idx.begin() + static_cast<long>(mid),
                     idx.begin() + static_cast<long>(hi), [&](int32_t a, int32_t b) {
                       const double ca = boxes[a].center()[axis], cb = boxes[b].center()[axis];
                       return ca < cb || (ca == cb && a < b);
                     });
    const int32_t left = buildTree(s, idx, lo, mid, boxes);
    const int32_t right = buildTree(s, idx, mid, hi, boxes);
    s.tree_.nodes[self].left = left;
    s.tree_.nodes[self].right = right;
    return self;
  }

  static void buildCompound(Shape& s) {
    std::vector<Aabb> boxes;
    for (const auto& c : s.children_) boxes.push_back(c.shape->bounds(c.local));
    std::vector<int32_t> idx(boxes.size());
    std::iota(idx.begin(), idx.end(), 0);
    s.tree_.nodes.clear();
    s.tree_.nodes.reserve(2 * boxes.size());
    buildTree(s, idx, 0, idx.size(), boxes);
    computeBounds(s);
  }

  static ShapePtr inflate(const Shape& from, double margin) {
    auto s = copy(from);
    switch (s->type_) {
      case ShapeType::Plane:
        s->planeOffset_ += margin;
        break;
      case ShapeType::Compound:
        // Children grow; an SDF (if any) still describes the uninflated surface.
        for (auto& c : s->children_) c.shape = c.shape->inflated(margin);
        buildCompound(*s);
        return s;
      default:
        s->radius_ += margin;
        break;
    }
    computeBounds(*s);
    return s;
  }
};

ShapePtr Shape::sphere(double radius) {
  requirePositive(radius, "Shape::sphere.radius");
  auto s = ShapeBuilder::make(ShapeType::Sphere);
  s->radius_ = radius;
  ShapeBuilder::computeBounds(*s);
  return s;
}

ShapePtr Shape::box(const Vec3& halfExtents, double rounding) {
  for (int k = 0; k < 3; ++k) requirePositive(halfExtents[k], "Shape::box.halfExtents");
  requireNonNegative(rounding, "Shape::box.rounding");
  auto s = ShapeBuilder::make(ShapeType::Box);
  s->halfExtents_ = halfExtents;
  s->radius_ = rounding;
  ShapeBuilder::computeBounds(*s);
  return s;
}

ShapePtr Shape::capsule(double radius, double halfHeight) {
  requirePositive(radius, "Shape::capsule.radius");
  requirePositive(halfHeight, "Shape::capsule.halfHeight");
  auto s = ShapeBuilder::make(ShapeType::Capsule);
  s->radius_ = radius;
  s->halfHeight_ = halfHeight;
  ShapeBuilder::computeBounds(*s);
  return s;
}

ShapePtr Shape::convexHull(const std::vector<Vec3>& points, double rounding) {
  const char* field = "Shape::convexHull.points";
  if (points.size() < 4)
    throw Error(field, "needs at least 4 points (got " + std::to_string(points.size()) + ")");
  for (const Vec3& p : points) requireFinite(p, field);
  requireNonNegative(rounding, "Shape::convexHull.rounding");
  auto hull = std::make_shared<ConvexHullData>(detail::buildConvexHull(points, field));
  auto s = ShapeBuilder::make(ShapeType::ConvexHull);
  s->hull_ = hull;
  // The centre of volume is a better "centre" than the vertex average (rays aim at it).
  hull->centroid = s->massProperties(1.0).com;
  s->radius_ = rounding;
  ShapeBuilder::computeBounds(*s);
  return s;
}

ShapePtr Shape::plane(const Vec3& normal, double offset) {
  requireFinite(normal, "Shape::plane.normal");
  requireFinite(offset, "Shape::plane.offset");
  const double len = normal.norm();
  if (!(len > 1e-12)) throw Error("Shape::plane.normal", "must be non-zero");
  auto s = ShapeBuilder::make(ShapeType::Plane);
  s->planeNormal_ = normal / len;
  s->planeOffset_ = offset / len;  // keeps the same set {x : normal . x <= offset}
  // Snap an axis normal exactly so its bounds are finite on the top side.
  for (int k = 0; k < 3; ++k)
    if (std::abs(s->planeNormal_[k]) == 1.0) s->planeNormal_ = Vec3::Unit(k) * s->planeNormal_[k];
  ShapeBuilder::computeBounds(*s);
  return s;
}

ShapePtr Shape::compound(std::vector<CompoundChild> children,
                         std::shared_ptr<const SignedDistanceField> sdf) {
  if (children.empty()) throw Error("Shape::compound.children", "must not be empty");
  for (size_t i = 0; i < children.size(); ++i) {
    const std::string field = "Shape::compound.children[" + std::to_string(i) + "]";
    auto& c = children[i];
    if (!c.shape) throw Error(field + ".shape", "must not be null");
    if (c.shape->type() == ShapeType::Plane || c.shape->type() == ShapeType::Compound)
      throw Error(field + ".shape",
                  std::string("a compound cannot hold a ") + shapeTypeName(c.shape->type()));
    requireFinite(c.local.p, (field + ".local.p").c_str());
    requireFinite(c.local.q, (field + ".local.q").c_str());
    c.local.q.normalize();
  }
  auto s = ShapeBuilder::make(ShapeType::Compound);
  s->children_ = std::move(children);
  s->sdf_ = std::move(sdf);
  ShapeBuilder::buildCompound(*s);
  return s;
}

ShapePtr Shape::inflated(double margin) const {
  requireNonNegative(margin, "Shape::inflated.margin");
  return ShapeBuilder::inflate(*this, margin);
}

// Rounding of boxes and hulls is ignored here: the mass is that of the core shape (the
// rounding is a thin contact skin, a few millimetres at most).
MassProperties Shape::massProperties(double density) const {
  requirePositive(density, "Shape::massProperties.density");
  switch (type_) {
    case ShapeType::Sphere:
      return sphereMass(radius_, density);
    case ShapeType::Box:
      return boxMass(halfExtents_, density);
    case ShapeType::Capsule:
      return capsuleMass(radius_, halfHeight_, density);
    case ShapeType::ConvexHull: {
      std::vector<std::array<int, 3>> tris;
      for (const auto& f : hull_->faces)
        for (size_t i = 1; i + 1 < f.vertices.size(); ++i)
          tris.push_back({f.vertices[0], f.vertices[i], f.vertices[i + 1]});
      return meshMass(hull_->vertices, tris, density);
    }
    case ShapeType::Plane:
      return MassProperties{};
    case ShapeType::Compound: {
      MassProperties total;
      std::vector<MassProperties> parts;
      for (const auto& c : children_) {
        MassProperties m = c.shape->massProperties(density);
        m.com = c.local.apply(m.com);
        m.inertia = rotateInertia(m.inertia, c.local.q);
        total.mass += m.mass;
        total.volume += m.volume;
        total.com += m.mass * m.com;
        parts.push_back(m);
      }
      total.com /= total.mass;
      for (const auto& m : parts)
        total.inertia += shiftInertia(m.inertia, m.mass, m.com - total.com);
      return total;
    }
  }
  return MassProperties{};
}

Aabb Shape::bounds(const Transform& t) const {
  if (type_ == ShapeType::Sphere)
    return {t.p - Vec3::Constant(radius_), t.p + Vec3::Constant(radius_)};
  if (type_ == ShapeType::Capsule) {
    const Vec3 axis = t.rotate(Vec3(0.0, halfHeight_, 0.0));
    const Vec3 a = t.p - axis, b = t.p + axis;
    return Aabb{a.cwiseMin(b), a.cwiseMax(b)}.inflated(radius_);
  }
  // Rotated box around the local bounds: |R| maps half extents to world half extents.
  const Mat3 absR = t.q.toRotationMatrix().cwiseAbs();
  const Vec3 c = t.apply(localBounds_.center());
  const Vec3 e = absR * (0.5 * localBounds_.extent());
  return {c - e, c + e};
}

Vec3 Shape::support(const Vec3& dir) const {
  const double len = dir.norm();
  const Vec3 n = len > 0.0 ? Vec3(dir / len) : Vec3(Vec3::UnitX());
  auto sgn = [](double x) { return x >= 0.0 ? 1.0 : -1.0; };
  switch (type_) {
    case ShapeType::Sphere:
      return radius_ * n;
    case ShapeType::Box:
      return Vec3(sgn(n.x()) * halfExtents_.x(), sgn(n.y()) * halfExtents_.y(),
                  sgn(n.z()) * halfExtents_.z()) +
             radius_ * n;
    case ShapeType::Capsule:
      return Vec3(0.0, sgn(n.y()) * halfHeight_, 0.0) + radius_ * n;
    case ShapeType::ConvexHull: {
      int best = 0;
      double bestD = -std::numeric_limits<double>::infinity();
      for (int i = 0; i < static_cast<int>(hull_->vertices.size()); ++i) {
        const double d = hull_->vertices[i].dot(n);
        if (d > bestD) bestD = d, best = i;
      }
      return hull_->vertices[best] + radius_ * n;
    }
    case ShapeType::Plane: {
      // The plane is unbounded: a far point in the direction, clamped to the half space.
      Vec3 x = n * kHuge;
      const double h = planeNormal_.dot(x) - planeOffset_;
      if (h > 0.0) x -= h * planeNormal_;
      return x;
    }
    case ShapeType::Compound: {
      Vec3 best = Vec3::Zero();
      double bestD = -std::numeric_limits<double>::infinity();
      for (const auto& c : children_) {
        const Vec3 p = c.local.apply(c.shape->support(c.local.rotateInverse(n)));
        if (p.dot(n) > bestD) bestD = p.dot(n), best = p;
      }
      return best;
    }
  }
  return Vec3::Zero();
}

Vec3 Shape::localCenter() const {
  switch (type_) {
    case ShapeType::ConvexHull:
      return hull_->centroid;
    case ShapeType::Plane:
      return planeNormal_ * planeOffset_;
    case ShapeType::Compound:
      return localBounds_.center();
    default:
      return Vec3::Zero();
  }
}

}  // namespace grip
