#include "collision/sdf.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace grip {

namespace {
constexpr int kB = SignedDistanceField::kBrick;
constexpr int kMaxSamples = 4096;  // per axis; far beyond any sane asset
}  // namespace

SignedDistanceField::SignedDistanceField(Data data) : d_(std::move(data)) {
  if (!isFinite(d_.origin)) throw Error("sdf.origin", "must be finite");
  requirePositive(d_.spacing, "sdf.spacing");
  requirePositive(d_.band, "sdf.band");
  size_t brickTotal = 1;
  for (int a = 0; a < 3; ++a) {
    const int n = d_.samples[a];
    if (n < kB || n > kMaxSamples || n % kB != 0)
      throw Error("sdf.samples", "must be a multiple of " + std::to_string(kB) + " in [" +
                                     std::to_string(kB) + ", " + std::to_string(kMaxSamples) +
                                     "] (got " + std::to_string(n) + ")");
    brickCount_[a] = n / kB;
    brickTotal *= static_cast<size_t>(brickCount_[a]);
  }
  if (d_.bricks.size() != brickTotal)
    throw Error("sdf.bricks", "has " + std::to_string(d_.bricks.size()) + " entries, expected " +
                                  std::to_string(brickTotal));
  const size_t brickSize = static_cast<size_t>(kB * kB * kB);
  if (d_.values.size() % brickSize != 0)
    throw Error("sdf.values", "size is not a whole number of bricks");
  const auto stored = static_cast<int64_t>(d_.values.size() / brickSize);
  for (int32_t b : d_.bricks)
    if (b != kOutside && b != kInside && (b < 0 || b >= stored))
      throw Error("sdf.bricks", "brick index " + std::to_string(b) + " out of range");
  const size_t coarseTotal = static_cast<size_t>(brickCount_[0] + 1) *
                             static_cast<size_t>(brickCount_[1] + 1) *
                             static_cast<size_t>(brickCount_[2] + 1);
  if (d_.coarse.size() != coarseTotal)
    throw Error("sdf.coarse", "has " + std::to_string(d_.coarse.size()) + " nodes, expected " +
                                  std::to_string(coarseTotal));
  for (float v : d_.coarse)
    if (!std::isfinite(v)) throw Error("sdf.coarse", "must be finite");
  bounds_.min = d_.origin;
  bounds_.max =
      d_.origin + d_.spacing * Vec3(d_.samples[0] - 1, d_.samples[1] - 1, d_.samples[2] - 1);
}

double SignedDistanceField::sample(int i, int j, int k) const {
  i = std::clamp(i, 0, d_.samples[0] - 1);
  j = std::clamp(j, 0, d_.samples[1] - 1);
  k = std::clamp(k, 0, d_.samples[2] - 1);
  const int32_t b = d_.bricks[static_cast<size_t>(
      i / kB + brickCount_[0] * (j / kB + brickCount_[1] * (k / kB)))];
  double sign = b == kInside ? -1.0 : 1.0;
  if (b >= 0) {
    const size_t at = static_cast<size_t>(b) * (kB * kB * kB) +
                      static_cast<size_t>(i % kB + kB * (j % kB + kB * (k % kB)));
    const int v = d_.values[at];
    if (v > -kQuantum && v < kQuantum) return v * (d_.band / kQuantum);  // within the band
    sign = v < 0 ? -1.0 : 1.0;
  }
  // Beyond the band: the band data knows the sign, the coarse lattice the magnitude.
  return sign * std::max(d_.band, std::abs(coarseAt(i, j, k)));
}

double SignedDistanceField::coarseAt(int i, int j, int k) const {
  const int n[3] = {brickCount_[0] + 1, brickCount_[1] + 1, brickCount_[2] + 1};
  const int c[3] = {i / kB, j / kB, k / kB};
  const double f[3] = {(i % kB) / double(kB), (j % kB) / double(kB), (k % kB) / double(kB)};
  auto node = [&](int x, int y, int z) {
    return static_cast<double>(d_.coarse[static_cast<size_t>(
        std::min(x, n[0] - 1) + n[0] * (std::min(y, n[1] - 1) + n[1] * std::min(z, n[2] - 1)))]);
  };
  double v = 0.0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        v += (dx ? f[0] : 1.0 - f[0]) * (dy ? f[1] : 1.0 - f[1]) * (dz ? f[2] : 1.0 - f[2]) *
             node(c[0] + dx, c[1] + dy, c[2] + dz);
  return v;
}

namespace {
// Lattice coordinates of a point clamped to the lattice: cell index and fraction per axis.
struct Cell {
  int i[3];
  double f[3];
};
Cell locate(const Vec3& u, const std::array<int, 3>& n) {
  Cell c;
  for (int a = 0; a < 3; ++a) {
    const double x = std::clamp(u[a], 0.0, static_cast<double>(n[a] - 1));
    int i = static_cast<int>(std::floor(x));
    i = std::min(i, n[a] - 2);
    c.i[a] = i;
    c.f[a] = x - i;
  }
  return c;
}
double lerp(double a, double b, double t) {
  return a + (b - a) * t;
}
}  // namespace

double SignedDistanceField::interior(const Vec3& local) const {
  const Cell c = locate((local - d_.origin) / d_.spacing, d_.samples);
  double s[2][2][2];
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) s[dz][dy][dx] = sample(c.i[0] + dx, c.i[1] + dy, c.i[2] + dz);
  const double x00 = lerp(s[0][0][0], s[0][0][1], c.f[0]);
  const double x10 = lerp(s[0][1][0], s[0][1][1], c.f[0]);
  const double x01 = lerp(s[1][0][0], s[1][0][1], c.f[0]);
  const double x11 = lerp(s[1][1][0], s[1][1][1], c.f[0]);
  return lerp(lerp(x00, x10, c.f[1]), lerp(x01, x11, c.f[1]), c.f[2]);
}

double SignedDistanceField::distance(const Vec3& local) const {
  const Vec3 c = local.cwiseMax(bounds_.min).cwiseMin(bounds_.max);
  return interior(c) + (local - c).norm();
}

double SignedDistanceField::distanceAndNormal(const Vec3& local, Vec3& n) const {
  const Vec3 c = local.cwiseMax(bounds_.min).cwiseMin(bounds_.max);
  const Cell cell = locate((c - d_.origin) / d_.spacing, d_.samples);
  // A 4x4x4 block of samples around the cell: the inner 2x2x2 give the distance, central
  // differences over the block give a gradient at each inner corner.
  double s[4][4][4];
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x)
        s[z][y][x] = sample(cell.i[0] + x - 1, cell.i[1] + y - 1, cell.i[2] + z - 1);
  double dist = 0.0;
  Vec3 g = Vec3::Zero();
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const double w = (dx ? cell.f[0] : 1.0 - cell.f[0]) * (dy ? cell.f[1] : 1.0 - cell.f[1]) *
                         (dz ? cell.f[2] : 1.0 - cell.f[2]);
        const int x = dx + 1, y = dy + 1, z = dz + 1;
        dist += w * s[z][y][x];
        g += w * Vec3(s[z][y][x + 1] - s[z][y][x - 1], s[z][y + 1][x] - s[z][y - 1][x],
                      s[z + 1][y][x] - s[z - 1][y][x]);
      }
  g /= 2.0 * d_.spacing;  // central differences -> gradient (|g| ~ 1 near the surface)
  const Vec3 out = local - c;
  const double outside = out.norm();
  if (outside > 0.0) {
    // Beyond the lattice the field continues as (distance at the box) + (distance to the box);
    // its gradient takes the clamped axes from the offset and the others from the lattice.
    const Vec3 u = out / outside;
    for (int a = 0; a < 3; ++a)
      if (out[a] != 0.0) g[a] = u[a];
    n = g.normalized();
    return dist + outside;
  }
  const double len = g.norm();
  if (len > 1e-9) {
    n = g / len;
  } else {
    // On a plateau of the clamped band there is no gradient: point away from the centre
    // (outside) or toward it (inside), the direction the thesis casts its contact ray.
    Vec3 r = local - bounds_.center();
    if (r.norm() < 1e-12) r = Vec3::UnitY();
    n = r.normalized();
  }
  return dist;
}

Vec3 SignedDistanceField::normal(const Vec3& local) const {
  Vec3 n;
  distanceAndNormal(local, n);
  return n;
}

Vec3 SignedDistanceField::closestPoint(const Vec3& local) const {
  // Newton steps on the distance field: p <- p - d(p) n(p). Near the surface one or two steps
  // suffice; beyond the band each step moves by at most the band width.
  Vec3 p = local;
  const double tol = 1e-6 * d_.spacing;
  for (int it = 0; it < 64; ++it) {
    Vec3 n;
    const double d = distanceAndNormal(p, n);
    if (std::abs(d) <= tol) break;
    p -= d * n;
  }
  return p;
}

bool SignedDistanceField::rayCast(const Vec3& origin, const Vec3& dir, double maxDistance,
                                  double& t, Vec3& n) const {
  // Clip the ray to the lattice box (the surface lies inside it).
  double t0 = 0.0, t1 = maxDistance;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(dir[a]) < 1e-300) {
      if (origin[a] < bounds_.min[a] || origin[a] > bounds_.max[a]) return false;
      continue;
    }
    double ta = (bounds_.min[a] - origin[a]) / dir[a];
    double tb = (bounds_.max[a] - origin[a]) / dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return false;
  double prevT = t0;
  double d = distance(origin + t0 * dir);
  if (d <= 0.0) {
    if (t0 == 0.0) {  // starts inside
      t = 0.0;
      n = normal(origin);
      return true;
    }
  } else {
    // Sphere tracing: never step farther than the distance to the surface (a minimum step
    // keeps grazing rays moving); a sign change brackets the hit.
    double tc = t0;
    const double minStep = 0.02 * d_.spacing;
    for (int it = 0; it < 4096 && d > 0.0; ++it) {
      prevT = tc;
      if (tc >= t1) return false;
      tc = std::min(t1, tc + std::max(d, minStep));
      d = distance(origin + tc * dir);
    }
    if (d > 0.0) return false;
    t0 = tc;
  }
  // Bisection between prevT (outside) and t0 (inside or on the surface).
  double lo = prevT, hi = t0;
  for (int it = 0; it < 40 && hi - lo > 1e-9 * d_.spacing; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (distance(origin + mid * dir) > 0.0)
      lo = mid;
    else
      hi = mid;
  }
  t = hi;
  n = normal(origin + t * dir);
  return true;
}

}  // namespace grip
