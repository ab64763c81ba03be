#pragma once
// Compressed-sparse-row adjacency, built by a counting sort in two passes over the same entries:
// csr_offsets counts them per row (offsets, rows + 1 of them, offsets[r]..offsets[r+1] = row r),
// the caller sizes its payload arrays to offsets.back(), csr_fill hands each entry its slot.
// Within a row, entries keep the order in which `entries` visits them (deterministic).
//
//   auto offsets = csr_offsets(n_rows, [&](auto&& emit) { for (...) emit(row, [&](index slot) { ... }); });
//   payload.resize(offsets.back());
//   csr_fill(offsets, same_entries);
//
// `entries(emit)` calls emit(row, place) once per entry, in the same order on both passes;
// place(slot) stores the entry (called by csr_fill only).

#include <cstddef>
#include <vector>

#include "types.hpp"

namespace tessera {

template <class Entries>
[[nodiscard]] std::vector<index_t> csr_offsets(index_t rows, Entries&& entries) {
  std::vector<index_t> offsets(static_cast<std::size_t>(rows) + 1, 0);
  entries([&](auto row, auto&&) { ++offsets[static_cast<std::size_t>(row) + 1]; });
  for (std::size_t r = 1; r < offsets.size(); ++r) offsets[r] += offsets[r - 1];
  return offsets;
}

template <class Entries>
void csr_fill(const std::vector<index_t>& offsets, Entries&& entries) {
  std::vector<index_t> next(offsets.begin(), offsets.end() - 1);
  entries([&](auto row, auto&& place) { place(next[static_cast<std::size_t>(row)]++); });
}

}  // namespace tessera
