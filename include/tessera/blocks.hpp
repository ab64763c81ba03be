#pragma once
// Module header for blocks/. Owners add their headers here as they land.
#include "core.hpp"
