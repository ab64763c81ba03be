#pragma once
// Narrow phase of contact detection between two convex polyhedra (DESIGN.md section 4): the
// contact plane of a pair (common_plane, contact_plane.hpp) and the contact patch on it
// (contact_patch_of, contact_patch.hpp), from which a detecting contact set makes its vertex
// sub-contacts. Both are pure functions of the two polyhedra (and the plane), deterministic and
// thread-safe; the broad phase that picks the pairs is broad_phase.hpp, the pass over all pairs
// detect.hpp.

#include "contact_patch.hpp"
#include "contact_plane.hpp"
