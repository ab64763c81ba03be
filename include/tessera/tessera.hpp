#pragma once
// tessera: header-only C++20 discontinuum mechanics (convex polyhedral blocks, cohesive-
// frictional contacts with tensile softening, embedded reinforcement with bond-slip, explicit
// central differences with local damping). Including this header brings in every module.
#include "core.hpp"
#include "geometry.hpp"
#include "io.hpp"
#include "law.hpp"
#include "blocks.hpp"
#include "contact.hpp"
#include "reinforcement.hpp"
#include "integrator.hpp"
#include "solver.hpp"
#include "analysis.hpp"
#include "presets.hpp"
