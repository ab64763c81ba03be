#pragma once
// Module header for solver/. Owners add their headers here as they land.
#include "core.hpp"
#include "solver/balance.hpp"
#include "solver/boundary.hpp"
#include "solver/energy.hpp"
#include "solver/recorders.hpp"
#include "solver/step_checker.hpp"
#include "solver/stop_conditions.hpp"
#include "solver/solver.hpp"
