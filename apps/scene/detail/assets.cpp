// Concave bodies in scene files: prepared runtime assets (collision/asset.hpp, no CGAL or
// OpenVDB needed) and meshes prepared on demand by the voxel module, cached by content.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/scene.hpp"

#ifdef GRIP_HAVE_VOXEL
#include "voxel/voxel.hpp"
#endif

namespace grip::scene {

namespace fs = std::filesystem;

std::string builtinBaseDir() {
#ifdef GRIP_SOURCE_ROOT
  return GRIP_SOURCE_ROOT;
#else
  return ".";
#endif
}

std::string resolvePath(const std::string& baseDir, const std::string& path) {
  const fs::path p(path);
  fs::path r = (p.is_absolute() || baseDir.empty() ? p : fs::path(baseDir) / p).lexically_normal();
  if (!r.has_filename() && r.has_parent_path()) r = r.parent_path();  // "dir/" -> "dir"
  return r.string();
}

bool haveVoxelModule() {
#ifdef GRIP_HAVE_VOXEL
  return true;
#else
  return false;
#endif
}

std::string assetCacheDir() {
  if (const char* d = std::getenv("GRIP_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d)
    return (fs::path(d) / "grip").string();
  if (const char* d = std::getenv("HOME"); d && *d)
    return (fs::path(d) / ".cache" / "grip").string();
  return (fs::temp_directory_path() / "grip-cache").string();
}

#ifdef GRIP_HAVE_VOXEL
namespace {

// FNV-1a 64 (the asset format's checksum, here as a cache key).
uint64_t fnv1a(const std::string& bytes, uint64_t h = 14695981039346656037ull) {
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string readAll(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw Error(path, "no such file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw Error(path, "cannot read");
  return ss.str();
}

}  // namespace
#endif

std::string preparedMeshAsset(const std::string& meshPath, const std::string& lod, double density) {
#ifndef GRIP_HAVE_VOXEL
  (void)lod, (void)density;
  throw Error(meshPath,
              "a mesh shape needs grip built with the voxel module (-DGRIP_BUILD_VOXEL=ON); "
              "or prepare it with `grip prep` and use {\"type\": \"asset\"}");
#else
  const std::string bytes = readAll(meshPath);
  voxel::PrepOptions po;
  po.lod = voxel::parseLod(lod);
  po.density = density;
  // The key covers everything the asset depends on: the mesh's bytes, the options and the
  // asset version. The name keeps the mesh's stem for people looking into the cache.
  char opts[128];
  std::snprintf(opts, sizeof opts, "|lod=%s|density=%.17g|asset=%u", lod.c_str(), density,
                kAssetVersion);
  char key[17];
  std::snprintf(key, sizeof key, "%016llx",
                static_cast<unsigned long long>(fnv1a(opts, fnv1a(bytes))));
  const fs::path dir = assetCacheDir();
  const fs::path cached =
      dir / (fs::path(meshPath).stem().string() + "_" + lod + "_" + key + ".grip");
  std::error_code ec;
  if (fs::is_regular_file(cached, ec)) {
    try {
      readAssetFile(cached.string());
      return cached.string();
    } catch (const Error&) {
      // A damaged cache entry is prepared again below.
    }
  }
  const voxel::Mesh mesh = voxel::loadMesh(meshPath);
  const AssetData asset = voxel::prepare(mesh, po);
  fs::create_directories(dir, ec);
  if (ec) throw Error(dir.string(), "cannot create the asset cache: " + ec.message());
  // Written under a temporary name and renamed: a cache file is always complete.
  const fs::path tmp = cached.string() + ".partial";
  writeAssetFile(tmp.string(), asset);
  fs::rename(tmp, cached, ec);
  if (ec) throw Error(cached.string(), "cannot write the asset cache: " + ec.message());
  return cached.string();
#endif
}

}  // namespace grip::scene
