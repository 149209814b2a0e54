// grip: the umbrella header. Include this to get the whole runtime API.
#pragma once

#include "collision/narrowphase.hpp"
#include "collision/query.hpp"
#include "collision/shape.hpp"
#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/mass.hpp"
#include "core/math.hpp"
#include "dynamics/world.hpp"
#if __has_include("interaction/interaction.hpp")
#include "interaction/interaction.hpp"
#endif
