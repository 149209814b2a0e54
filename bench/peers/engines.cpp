#include "peers/peers.hpp"

namespace grip::peers {

std::vector<sweep::Engine> allEngines() {
  std::vector<sweep::Engine> e = {sweep::gripEngine()};
#ifdef GRIP_HAVE_BULLET
  e.push_back(bulletEngine());
#endif
#ifdef GRIP_HAVE_ODE
  e.push_back(odeEngine());
#endif
  e.push_back(sweep::gripTwoThreadEngine());  // last: the chart's colours of the others stay
  return e;
}

}  // namespace grip::peers
