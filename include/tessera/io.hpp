#pragma once
// Module header for io/. Owners add their headers here as they land.
#include "core.hpp"
