#pragma once
// The power centre of a set of generators and box sides: the point of equal power distance to
// all of them, as the least-squares point of their pairwise power planes. The tessellation
// cleanup (vertex_weld.hpp) recomputes an ill-conditioned welded vertex with it.
//
// Cost: O(k^2) rows for k ids, a 3-column Householder QR and a 3x3 Jacobi SVD; no Eigen
// decomposition (see power_centre). Thread safety: pure functions.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/types.hpp"
#include "predicates.hpp"
#include "tessellation.hpp"

namespace tessera::geometry {

namespace detail {

/// Singular values of the 3x3 matrix whose columns are w[0], w[1], w[2], by one-sided (Hestenes)
/// Jacobi rotations: the columns are rotated pairwise until mutually orthogonal, and their norms
/// are then the singular values, each to a few ulps of the largest (enough for the 1e-9 ratio test
/// of power_centre; the normal equations A^T A would square the ratio to 1e-18, below rounding).
/// Returns {largest, smallest}; NaN entries give NaN.
[[nodiscard]] TESSERA_INLINE std::array<real, 2> extreme_singular_values_3x3(std::array<vec3, 3> w);

}  // namespace detail

/// The power centre of the generators and box sides in `ids` (generator ids >= 0, boundary
/// tags < 0): the least-squares point of every pairwise power plane and every side plane.
/// Returns false when those planes do not fix a point (smallest singular value of the rows x 3
/// system below 1e-9 of the largest), e.g. fewer than three independent directions; the point is
/// then unique and is solved by Householder QR (the rows are unit normals, offsets in m) and back
/// substitution. Written out by hand rather than with an Eigen decomposition: this non-template
/// inline function is compiled in every translation unit that includes geometry.hpp, and Eigen's
/// JacobiSVD<MatrixXd> it used cost ~4 s of compile time in each (issue #40 item 9).
[[nodiscard]] TESSERA_INLINE bool power_centre(std::span<const index_t> ids, std::span<const vec3> seeds,
                                               std::span<const real> weights, const aabb& domain, vec3& x);
}  // namespace tessera::geometry

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/power_centre.ipp"
#endif
