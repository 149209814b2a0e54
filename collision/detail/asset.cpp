// Reading and writing grip's runtime asset (format: docs/assets.md). Plain C++: no CGAL, no
// OpenVDB. Every field read is checked, so a damaged file is refused rather than misread.
#include "collision/asset.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "core/error.hpp"
#include "core/hash.hpp"

namespace grip {

static_assert(std::endian::native == std::endian::little,
              "the asset format is little-endian; add byte swapping for this platform");

namespace {

constexpr char kMagic[8] = {'G', 'R', 'I', 'P', 'A', 'S', 'E', 'T'};
constexpr size_t kHeaderBytes = 32;  // magic, version, reserved, payload size, checksum
constexpr size_t kBrickValues =
    SignedDistanceField::kBrick * SignedDistanceField::kBrick * SignedDistanceField::kBrick;

uint64_t fnv1a(const uint8_t* data, size_t n) {
  StateHash h;
  h.add(data, n);
  return h.value();
}

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void put(const Vec3& v) { put(v.x()), put(v.y()), put(v.z()); }
  std::vector<uint8_t> bytes;
};

class Reader {
 public:
  Reader(const uint8_t* p, size_t n) : p_(p), n_(n) {}
  template <class T>
  T get(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, p_ + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  double real(const char* what) {
    const double v = get<double>(what);
    if (!std::isfinite(v)) throw Error("asset", std::string(what) + " is not finite");
    return v;
  }
  Vec3 vec(const char* what) {
    const double x = real(what), y = real(what), z = real(what);
    return {x, y, z};
  }
  void need(size_t bytes, const char* what) const {
    if (bytes > n_ - at_) throw Error("asset", std::string("truncated while reading ") + what);
  }
  size_t left() const { return n_ - at_; }

 private:
  const uint8_t* p_;
  size_t n_;
  size_t at_ = 0;
};

}  // namespace

Vec3 AssetData::boxCenter(const Box& b) const {
  const Vec3 lo(b.lo[0], b.lo[1], b.lo[2]), hi(b.hi[0], b.hi[1], b.hi[2]);
  return boxOrigin + voxelSize * (0.5 * (lo + hi) - Vec3::Constant(0.5));
}

Vec3 AssetData::boxHalfExtents(const Box& b) const {
  return 0.5 * voxelSize * Vec3(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]);
}

double AssetData::boxVolume() const {
  double v = 0.0;
  for (const Box& b : boxes) {
    const Vec3 h = boxHalfExtents(b);
    v += 8.0 * h.x() * h.y() * h.z();
  }
  return v;
}

std::vector<uint8_t> encodeAsset(const AssetData& a) {
  Writer w;
  w.put(a.density);
  w.put(a.mass.mass);
  w.put(a.mass.volume);
  w.put(a.mass.com);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) w.put(a.mass.inertia(r, c));
  w.put(a.sourceTriangles);
  w.put(a.voxelSize);
  w.put(a.boxOrigin);
  w.put(static_cast<uint32_t>(a.boxes.size()));
  for (const auto& b : a.boxes) {
    for (uint16_t v : b.lo) w.put(v);
    for (uint16_t v : b.hi) w.put(v);
  }
  const auto& s = a.sdf;
  w.put(s.origin);
  w.put(s.spacing);
  for (int n : s.samples) w.put(static_cast<uint32_t>(n));
  w.put(s.band);
  w.put(static_cast<uint32_t>(s.bricks.size()));
  for (int32_t b : s.bricks) w.put(b);
  w.put(static_cast<uint32_t>(s.values.size() / kBrickValues));
  for (int8_t v : s.values) w.put(v);
  w.put(static_cast<uint32_t>(s.coarse.size()));
  for (float v : s.coarse) w.put(v);

  Writer out;
  out.bytes.insert(out.bytes.end(), kMagic, kMagic + 8);
  out.put(kAssetVersion);
  out.put(uint32_t{0});
  out.put(static_cast<uint64_t>(w.bytes.size()));
  out.put(fnv1a(w.bytes.data(), w.bytes.size()));
  out.bytes.insert(out.bytes.end(), w.bytes.begin(), w.bytes.end());
  return out.bytes;
}

AssetData decodeAsset(const std::vector<uint8_t>& bytes) {
  if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, 8) != 0)
    throw Error("asset", "not a grip asset (bad magic)");
  Reader h(bytes.data() + 8, kHeaderBytes - 8);
  const auto version = h.get<uint32_t>("version");
  if (version != kAssetVersion)
    throw Error("asset", "version " + std::to_string(version) +
                             " is not supported (this build "
                             "reads version " +
                             std::to_string(kAssetVersion) + "); re-run grip prep");
  h.get<uint32_t>("reserved");
  const auto payload = h.get<uint64_t>("payload size");
  const auto checksum = h.get<uint64_t>("checksum");
  if (payload != bytes.size() - kHeaderBytes)
    throw Error("asset", "truncated or padded: header says " + std::to_string(payload) +
                             " payload bytes, file has " +
                             std::to_string(bytes.size() - kHeaderBytes));
  if (fnv1a(bytes.data() + kHeaderBytes, payload) != checksum)
    throw Error("asset", "checksum mismatch (the file is corrupted)");

  Reader r(bytes.data() + kHeaderBytes, payload);
  AssetData a;
  a.density = r.real("density");
  a.mass.mass = r.real("mass");
  a.mass.volume = r.real("volume");
  a.mass.com = r.vec("centre of mass");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a.mass.inertia(i, j) = r.real("inertia");
  if (!(a.density > 0.0 && a.mass.mass > 0.0 && a.mass.volume > 0.0))
    throw Error("asset", "density, mass and volume must be positive");
  if (!(a.mass.inertia.diagonal().array() > 0.0).all())
    throw Error("asset", "inertia must have a positive diagonal");
  a.sourceTriangles = r.get<uint32_t>("triangle count");
  a.voxelSize = r.real("voxel size");
  if (!(a.voxelSize > 0.0)) throw Error("asset", "voxel size must be positive");
  a.boxOrigin = r.vec("box origin");
  const auto boxCount = r.get<uint32_t>("box count");
  r.need(static_cast<size_t>(boxCount) * 12, "boxes");
  a.boxes.resize(boxCount);
  for (uint32_t i = 0; i < boxCount; ++i) {
    auto& b = a.boxes[i];
    for (auto& v : b.lo) v = r.get<uint16_t>("box");
    for (auto& v : b.hi) v = r.get<uint16_t>("box");
    for (int k = 0; k < 3; ++k)
      if (b.lo[k] >= b.hi[k])
        throw Error("asset", "box " + std::to_string(i) + " is empty or inverted");
  }
  if (a.boxes.empty()) throw Error("asset", "has no boxes");
  auto& s = a.sdf;
  s.origin = r.vec("sdf origin");
  s.spacing = r.real("sdf spacing");
  for (int& n : s.samples) {
    const auto v = r.get<uint32_t>("sdf size");
    if (v > 4096) throw Error("asset", "sdf size " + std::to_string(v) + " is absurd");
    n = static_cast<int>(v);
  }
  s.band = r.real("sdf band");
  const auto brickCount = r.get<uint32_t>("sdf brick table size");
  r.need(static_cast<size_t>(brickCount) * 4, "sdf brick table");
  s.bricks.resize(brickCount);
  for (auto& b : s.bricks) b = r.get<int32_t>("sdf brick table");
  const auto stored = r.get<uint32_t>("sdf brick count");
  r.need(static_cast<size_t>(stored) * kBrickValues, "sdf bricks");
  s.values.resize(static_cast<size_t>(stored) * kBrickValues);
  for (auto& v : s.values) v = r.get<int8_t>("sdf bricks");
  const auto coarse = r.get<uint32_t>("sdf coarse size");
  r.need(static_cast<size_t>(coarse) * 4, "sdf coarse lattice");
  s.coarse.resize(coarse);
  for (auto& v : s.coarse) v = r.get<float>("sdf coarse lattice");
  if (r.left() != 0) throw Error("asset", std::to_string(r.left()) + " unexpected trailing bytes");
  try {
    SignedDistanceField check(s);  // validates sizes and brick indices
  } catch (const Error& e) {
    throw Error("asset", std::string("invalid distance field: ") + e.what());
  }
  return a;
}

void writeAssetFile(const std::string& path, const AssetData& a) {
  const auto bytes = encodeAsset(a);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) throw Error(path, "cannot open for writing");
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!f) throw Error(path, "write failed");
}

AssetData readAssetFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(path, "cannot open asset");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  try {
    return decodeAsset(bytes);
  } catch (const Error& e) {
    throw Error(path, e.what());
  }
}

}  // namespace grip
