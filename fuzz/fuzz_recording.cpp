// libFuzzer target: the recording reader (apps/scene checkRecording). Only grip::Error may
// come out.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "core/error.hpp"
#include "scene/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    grip::scene::checkRecording(in, "fuzz");
  } catch (const grip::Error&) {
  }
  return 0;
}
