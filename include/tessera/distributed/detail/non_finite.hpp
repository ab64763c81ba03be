#pragma once
// The non-finite check of a split run, reduced over the ranks (distributed::stepper,
// rigid_stepper and local_model): each rank finds its first offending node, the smallest label is
// reduced, and every rank throws together, so none is left waiting in the next exchange.
// Only where MPI is built in (TESSERA_HAVE_MPI).

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <cstdint>
#include <limits>
#include <string_view>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"

namespace tessera::distributed::detail {

/// What a rank passes to throw_first_non_finite when all its nodes are finite.
inline constexpr long long all_finite = std::numeric_limits<long long>::max();

/// Reduces `mine` (this rank's first offending label, or all_finite) to the smallest over `comm`
/// and, when any rank found one, throws numerical_instability on every rank naming it: a label
/// below `gridpoints` is that gridpoint, a larger one bar node label - gridpoints. `where` closes
/// the message in parentheses. Every rank of `comm` must call it. Allocates nothing unless it
/// throws.
inline void throw_first_non_finite(long long mine, long long gridpoints, std::int64_t step, real time,
                                   std::string_view where, MPI_Comm comm) {
  long long worst = all_finite;
  MPI_Allreduce(&mine, &worst, 1, MPI_LONG_LONG, MPI_MIN, comm);
  if (worst == all_finite) return;
  const bool gridpoint = worst < gridpoints;
  throw numerical_instability(tessera::detail::concat(
      "numerical instability at step ", step, " (t = ", time, " s): non-finite displacement or velocity at ",
      gridpoint ? "gridpoint " : "bar node ", gridpoint ? worst : worst - gridpoints, " (", where, ")"));
}

}  // namespace tessera::distributed::detail

#endif  // TESSERA_HAVE_MPI
