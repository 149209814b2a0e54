// Bullet and ODE behind the sweep's Sim interface (apps/sweep/sweep.hpp), for
// bench/peers_sweep and bench/peers_bench. Built only with GRIP_WITH_BULLET / GRIP_WITH_ODE, so
// grip's runtime libraries never link a peer engine.
#pragma once

#include "sweep/sweep.hpp"

namespace grip::peers {

#ifdef GRIP_HAVE_BULLET
// Bullet 3.24 (Debian's libbullet-dev): btDiscreteDynamicsWorld with the sequential-impulse
// solver. Knobs: the step, internal substeps (stepSimulation's fixed substep), solver
// iterations. Defaults: 60 Hz, 1 substep, 10 iterations.
sweep::Engine bulletEngine();
#endif

#ifdef GRIP_HAVE_ODE
// ODE 0.16 (Debian's libode-dev): dWorldQuickStep (iterations > 0) or the direct dWorldStep
// (iterations = 0), world ERP 0.2 and CFM 1e-5 (ODE's defaults), Coulomb friction
// (dContactApprox1). Defaults: 60 Hz, 1 substep, 20 quickstep iterations.
sweep::Engine odeEngine();
#endif

// grip, then every peer this build has.
std::vector<sweep::Engine> allEngines();

}  // namespace grip::peers
