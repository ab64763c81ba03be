#pragma once
// Shared helpers of the libFuzzer targets (tests/fuzz/): a front-to-back byte decoder that reads
// zeros once the input is exhausted (so every input, even the empty one, decodes to a case and
// hand-written corpus files read left to right), and the finding report.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace tessera::fuzz {

/// Consumes the fuzzer's bytes in order; past the end every read yields 0.
class byte_reader {
 public:
  byte_reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  [[nodiscard]] bool exhausted() const { return pos_ >= size_; }
  std::uint8_t u8() { return pos_ < size_ ? data_[pos_++] : std::uint8_t{0}; }
  std::uint16_t u16() {
    const std::uint16_t lo = u8();
    const std::uint16_t hi = u8();
    return static_cast<std::uint16_t>(lo | (hi << 8));
  }
  std::int16_t i16() { return static_cast<std::int16_t>(u16()); }
  /// u16 / 65535 in [0, 1], both ends reachable (points exactly on a box side).
  double unit() { return u16() / 65535.0; }
  /// u8 / 255 in [0, 1].
  double unit8() { return u8() / 255.0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

/// Reports a violated invariant and aborts, which libFuzzer records as a crash with the input.
[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "\n==tessera fuzz finding== %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace tessera::fuzz
