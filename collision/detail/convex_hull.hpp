// Private: quickhull over a point cloud, with coplanar triangles merged into polygons.
#pragma once

#include <vector>

#include "collision/shape.hpp"

namespace grip::detail {

// Builds the hull of `points` (validated finite, at least 4). Throws grip::Error("field", ...)
// when the points are coincident, collinear or coplanar.
ConvexHullData buildConvexHull(const std::vector<Vec3>& points, const char* field);

}  // namespace grip::detail
