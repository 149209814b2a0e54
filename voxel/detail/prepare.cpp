// The preparation pipeline (plain C++; CGAL and OpenVDB are behind voxel.hpp's functions):
// exact mass properties, signed-distance lattice, interior voxels merged into boxes, SDF bricks.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>

#include "core/error.hpp"
#include "core/mass.hpp"
#include "voxel/voxel.hpp"

namespace grip::voxel {

int lodResolution(Lod lod) {
  switch (lod) {
    case Lod::Low:
      return 16;
    case Lod::Medium:
      return 32;
    case Lod::High:
      return 64;
    case Lod::VeryHigh:
      return 128;
  }
  return 64;
}

const char* lodName(Lod lod) {
  switch (lod) {
    case Lod::Low:
      return "low";
    case Lod::Medium:
      return "medium";
    case Lod::High:
      return "high";
    case Lod::VeryHigh:
      return "very-high";
  }
  return "high";
}

Lod parseLod(const std::string& name) {
  for (Lod l : {Lod::Low, Lod::Medium, Lod::High, Lod::VeryHigh})
    if (name == lodName(l)) return l;
  throw Error("lod", "unknown level of detail '" + name + "' (low, medium, high, very-high)");
}

std::vector<AssetData::Box> mergeVoxels(const std::vector<uint8_t>& occupied,
                                        const std::array<int, 3>& n) {
  const size_t total =
      static_cast<size_t>(n[0]) * static_cast<size_t>(n[1]) * static_cast<size_t>(n[2]);
  if (occupied.size() != total) throw Error("mergeVoxels", "occupancy size mismatch");
  if (n[0] > 65535 || n[1] > 65535 || n[2] > 65535)
    throw Error("mergeVoxels", "lattice too large for 16-bit box coordinates");
  auto index = [&](const std::array<int, 3>& c) {
    return static_cast<size_t>(c[0]) +
           static_cast<size_t>(n[0]) *
               (static_cast<size_t>(c[1]) + static_cast<size_t>(n[1]) * static_cast<size_t>(c[2]));
  };
  std::vector<uint8_t> free = occupied;  // occupied and not yet in a box
  // Is the slab lo..hi (hi exclusive) with axis `a` fixed at `at` all free?
  auto slabFree = [&](std::array<int, 3> lo, std::array<int, 3> hi, int a, int at) {
    lo[a] = at, hi[a] = at + 1;
    std::array<int, 3> c;
    for (c[2] = lo[2]; c[2] < hi[2]; ++c[2])
      for (c[1] = lo[1]; c[1] < hi[1]; ++c[1])
        for (c[0] = lo[0]; c[0] < hi[0]; ++c[0])
          if (!free[index(c)]) return false;
    return true;
  };
  // Grow orders tried from each seed; the box of largest volume wins (ties: first order).
  static constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                        {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::vector<AssetData::Box> boxes;
  std::array<int, 3> s;
  for (s[2] = 0; s[2] < n[2]; ++s[2])
    for (s[1] = 0; s[1] < n[1]; ++s[1])
      for (s[0] = 0; s[0] < n[0]; ++s[0]) {
        if (!free[index(s)]) continue;
        std::array<int, 3> bestHi{};
        long long bestVolume = -1;
        for (const auto& order : kOrders) {
          std::array<int, 3> hi{s[0] + 1, s[1] + 1, s[2] + 1};
          for (int a : order)
            while (hi[a] < n[a] && slabFree(s, hi, a, hi[a])) ++hi[a];
          const long long v = 1LL * (hi[0] - s[0]) * (hi[1] - s[1]) * (hi[2] - s[2]);
          if (v > bestVolume) bestVolume = v, bestHi = hi;
        }
        std::array<int, 3> c;
        for (c[2] = s[2]; c[2] < bestHi[2]; ++c[2])
          for (c[1] = s[1]; c[1] < bestHi[1]; ++c[1])
            for (c[0] = s[0]; c[0] < bestHi[0]; ++c[0]) free[index(c)] = 0;
        AssetData::Box b;
        for (int a = 0; a < 3; ++a) {
          b.lo[static_cast<size_t>(a)] = static_cast<uint16_t>(s[a]);
          b.hi[static_cast<size_t>(a)] = static_cast<uint16_t>(bestHi[a]);
        }
        boxes.push_back(b);
      }
  return boxes;
}

namespace {

// Cuts the dense lattice into bricks; keeps (quantised) only those that touch the band; adds the
// coarse unclamped lattice (one node per brick corner) for queries beyond the band.
SignedDistanceField::Data makeSdf(const Mesh& mesh, const DenseGrid& g, double band) {
  constexpr int B = SignedDistanceField::kBrick;
  SignedDistanceField::Data s;
  s.origin = g.origin;
  s.spacing = g.spacing;
  s.samples = g.size;
  s.band = band;
  const int nb[3] = {g.size[0] / B, g.size[1] / B, g.size[2] / B};
  s.bricks.assign(
      static_cast<size_t>(nb[0]) * static_cast<size_t>(nb[1]) * static_cast<size_t>(nb[2]),
      SignedDistanceField::kOutside);
  // The lattice holds floats clamped to the band: compare with a hair less than the band so a
  // clamped value (rounded to float) never counts as inside it.
  const double inBand = band * (1.0 - 1e-6);
  size_t at = 0;
  int32_t stored = 0;
  for (int bz = 0; bz < nb[2]; ++bz)
    for (int by = 0; by < nb[1]; ++by)
      for (int bx = 0; bx < nb[0]; ++bx, ++at) {
        bool touches = false, inside = false;
        for (int z = 0; z < B && !touches; ++z)
          for (int y = 0; y < B && !touches; ++y)
            for (int x = 0; x < B && !touches; ++x) {
              const double v = g.at(bx * B + x, by * B + y, bz * B + z);
              if (std::abs(v) < inBand) touches = true;
              inside = v < 0.0;
            }
        if (!touches) {
          s.bricks[at] = inside ? SignedDistanceField::kInside : SignedDistanceField::kOutside;
          continue;
        }
        s.bricks[at] = stored++;
        for (int z = 0; z < B; ++z)
          for (int y = 0; y < B; ++y)
            for (int x = 0; x < B; ++x) {
              const double v = g.at(bx * B + x, by * B + y, bz * B + z);
              const double q = std::clamp(v / band, -1.0, 1.0) * SignedDistanceField::kQuantum;
              s.values.push_back(static_cast<int8_t>(std::lround(q)));
            }
      }
  const std::array<int, 3> coarseSize{nb[0] + 1, nb[1] + 1, nb[2] + 1};
  // A band as wide as the coarse lattice: every node gets its true signed distance.
  const double wide = 2.0 * std::max({coarseSize[0], coarseSize[1], coarseSize[2]}) + 2.0;
  const DenseGrid c = signedDistanceLattice(mesh, g.origin, B * g.spacing, coarseSize, wide);
  s.coarse = c.values;
  return s;
}

}  // namespace

AssetData prepare(const Mesh& mesh, const PrepOptions& opt, PrepStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  requirePositive(opt.density, "density");
  requirePositive(opt.bandVoxels, "band");
  if (mesh.triangles.empty()) throw Error("mesh", "empty mesh");
  auto progress = [&](const char* stage, double f) {
    if (opt.progress) opt.progress(stage, f);
  };

  progress("mass properties", 0.0);
  AssetData a;
  a.density = opt.density;
  a.mass = meshMass(mesh.vertices, mesh.triangles, opt.density);
  if (!(a.mass.volume > 0.0)) throw Error("mesh", "encloses no volume (not closed or inside out)");
  a.sourceTriangles = static_cast<uint32_t>(mesh.triangles.size());

  Aabb box{mesh.vertices[0], mesh.vertices[0]};
  for (const Vec3& p : mesh.vertices) box = box.merged({p, p});
  const double h =
      opt.voxelSize > 0.0 ? opt.voxelSize : box.extent().maxCoeff() / lodResolution(opt.lod);
  requirePositive(h, "voxel size");

  progress("voxelizing", 0.0);
  // The lattice reaches past the band so that distance queries around the object stay on it
  // (past the lattice only the distance to its box is added).
  const int margin = static_cast<int>(std::ceil(opt.bandVoxels)) + 1 + SignedDistanceField::kBrick;
  double hs = h;
  if (opt.sdfMaxResolution > 0) hs = std::max(h, box.extent().maxCoeff() / opt.sdfMaxResolution);
  const bool sameLattice = hs == h;
  const DenseGrid g =
      signedDistanceGrid(mesh, h, opt.bandVoxels, margin, sameLattice ? opt.vdbPath : std::string(),
                         [&](double f) { progress("voxelizing", f); });

  progress("merging boxes", 0.0);
  std::vector<uint8_t> occupied(g.values.size());
  size_t voxels = 0;
  for (size_t i = 0; i < g.values.size(); ++i) {
    occupied[i] = g.values[i] < 0.0f ? 1 : 0;
    voxels += occupied[i];
  }
  if (voxels == 0)
    throw Error("voxel size",
                "too coarse for this mesh: no voxel centre lies inside it (the "
                "object is thinner than a voxel; use a finer --lod or --voxel)");
  a.voxelSize = h;
  a.boxOrigin = g.origin;
  a.boxes = mergeVoxels(occupied, g.size);

  progress("distance field", 0.0);
  if (sameLattice) {
    a.sdf = makeSdf(mesh, g, opt.bandVoxels * h);
  } else {
    const DenseGrid gs = signedDistanceGrid(mesh, hs, opt.bandVoxels, margin, opt.vdbPath,
                                            [&](double f) { progress("distance field", f); });
    a.sdf = makeSdf(mesh, gs, opt.bandVoxels * hs);
  }
  progress("done", 1.0);

  if (stats) {
    stats->triangles = mesh.triangles.size();
    stats->voxels = voxels;
    stats->boxes = a.boxes.size();
    stats->exactVolume = a.mass.volume;
    stats->voxelVolume = a.boxVolume();
    for (int i = 0; i < 3; ++i)
      stats->gridSize[static_cast<size_t>(i)] = g.size[static_cast<size_t>(i)];
    stats->sdfSpacing = a.sdf.spacing;
    stats->sdfBricks =
        a.sdf.values.size() /
        (SignedDistanceField::kBrick * SignedDistanceField::kBrick * SignedDistanceField::kBrick);
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return a;
}

void exportBoxesObj(const std::string& path, const AssetData& a) {
  std::ofstream f(path);
  if (!f) throw Error(path, "cannot open for writing");
  f << "# grip voxel boxes: " << a.boxes.size() << " boxes, voxel size " << a.voxelSize << "\n";
  f << std::setprecision(9);
  size_t base = 1;
  for (const auto& b : a.boxes) {
    const Vec3 c = a.boxCenter(b), e = a.boxHalfExtents(b);
    for (int i = 0; i < 8; ++i) {
      const Vec3 p =
          c + Vec3((i & 1) ? e.x() : -e.x(), (i & 2) ? e.y() : -e.y(), (i & 4) ? e.z() : -e.z());
      f << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    }
    // Corner i has bits (x, y, z); faces counter-clockwise seen from outside.
    static constexpr int kFaces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : kFaces)
      f << "f " << base + q[0] << ' ' << base + q[1] << ' ' << base + q[2] << ' ' << base + q[3]
        << '\n';
    base += 8;
  }
  if (!f) throw Error(path, "write failed");
}

}  // namespace grip::voxel
