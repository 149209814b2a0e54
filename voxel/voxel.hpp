// grip's offline preprocessing of concave objects (thesis 3.7): mesh loading, validation and
// repair (CGAL), exact mass properties, voxelization and a narrow-band signed-distance field
// (OpenVDB), interior voxels merged into boxes, and the runtime asset (collision/asset.hpp).
// CGAL and OpenVDB stay private to this library; applications that only simulate never link it.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "collision/asset.hpp"
#include "core/math.hpp"

namespace grip::voxel {

// An indexed triangle mesh. After loadMesh/repairMesh: closed, manifold, outward oriented.
struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

struct RepairOptions {
  bool fillHoles = true;                // close open boundaries by triangulating the holes
  bool allowSelfIntersections = false;  // otherwise a self-intersecting mesh is refused
};

// What loading and repairing found and did (one line per item, for the summary).
struct MeshReport {
  size_t inputVertices = 0;
  size_t inputFaces = 0;
  std::vector<std::string> repairs;   // e.g. "merged 12 duplicate vertices"
  std::vector<std::string> warnings;  // e.g. "3 zero-area faces kept (they add no volume)"
};

// Reads OFF, OBJ, STL or PLY (by extension) and repairs it. Throws grip::Error with a one-line
// message naming the problem (unknown format, unreadable/truncated, empty, non-finite, absurd
// size, non-manifold, open and not closable, self-intersecting, no volume).
Mesh loadMesh(const std::string& path, const RepairOptions& options = {},
              MeshReport* report = nullptr);
// The same validation and repair for a mesh already in memory.
Mesh repairMesh(const Mesh& mesh, const RepairOptions& options = {}, MeshReport* report = nullptr);
// Writes a mesh as OFF or OBJ (by extension), 9 significant digits.
void writeMesh(const std::string& path, const Mesh& mesh);

// Level of detail: voxels across the longest side of the mesh's bounding box.
enum class Lod { Low, Medium, High, VeryHigh };
int lodResolution(Lod lod);             // 16, 32, 64, 128
const char* lodName(Lod lod);           // "low", "medium", "high", "very-high"
Lod parseLod(const std::string& name);  // throws grip::Error

struct PrepOptions {
  Lod lod = Lod::High;
  double voxelSize = 0.0;   // > 0 overrides the LOD
  double density = 1000.0;  // kg/m^3
  double bandVoxels = 3.0;  // narrow-band half width of the SDF, in SDF samples
  // The SDF's sample spacing is the voxel size, but no finer than the longest side / this
  // (0: always the voxel size). Keeps very-high assets small; the SDF's accuracy is set by its
  // own spacing, the boxes' by the voxel size.
  int sdfMaxResolution = 48;
  std::string vdbPath;  // if set, also write the SDF as an OpenVDB level set
  // Progress: stage name and fraction done in [0, 1] (called from the calling thread).
  std::function<void(const std::string& stage, double fraction)> progress;
};

struct PrepStats {
  size_t triangles = 0;
  size_t voxels = 0;  // interior voxels
  size_t boxes = 0;
  double exactVolume = 0.0;
  double voxelVolume = 0.0;  // of the boxes
  double volumeError() const { return (voxelVolume - exactVolume) / exactVolume; }
  std::array<int, 3> gridSize{};  // voxels per axis
  double sdfSpacing = 0.0;
  size_t sdfBricks = 0;  // stored (narrow-band) bricks
  double seconds = 0.0;
};

// Turns a repaired mesh into a runtime asset. Deterministic: the same mesh and options give a
// bit-identical asset.
AssetData prepare(const Mesh& mesh, const PrepOptions& options, PrepStats* stats = nullptr);

// Writes the boxes of an asset as an OBJ (one cube per box), for standard viewers.
void exportBoxesObj(const std::string& path, const AssetData& asset);

// ---- building blocks (exposed for tests and benchmarks) ----

// A dense lattice of samples: value(i,j,k) at origin + spacing*(i,j,k), x fastest.
struct DenseGrid {
  Vec3 origin = Vec3::Zero();
  double spacing = 0.0;
  std::array<int, 3> size{};
  std::vector<float> values;
  float at(int i, int j, int k) const {
    return values[static_cast<size_t>(i) +
                  static_cast<size_t>(size[0]) *
                      (static_cast<size_t>(j) +
                       static_cast<size_t>(size[1]) * static_cast<size_t>(k))];
  }
};

// Signed distance of a closed mesh sampled on a lattice of the given spacing that covers the
// mesh plus `marginVoxels` on every side (OpenVDB mesh-to-volume; exact distances within
// `bandVoxels` of the surface, +-band beyond; negative inside).
DenseGrid signedDistanceGrid(const Mesh& mesh, double spacing, double bandVoxels, int marginVoxels,
                             const std::string& vdbPath = {},
                             const std::function<void(double)>& progress = {});

// The same on a given lattice (no rounding, no margin).
DenseGrid signedDistanceLattice(const Mesh& mesh, const Vec3& origin, double spacing,
                                const std::array<int, 3>& size, double bandVoxels,
                                const std::string& vdbPath = {},
                                const std::function<void(double)>& progress = {});

// Greedy merging of occupied voxels into disjoint boxes: from the first free occupied voxel in
// x-y-z scan order, grow along x, then y, then z while every voxel is occupied and free.
std::vector<AssetData::Box> mergeVoxels(const std::vector<uint8_t>& occupied,
                                        const std::array<int, 3>& size);

// The same mesh in a canonical order: vertices sorted by position, each triangle starting at
// its smallest index (orientation kept), triangles sorted. CGAL's output order can depend on
// memory addresses; canonical order makes every later step (and the asset) deterministic.
Mesh canonicalMesh(Mesh mesh);

// Built-in procedural objects (metres, Y up): "mug", "axe", "torus", "l-block", "figurine".
// Primitives are joined with CGAL's exact corefinement, so the results are closed and manifold.
std::vector<std::string> builtinNames();
Mesh builtinMesh(const std::string& name);

// Union of closed meshes (CGAL corefinement). Throws grip::Error if CGAL cannot do it.
Mesh meshUnion(const std::vector<Mesh>& parts);

}  // namespace grip::voxel
