#pragma once
// Module header for reinforcement/. Owners add their headers here as they land.
#include "core.hpp"
#include "reinforcement/concepts.hpp"
#include "reinforcement/none.hpp"
