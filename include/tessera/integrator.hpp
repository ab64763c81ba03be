#pragma once
// Module header for integrator/. Owners add their headers here as they land.
#include "core.hpp"
