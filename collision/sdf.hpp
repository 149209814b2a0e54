// A narrow-band signed-distance field baked by the preprocessing tool (voxel/) and read from a
// runtime asset. It answers the hand-contact queries on concave objects: signed distance,
// smooth outward normal, closest surface point and ray casts, all in the compound's LOCAL frame.
//
// Storage: a lattice of samples (origin + spacing * (i, j, k)) cut into 4x4x4 bricks. Only
// bricks that touch the narrow band |d| < band are stored, as 8-bit fractions of the band
// (with the default 3-voxel band a step of 0.024 voxel, far below the interpolation error);
// every other brick is wholly outside or inside. Farther than the band, a sample takes its
// magnitude from a coarse, unclamped distance lattice (one node per brick corner) and its sign
// from the band data, so the field stays monotone and has a gradient everywhere: closest-point
// and normal queries work from any distance, exactly near the surface and approximately far
// from it. Outside the lattice the distance to the lattice box is added. Small bricks and 8-bit
// values keep assets small.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/math.hpp"

namespace grip {

class SignedDistanceField {
 public:
  static constexpr int kBrick = 4;         // samples per brick edge
  static constexpr int32_t kOutside = -1;  // brick index of a brick wholly outside the band
  static constexpr int32_t kInside = -2;   // ... wholly inside
  static constexpr double kQuantum = 127.0;

  // The raw data (also what the asset file stores). Validated by the constructor.
  struct Data {
    Vec3 origin = Vec3::Zero();    // position of sample (0,0,0)
    double spacing = 0.0;          // distance between samples
    std::array<int, 3> samples{};  // samples per axis (a multiple of kBrick)
    double band = 0.0;             // narrow-band half width (distances are clamped to it)
    std::vector<int32_t> bricks;   // per brick (x fastest): data index, kOutside or kInside
    std::vector<int8_t> values;    // kBrick^3 per stored brick (x fastest), d = v/kQuantum*band
    // Coarse lattice: node (I,J,K) at origin + kBrick*spacing*(I,J,K), samples/kBrick + 1 per
    // axis, x fastest: exact signed distances (not clamped to the band).
    std::vector<float> coarse;
  };

  // Throws grip::Error when the data is inconsistent.
  explicit SignedDistanceField(Data data);

  const Data& data() const { return d_; }
  double spacing() const { return d_.spacing; }
  // Bounds of the lattice (the surface lies inside, at least `band` from its faces).
  Aabb bounds() const { return bounds_; }

  // Signed distance: negative inside.
  double distance(const Vec3& local) const;
  // Outward unit normal: the normalised gradient (central differences at the samples,
  // interpolated trilinearly, so it varies smoothly across cells).
  Vec3 normal(const Vec3& local) const;
  // Distance and normal in one go (cheaper than calling both).
  double distanceAndNormal(const Vec3& local, Vec3& n) const;
  // The nearest point on the zero level set (Newton steps along the normal).
  Vec3 closestPoint(const Vec3& local) const;
  // First crossing of origin + t*dir (dir unit length), 0 <= t <= maxDistance. A ray that
  // starts inside hits at t = 0 with the normal at the origin.
  bool rayCast(const Vec3& origin, const Vec3& dir, double maxDistance, double& t, Vec3& n) const;

 private:
  double sample(int i, int j, int k) const;    // i, j, k clamped to the lattice
  double coarseAt(int i, int j, int k) const;  // coarse lattice interpolated at a sample
  double interior(const Vec3& local) const;    // trilinear, local clamped to the lattice
  Data d_;
  Aabb bounds_;
  std::array<int, 3> brickCount_{};
};

}  // namespace grip
