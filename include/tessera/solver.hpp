#pragma once
// Module header for solver/. Owners add their headers here as they land.
#include "core.hpp"
