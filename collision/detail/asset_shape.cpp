// Building the runtime shape of an asset (kept apart from the file format so that the format
// can be used where only data is needed).
#include <map>

#include "collision/asset.hpp"

namespace grip {

LoadedAsset makeAssetShape(const AssetData& a) {
  LoadedAsset out;
  out.sdf = std::make_shared<const SignedDistanceField>(a.sdf);
  // Boxes of the same size share one shape (an ordered map keeps construction deterministic).
  std::map<std::array<int, 3>, ShapePtr> bySize;
  std::vector<CompoundChild> children;
  children.reserve(a.boxes.size());
  for (const auto& b : a.boxes) {
    const std::array<int, 3> size{b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]};
    auto it = bySize.find(size);
    if (it == bySize.end()) it = bySize.emplace(size, Shape::box(a.boxHalfExtents(b))).first;
    CompoundChild c;
    c.shape = it->second;
    c.local.p = a.boxCenter(b);
    children.push_back(std::move(c));
  }
  out.shape = Shape::compound(std::move(children), out.sdf);
  out.mass = a.mass;
  return out;
}

LoadedAsset loadAsset(const std::string& path) {
  return makeAssetShape(readAssetFile(path));
}

}  // namespace grip
