#pragma once
// Steps 2-4 of the tessellation cleanup (cleanup.hpp states the whole policy), on the face loops
// after welding: repeated ids and spikes left by collapsed short edges are removed from a loop
// (clean_loop), and every interior face is paired with its twin in the neighbour cell, the same
// vertex ids in reverse order (match_twins), or the cleanup fails with geometry_error.
//
// Cost: clean_loop O(loop length) per pass; match_twins O(faces x faces per cell).
// Thread safety: pure functions.

#include <algorithm>
#include <cstddef>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "mass_properties.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

/// Removes repeated consecutive ids (cyclically) and spikes a-b-a from a face loop, in place.
TESSERA_INLINE void clean_loop(std::vector<index_t>& loop);

/// Pairs every interior face of `t` with its twin, the face of the neighbour tagged with this cell
/// and the reversed loop, and lists the shared faces; throws geometry_error for a face without one.
TESSERA_INLINE void match_twins(tessellation& t);

}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/loop_cleanup.ipp"
#endif
