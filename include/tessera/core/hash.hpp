#pragma once
// FNV-1a, 64 bits: a fingerprint of bytes (checkpoint integrity, reference-geometry identity).
// Not cryptographic; collisions are astronomically unlikely for accidental differences.

#include <cstddef>
#include <cstdint>

namespace tessera {

/// FNV-1a 64-bit hash of bytes (fingerprints of models and states, not for security)
struct fnv1a {
  std::uint64_t value = 0xcbf29ce484222325ull;  ///< the hash so far
  void add(const void* data, std::size_t n) noexcept {  ///< Adds n bytes at data
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) value = (value ^ p[i]) * 0x100000001b3ull;
  }
};

}  // namespace tessera
