#pragma once
// distributed::gather_detection: the whole result of a detection pass whose narrow phase the
// ranks split (contact::detection_share, detected_contacts::set_detection_split). Each rank
// evaluated one contiguous part of the same candidate list (every rank runs the same broad phase
// on the same geometry); the parts, concatenated in rank order, are the pass one process makes,
// to the bit. distributed::rigid_stepper installs it, so a split run's rebuilds cost each rank
// about 1 / ranks of the common planes and patches, plus this exchange.
//
// Cost: one MPI_Allgather of the part sizes and one MPI_Allgatherv of the parts' bytes (pairs,
// planes, patch types and corner counts; per corner its point, gap, area and label: 56 bytes),
// about 2 MB for the 1 000-block rubble heap. Allocates (at rebuilds only). Every rank of the
// communicator must call it at the same rebuilds. Only where MPI is built in (TESSERA_HAVE_MPI).

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "../contact/detection/detect.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"

namespace tessera::distributed {

namespace detail {

/// Appends the bytes of `v` to `out`.
template <class T>
void append_bytes(std::vector<unsigned char>& out, const std::vector<T>& v) {
  static_assert(std::is_trivially_destructible_v<T>, "a detection field moves between ranks as bytes");
  const auto* p = reinterpret_cast<const unsigned char*>(v.data());
  out.insert(out.end(), p, p + v.size() * sizeof(T));
}

/// Appends `n` values of T read from `in` to `v`; returns the position after them.
template <class T>
const unsigned char* take_bytes(const unsigned char* in, std::size_t n, std::vector<T>& v) {
  const std::size_t old = v.size();
  v.resize(old + n);
  std::memcpy(static_cast<void*>(v.data() + old), in, n * sizeof(T));
  return in + n * sizeof(T);
}

}  // namespace detail

/// Replaces `part` (this rank's part of a split pass: contact::detect with detection_share
/// {rank, ranks}) by the whole pass: every rank's part, in rank order. Every rank of `comm` must
/// call it with its own part of the same pass. Throws invalid_input when a part is too large
/// for one exchange (2 GiB).
inline void gather_detection(MPI_Comm comm, contact::detection::detection_result& part) {
  using contact::detection::block_pair;
  using contact::detection::contact_plane;
  using contact::detection::patch_type;
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  // This part: pair count, corner count, then the fields.
  const std::int64_t n_pairs = static_cast<std::int64_t>(part.pairs.size());
  const std::int64_t n_corners = static_cast<std::int64_t>(part.point.size());
  std::vector<index_t> corners(static_cast<std::size_t>(n_pairs));
  for (std::size_t k = 0; k < corners.size(); ++k) corners[k] = part.first_corner[k + 1] - part.first_corner[k];
  std::vector<unsigned char> mine;
  mine.resize(2 * sizeof(std::int64_t));
  std::memcpy(mine.data(), &n_pairs, sizeof n_pairs);
  std::memcpy(mine.data() + sizeof n_pairs, &n_corners, sizeof n_corners);
  detail::append_bytes(mine, part.pairs);
  detail::append_bytes(mine, part.planes);
  detail::append_bytes(mine, part.type);
  detail::append_bytes(mine, corners);
  detail::append_bytes(mine, part.point);
  detail::append_bytes(mine, part.gap);
  detail::append_bytes(mine, part.area);
  detail::append_bytes(mine, part.label);
  require(mine.size() <= static_cast<std::size_t>(INT32_MAX), "distributed::gather_detection: a rank's part holds ",
          mine.size(), " bytes, more than one MPI exchange carries (2 GiB): split over more ranks");
  const int bytes = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks), 0);
  MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  std::int64_t total = 0;
  for (int r = 0; r < ranks; ++r) {
    offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
    total += counts[static_cast<std::size_t>(r)];
  }
  require(total <= INT32_MAX, "distributed::gather_detection: the pass holds ", total,
          " bytes, more than one MPI exchange carries (2 GiB)");
  std::vector<unsigned char> all(static_cast<std::size_t>(total));
  MPI_Allgatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, comm);
  // The whole pass: the parts in rank order (candidates, the broad phase's count, is every rank's).
  part.clear_pairs();
  for (int r = 0; r < ranks; ++r) {
    const unsigned char* in = all.data() + offsets[static_cast<std::size_t>(r)];
    std::int64_t np = 0, nc = 0;
    std::memcpy(&np, in, sizeof np);
    std::memcpy(&nc, in + sizeof np, sizeof nc);
    in += 2 * sizeof(std::int64_t);
    const auto p = static_cast<std::size_t>(np), c = static_cast<std::size_t>(nc);
    in = detail::take_bytes(in, p, part.pairs);
    in = detail::take_bytes(in, p, part.planes);
    in = detail::take_bytes(in, p, part.type);
    corners.clear();
    in = detail::take_bytes(in, p, corners);
    for (const index_t k : corners) part.first_corner.push_back(part.first_corner.back() + k);
    in = detail::take_bytes(in, c, part.point);
    in = detail::take_bytes(in, c, part.gap);
    in = detail::take_bytes(in, c, part.area);
    in = detail::take_bytes(in, c, part.label);
  }
}

}  // namespace tessera::distributed

#endif  // TESSERA_HAVE_MPI
