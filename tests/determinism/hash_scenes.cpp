// Prints "<scene> <hash>" for every determinism scene. scripts/compare_compilers.sh builds
// this with g++ and with clang++ and diffs the output; the lines are also the format of the
// golden table in determinism_test.cpp.
#include <cinttypes>
#include <cstdio>

#include "scenes.hpp"

int main() {
  for (const auto& scene : grip::determinism::hashScenes())
    std::printf("%s %016" PRIx64 "\n", scene.name.c_str(), scene.run());
  return 0;
}
