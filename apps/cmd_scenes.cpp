// `grip scenes`: lists the built-in scenes; `grip scenes --print NAME` prints one as a scene file.
#include <cstdio>

#include "commands.hpp"
#include "scene/scene.hpp"

namespace grip::cli {

namespace {
int listScenes(const std::string& print) {
  if (!print.empty()) {
    const auto doc = scene::builtinScene(print);
    if (!doc) throw Error(print, "no such built-in scene (`grip scenes` lists them)");
    std::printf("%s\n", doc->dump(2).c_str());
    return 0;
  }
  for (const scene::BuiltinScene& s : scene::builtinScenes()) {
    std::printf("%-15s %s\n", s.name.c_str(), s.summary.c_str());
  }
  std::printf("\nrun one with `grip run NAME`; `grip scenes --print NAME` shows its scene file\n");
  return 0;
}
}  // namespace

Command addScenesCommand(CLI::App& app) {
  auto* sub = app.add_subcommand("scenes", "list the built-in scenes");
  auto print = std::make_shared<std::string>();
  sub->add_option("--print", *print, "print the scene file of a built-in scene");
  return {sub, [print] { return listScenes(*print); }};
}

}  // namespace grip::cli
