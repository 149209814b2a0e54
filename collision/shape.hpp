// Collision shapes. Shapes are immutable and shared (ShapePtr); a body holds one shape, and a
// compound holds child shapes at local transforms. Every convex shape may carry a rounding
// radius (a Minkowski sum with a sphere): that is how a shape is inflated by a margin.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/mass.hpp"
#include "core/math.hpp"

namespace grip {

enum class ShapeType : uint8_t { Sphere, Box, Capsule, ConvexHull, Plane, Compound };
const char* shapeTypeName(ShapeType t);

class Shape;
using ShapePtr = std::shared_ptr<const Shape>;
class SignedDistanceField;  // collision/sdf.hpp (baked by the voxel tool)

// A convex polyhedron: vertices, faces as vertex loops (counter-clockwise seen from outside)
// with outward unit normals, and unique edges. Built by quickhull from a point cloud.
struct ConvexHullData {
  struct Face {
    Vec3 normal;
    double offset = 0.0;  // normal . x = offset on the face plane
    std::vector<int> vertices;
  };
  std::vector<Vec3> vertices;
  std::vector<Face> faces;
  std::vector<std::array<int, 2>> edges;
  Vec3 centroid = Vec3::Zero();
};

struct CompoundChild {
  ShapePtr shape;
  Transform local;
};

// A bounding-volume hierarchy over a compound's children (built once, when the shape is made).
struct CompoundTree {
  struct Node {
    Aabb box;
    int32_t left = -1, right = -1;  // children nodes; both -1 for a leaf
    int32_t child = -1;             // compound child index for a leaf
  };
  std::vector<Node> nodes;  // nodes[0] is the root when not empty
  // Calls visit(childIndex) for each child whose bounds overlap `query` (in compound space),
  // in a fixed order.
  template <class F>
  void query(const Aabb& box, F&& visit) const;
};

class Shape {
 public:
  // Factories validate their arguments and throw grip::Error naming the bad one.
  static ShapePtr sphere(double radius);
  static ShapePtr box(const Vec3& halfExtents, double rounding = 0.0);
  // Along the local Y axis: segment from (0,-halfHeight,0) to (0,halfHeight,0), swept by radius.
  static ShapePtr capsule(double radius, double halfHeight);
  // Convex hull of at least 4 non-coplanar points.
  static ShapePtr convexHull(const std::vector<Vec3>& points, double rounding = 0.0);
  // A half space {x : normal . x <= offset}; static bodies only.
  static ShapePtr plane(const Vec3& normal, double offset);
  // Children may be any shape but planes and compounds. `sdf` is optional (voxel assets).
  static ShapePtr compound(std::vector<CompoundChild> children,
                           std::shared_ptr<const SignedDistanceField> sdf = nullptr);

  // The same shape grown by `margin` in every direction (rounding += margin; planes move out).
  ShapePtr inflated(double margin) const;

  ShapeType type() const { return type_; }
  bool isConvex() const { return type_ != ShapeType::Plane && type_ != ShapeType::Compound; }
  // Sphere radius, capsule radius or the rounding of a box or hull.
  double radius() const { return radius_; }
  const Vec3& halfExtents() const { return halfExtents_; }  // box
  double halfHeight() const { return halfHeight_; }         // capsule
  const Vec3& planeNormal() const { return planeNormal_; }
  double planeOffset() const { return planeOffset_; }
  const ConvexHullData& hull() const { return *hull_; }
  const std::vector<CompoundChild>& children() const { return children_; }
  const CompoundTree& tree() const { return tree_; }
  const SignedDistanceField* sdf() const { return sdf_.get(); }

  // Mass properties at uniform density (planes have none: static only). The rounding of a box
  // or hull is a thin contact skin and is ignored here: the mass is the core shape's.
  MassProperties massProperties(double density) const;
  // Bounds in the shape's own frame and under a transform (planes: a very large box).
  Aabb localBounds() const { return localBounds_; }
  Aabb bounds(const Transform& t) const;
  // Support point in local space: the farthest point along `dir` (rounding included).
  Vec3 support(const Vec3& dir) const;
  // The centre the thesis casts its contact ray toward (the shape's own centre).
  Vec3 localCenter() const;

 private:
  Shape() = default;
  ShapeType type_ = ShapeType::Sphere;
  double radius_ = 0.0;
  Vec3 halfExtents_ = Vec3::Zero();
  double halfHeight_ = 0.0;
  Vec3 planeNormal_ = Vec3::UnitY();
  double planeOffset_ = 0.0;
  std::shared_ptr<const ConvexHullData> hull_;
  std::vector<CompoundChild> children_;
  CompoundTree tree_;
  std::shared_ptr<const SignedDistanceField> sdf_;
  Aabb localBounds_;
  friend struct ShapeBuilder;
};

template <class F>
void CompoundTree::query(const Aabb& box, F&& visit) const {
  if (nodes.empty()) return;
  int32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes[stack[--top]];
    if (!n.box.overlaps(box)) continue;
    if (n.child >= 0) {
      visit(n.child);
    } else {
      if (top + 2 > 64) continue;  // depth is bounded by construction (median splits)
      stack[top++] = n.right;
      stack[top++] = n.left;
    }
  }
}

}  // namespace grip
