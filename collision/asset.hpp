// grip's runtime asset for concave objects (written by `grip prep`, see docs/assets.md): a
// compound of boxes with exact mass properties and a narrow-band signed-distance field.
// Reading needs neither CGAL nor OpenVDB. Any corruption, truncation or version mismatch is
// refused with a grip::Error naming the problem.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "collision/sdf.hpp"
#include "collision/shape.hpp"
#include "core/mass.hpp"

namespace grip {

inline constexpr uint32_t kAssetVersion = 1;

struct AssetData {
  // Boxes on a voxel lattice: box b covers voxels [lo, hi) (voxel (i,j,k) is the cube of side
  // voxelSize centred at boxOrigin + voxelSize * (i,j,k)).
  struct Box {
    std::array<uint16_t, 3> lo{}, hi{};
  };
  double voxelSize = 0.0;
  Vec3 boxOrigin = Vec3::Zero();
  std::vector<Box> boxes;
  // Exact mass properties of the source mesh at `density` (inertia about com, asset frame).
  double density = 0.0;
  MassProperties mass;
  uint32_t sourceTriangles = 0;
  SignedDistanceField::Data sdf;

  Vec3 boxCenter(const Box& b) const;
  Vec3 boxHalfExtents(const Box& b) const;
  double boxVolume() const;  // sum of the boxes (they do not overlap)
};

// Serialisation (little-endian, FNV-1a 64 checksum over the payload).
std::vector<uint8_t> encodeAsset(const AssetData& a);
AssetData decodeAsset(const std::vector<uint8_t>& bytes);  // throws grip::Error
void writeAssetFile(const std::string& path, const AssetData& a);
AssetData readAssetFile(const std::string& path);  // throws grip::Error

struct LoadedAsset {
  ShapePtr shape;       // a compound of boxes (BVH built) carrying the SDF
  MassProperties mass;  // exact, of the source mesh, at the asset's density
  std::shared_ptr<const SignedDistanceField> sdf;
};
// Reads an asset file and builds the runtime shape.
LoadedAsset loadAsset(const std::string& path);
LoadedAsset makeAssetShape(const AssetData& a);

}  // namespace grip
