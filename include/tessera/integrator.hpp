#pragma once
// Module header for integrator/. Owners add their headers here as they land.
#include "core.hpp"
#include "integrator/concepts.hpp"
#include "integrator/damping.hpp"
#include "integrator/central_difference.hpp"
#include "integrator/timestep.hpp"
