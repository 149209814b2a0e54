// libFuzzer target: mesh input (voxel/ loadMesh: OFF, OBJ, STL, PLY read by CGAL, then checked
// and repaired). loadMesh reads files by extension, so each input is written to a temporary
// file whose extension is chosen from its content: "ply" -> .ply, "OFF" in the first line
// -> .off, "solid" or binary bytes -> .stl, anything else -> .obj. Only grip::Error may come out.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/error.hpp"
#include "voxel/voxel.hpp"

namespace {

std::string extensionFor(const std::string& s) {
  if (s.rfind("ply", 0) == 0) return "ply";
  if (s.substr(0, s.find('\n')).find("OFF") != std::string::npos) return "off";
  if (s.rfind("solid", 0) == 0) return "stl";
  for (size_t i = 0; i < s.size() && i < 80; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 9 || (c > 13 && c < 32) || c > 126) return "stl";  // binary: a binary STL
  }
  return "obj";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  // The process id is zero-padded: a path whose length changed from run to run changed the
  // code paths the messages take, so a fixed-seed run did not repeat itself.
  char pid[16];
  std::snprintf(pid, sizeof pid, "%010d", static_cast<int>(getpid()));
  const std::string path = "/tmp/grip_fuzz_mesh_" + std::string(pid) + "." + extensionFor(bytes);
  if (FILE* f = std::fopen(path.c_str(), "wb")) {
    std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
  } else {
    return 0;
  }
  try {
    grip::voxel::loadMesh(path);
  } catch (const grip::Error&) {
  }
  std::remove(path.c_str());
  return 0;
}
