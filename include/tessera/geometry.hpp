#pragma once
// Module header for geometry/. Owners add their headers here as they land.
#include "core.hpp"
#include "geometry/tessellation.hpp"
#include "geometry/block_mesh.hpp"
#include "geometry/predicates.hpp"
#include "geometry/mass_properties.hpp"
#include "geometry/convex_polyhedron.hpp"
#include "geometry/cleanup.hpp"
#include "geometry/voronoi.hpp"
#include "geometry/tessellation_queries.hpp"
#include "geometry/zoning.hpp"
#include "geometry/polygon_triangulation.hpp"
#include "geometry/regularize.hpp"
