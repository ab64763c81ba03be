#pragma once
// Module header for geometry/. Owners add their headers here as they land.
#include "core.hpp"
#include "geometry/tessellation.hpp"
#include "geometry/block_mesh.hpp"
