// Everything that needs OpenVDB, in one translation unit: the mesh-to-level-set conversion that
// gives both the interior voxels and the narrow-band signed distances, and the .vdb export.
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <mutex>

#include "core/error.hpp"
#include "voxel/voxel.hpp"

namespace grip::voxel {

DenseGrid signedDistanceLattice(const Mesh& mesh, const Vec3& origin, double spacing,
                                const std::array<int, 3>& size, double bandVoxels,
                                const std::string& vdbPath,
                                const std::function<void(double)>& progress) {
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  requirePositive(spacing, "voxel size");
  requirePositive(bandVoxels, "band");
  if (mesh.vertices.empty() || mesh.triangles.empty()) throw Error("mesh", "empty mesh");
  size_t total = 1;
  for (int n : size) {
    if (n < 1 || n > 4096) throw Error("lattice", "size out of range");
    total *= static_cast<size_t>(n);
  }
  // The mesh goes to OpenVDB relative to the lattice origin (sample (i,j,k) = index (i,j,k)),
  // so its single-precision points keep their precision wherever the mesh sits.
  std::vector<openvdb::Vec3s> points;
  points.reserve(mesh.vertices.size());
  for (const Vec3& p : mesh.vertices) {
    const Vec3 q = p - origin;
    points.emplace_back(static_cast<float>(q.x()), static_cast<float>(q.y()),
                        static_cast<float>(q.z()));
  }
  std::vector<openvdb::Vec3I> tris;
  tris.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    tris.emplace_back(static_cast<uint32_t>(t[0]), static_cast<uint32_t>(t[1]),
                      static_cast<uint32_t>(t[2]));

  // One thread: OpenVDB grows the narrow band from neighbouring voxels' closest triangles, so
  // with several threads the candidates a voxel sees (and the last bits of its distance) depend
  // on scheduling. Assets must be bit-identical from run to run.
  tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
  auto xform = openvdb::math::Transform::createLinearTransform(spacing);
  openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(
      *xform, points, tris, static_cast<float>(bandVoxels));
  if (progress) progress(0.5);

  // Dense sampling; deep interior and exterior read as -/+ background (the band width).
  DenseGrid g;
  g.origin = origin;
  g.spacing = spacing;
  g.size = size;
  const auto bg = static_cast<float>(bandVoxels * spacing);
  g.values.resize(total);
  auto acc = grid->getConstAccessor();
  size_t at = 0;
  for (int k = 0; k < size[2]; ++k) {
    for (int j = 0; j < size[1]; ++j)
      for (int i = 0; i < size[0]; ++i)
        g.values[at++] = std::clamp(acc.getValue(openvdb::Coord(i, j, k)), -bg, bg);
    if (progress && (k & 7) == 0) progress(0.5 + 0.5 * k / size[2]);
  }

  if (!vdbPath.empty()) {
    // Place the level set in the mesh's own frame for other tools.
    auto placed = openvdb::math::Transform::createLinearTransform(spacing);
    placed->postTranslate(openvdb::Vec3d(origin.x(), origin.y(), origin.z()));
    grid->setTransform(placed);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    grid->setName("sdf");
    try {
      openvdb::io::File file(vdbPath);
      file.write({grid});
      file.close();
    } catch (const std::exception& e) {
      throw Error(vdbPath, std::string("cannot write .vdb: ") + e.what());
    }
  }
  return g;
}

DenseGrid signedDistanceGrid(const Mesh& mesh, double spacing, double bandVoxels, int marginVoxels,
                             const std::string& vdbPath,
                             const std::function<void(double)>& progress) {
  requirePositive(spacing, "voxel size");
  if (mesh.vertices.empty()) throw Error("mesh", "empty mesh");
  Aabb box{mesh.vertices[0], mesh.vertices[0]};
  for (const Vec3& p : mesh.vertices) box = box.merged({p, p});
  // The first sample inside the bounds sits half a voxel in from the minimum corner, so voxel
  // faces line up with the mesh faces that touch the bounds there.
  const Vec3 origin = box.min - Vec3::Constant((marginVoxels - 0.5) * spacing);
  const Vec3 extent = box.extent() / spacing;
  std::array<int, 3> size{};
  for (int a = 0; a < 3; ++a) {
    // Cover the bounds plus the margin on both sides, in whole bricks.
    const double need = std::ceil(extent[a] + 2 * marginVoxels - 0.5) + 1;
    if (need > 2048)
      throw Error("voxel size",
                  "too small for this mesh: " + std::to_string(static_cast<long long>(need)) +
                      " samples along one axis (limit 2048)");
    constexpr int B = SignedDistanceField::kBrick;
    size[static_cast<size_t>(a)] = (static_cast<int>(need) + B - 1) / B * B;
  }
  return signedDistanceLattice(mesh, origin, spacing, size, bandVoxels, vdbPath, progress);
}

}  // namespace grip::voxel
