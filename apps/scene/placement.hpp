// The accuracy evaluation of thesis section 5.2 (Table 5.2), run by a scripted user: a cube on a
// chessboard is moved from a random start square to a random target square by a controller that
// plans grasp-and-place, push and pull motions and corrects from what it sees, through seeded
// tracking noise. The same trials, noise and controller are run with each interaction method.
// See docs/evaluation.md for the controller and the measured table.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace grip::scene {

struct PlacementDef {
  int trials = 20;
  uint64_t seed = 1;
  // Tracking noise: each bone's position gets independent Gaussian jitter every frame, this rms
  // length (m) over the three axes (Leap Motion: about a millimetre). The user sees the cube
  // with the same error.
  double noise = 0.001;
  double hz = 60.0;
  double timeLimit = 12.0;   // s: the user stops correcting after this long
  double tolerance = 0.002;  // m: the user is satisfied when the cube looks this close
};

struct PlacementTrial {
  Vec3 start = Vec3::Zero(), target = Vec3::Zero();  // square centres on the board (y = 0)
  double error = 0.0;  // m: final distance of the cube's centre from the target, on the board
  double time = 0.0;   // s: simulated time until the user was done
  int grasps = 0, pushes = 0, pulls = 0;
};

struct Summary {
  double mean = 0.0, sd = 0.0, median = 0.0;
};
Summary summarize(std::vector<double> values);

struct PlacementMethod {
  std::string method;  // "coulomb" or "kinematic"
  std::vector<PlacementTrial> trials;
  Summary error, time;  // error in m, time in s
};

// Runs every trial with both methods. Throws grip::Error naming a bad field.
std::vector<PlacementMethod> evaluatePlacement(const PlacementDef& def);
// The table printed by `grip eval placement` (Table 5.2's layout: mean ± sd / median).
std::string placementTable(const PlacementDef& def, const std::vector<PlacementMethod>& results);

}  // namespace grip::scene
