// grip, Bullet and ODE on the sweep's reference scenes in one process (docs/accuracy.md): the
// same options and files as `grip sweep`. Built with -DGRIP_WITH_BULLET=ON and/or
// -DGRIP_WITH_ODE=ON; run build/bench/peers_sweep --out DIR.
#include <cstdio>

#include "core/error.hpp"
#include "peers/peers.hpp"

int main(int argc, char** argv) {
  CLI::App app{"grip beside Bullet and ODE: run time against error on the reference scenes"};
  grip::sweep::CommandLine c;
  grip::sweep::addOptions(app, c);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "peers_sweep: %s\n", e.what());
    return 2;
  }
  try {
    return grip::sweep::runCommand(grip::peers::allEngines(), c);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peers_sweep: %s\n", e.what());
    return 1;
  }
}
