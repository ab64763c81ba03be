#pragma once
// Module header for reinforcement/. Owners add their headers here as they land.
#include "core.hpp"
