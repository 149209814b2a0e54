// libFuzzer target: scene files (apps/scene parseJson + parseScene). Any input must either parse
// or be refused with grip::Error; anything else escaping (another exception type, a crash, a
// sanitizer report) is a bug. A scene that parses is also run for a few steps, because a scene
// the parser accepts must build a valid world.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  grip::scene::Scene scene;
  try {
    scene = grip::scene::parseScene(grip::scene::parseJson(text, "fuzz"));
  } catch (const grip::Error&) {
    return 0;  // refused with a message: the expected outcome for most inputs
  }
  // At most three steps: the fuzzer looks for crashes, not for long runs. (A check measured
  // from a later time is then refused by run(); measure from the start instead.)
  scene.duration = std::min(scene.duration, 3.0 * scene.dt);
  for (grip::scene::CheckSpec& c : scene.checks) c.since = 0.0;
  try {
    grip::scene::run(scene);
  } catch (const grip::Error&) {
  }
  return 0;
}
