// Shared between the sweep's scene files (not part of its interface).
#pragma once

#include <limits>

#include "sweep/sweep.hpp"

namespace grip::sweep::detail {

// What a scene run measured: its error(s), the simulated time and the wall time of its steps.
struct Outcome {
  double error = 0, error2 = std::numeric_limits<double>::quiet_NaN();
  double simulated = 0, wall = 0;  // s
};

// The two-finger hold threshold (hold.cpp): grip's World and hand interaction directly.
Outcome hold(const Settings& s);

}  // namespace grip::sweep::detail
