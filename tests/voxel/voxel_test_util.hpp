// Helpers shared by the voxel tests: paths, analytic shapes, the CGAL sample-data archive.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "core/error.hpp"
#include "voxel/voxel.hpp"

namespace grip::voxel::test {

inline std::string sourceDir() {
  const char* s = std::getenv("GRIP_SOURCE_DIR");
  if (s) return s;
  // Run outside ctest: this header sits in <source>/tests/voxel/.
  return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path().string();
}

inline std::string assetPath(const std::string& file) {
  return sourceDir() + "/assets/" + file;
}

// Debian's libcgal-demo ships CGAL's sample data as an archive; the tests extract the meshes
// they need into a temporary folder (nothing is copied into the repository).
inline const char* kCgalArchive = "/usr/share/doc/libcgal-dev/data.tar.gz";

inline std::string cgalMesh(const std::string& name) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "grip_cgal_data";
  const fs::path file = dir / "data" / "meshes" / name;
  if (!fs::exists(file)) {
    // ctest runs tests in parallel processes: each extracts into a folder of its own and moves
    // the finished file into place (a rename is atomic), so no test reads a half-written mesh.
    const fs::path mine = dir / ("extract_" + std::to_string(::getpid()));
    fs::create_directories(mine);
    fs::create_directories(file.parent_path());
    const std::string cmd = "tar -xzf " + std::string(kCgalArchive) + " -C " + mine.string() +
                            " 'data/meshes/" + name + "' 2>/dev/null";
    const fs::path extracted = mine / "data" / "meshes" / name;
    std::error_code ec;
    if (std::system(cmd.c_str()) == 0 && fs::exists(extracted)) fs::rename(extracted, file, ec);
    fs::remove_all(mine, ec);
    if (!fs::exists(file)) return {};
  }
  return file.string();
}

inline bool haveCgalData() {
  return std::filesystem::exists(kCgalArchive);
}

// A torus about Y: major radius R, minor radius r.
struct Torus {
  double R = 0.05, r = 0.015;
  double distance(const Vec3& p) const {
    const double q = std::hypot(p.x(), p.z()) - R;
    return std::hypot(q, p.y()) - r;
  }
  Vec3 normal(const Vec3& p) const {
    const double rho = std::hypot(p.x(), p.z());
    const Vec3 c(p.x() / rho * R, 0.0, p.z() / rho * R);  // nearest point on the core circle
    return (p - c).normalized();
  }
  Mesh mesh(int nu, int nv) const {
    Mesh m;
    for (int u = 0; u < nu; ++u)
      for (int v = 0; v < nv; ++v) {
        const double a = 2.0 * kPi * u / nu, b = 2.0 * kPi * v / nv;
        const double rr = R + r * std::cos(b);
        m.vertices.emplace_back(rr * std::cos(a), r * std::sin(b), rr * std::sin(a));
      }
    auto at = [&](int u, int v) { return (u % nu) * nv + (v % nv); };
    for (int u = 0; u < nu; ++u)
      for (int v = 0; v < nv; ++v) {
        m.triangles.push_back({at(u, v), at(u, v + 1), at(u + 1, v + 1)});
        m.triangles.push_back({at(u, v), at(u + 1, v + 1), at(u + 1, v)});
      }
    return m;
  }
};

}  // namespace grip::voxel::test
