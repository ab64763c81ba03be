#pragma once
// Reader of Neper tessellation files (.tess, format 3.x, as written by `neper -T`), the
// tessellation tool of the reference study, into a tessera::geometry::tessellation.
//
// File layout read here (indentation free; ids are 1-based; "*" = signed id):
//   ***tess
//    **format      3.4
//    **general     3 standard                        (dimension must be 3)
//    **cell        N
//      *id         N cell ids                          (optional)
//      *seed       N lines: id x y z weight           (optional; stored as seeds / weights)
//      *ori, *crysym, *lam, *mode, *group ...        (skipped)
//    **vertex      Nv, then Nv lines: id x y z state
//    **edge        Ne, then Ne lines: id v1 v2 state
//    **face        Nf, then per face four lines:
//                    id nver v_1 .. v_nver
//                    nedge e*_1 .. e*_nedge
//                    d a b c                            (face plane ax + by + cz = d)
//                    state point_type x y z
//    **polyhedron  Np (= N), then Np lines: id nface f*_1 .. f*_nface
//    **domain      *general type (must be "cube"); the rest is skipped
//   ***end
//
// Decisions:
//  - Face loops are oriented geometrically (outward from the cell's vertex centroid), not from
//    the sign of f* in **polyhedron, so the result does not depend on a sign convention; a face
//    used by two polyhedra is stored once per cell with reversed loops (twins).
//  - The domain box is the bounding box of the vertices. A face used by one polyhedron must lie
//    on a side of that box (within 1e-9 of its extent; vertices are snapped onto the side) and
//    gets boundary_tag(side); a face used by three or more polyhedra is an error.
//  - Each **section (and *seed) may appear once: a repeated one would make the counts of cells,
//    seeds and polyhedra disagree.
//  - Malformed input throws io_error naming the file, line, section and offending value.
//
// Cost: O(file size). Thread safety: pure function of its input.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <istream>
#include <sstream>
#include <string>
#include <vector>

#include "../core/separate_compilation.hpp"
#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "../geometry/mass_properties.hpp"
#include "../geometry/tessellation.hpp"

namespace tessera::io {

namespace detail {

/// Whitespace-separated tokens of a text stream, with their line numbers and the current section.
class tess_tokens {
 public:
  tess_tokens(std::istream& in, std::string name) : name_(std::move(name)) {
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
      ++number;
      std::istringstream ls(line);
      std::string word;
      while (ls >> word) tokens_.push_back({word, number});
    }
  }
  [[nodiscard]] bool done() const { return pos_ >= tokens_.size(); }
  [[nodiscard]] const std::string& peek() const {
    if (done()) fail("unexpected end of file");
    return tokens_[pos_].text;
  }
  [[nodiscard]] int line() const { return done() ? (tokens_.empty() ? 0 : tokens_.back().line) : tokens_[pos_].line; }
  [[nodiscard]] bool at_marker() const { return !done() && tokens_[pos_].text.front() == '*'; }
  std::string next(const char* what) {
    if (done()) fail(tessera::detail::concat("unexpected end of file while reading ", what));
    return tokens_[pos_++].text;
  }
  /// Skips the rest of the current token's line.
  void skip_line() {
    if (done()) return;
    const int l = tokens_[pos_].line;
    while (!done() && tokens_[pos_].line == l) ++pos_;
  }
  /// Skips tokens up to the next section marker (a token starting with '*').
  void skip_to_marker() {
    while (!done() && !at_marker()) ++pos_;
  }
  long long integer(const char* what) {
    const int l = line();
    const std::string t = next(what);
    char* end = nullptr;
    const long long v = std::strtoll(t.c_str(), &end, 10);
    if (t.empty() || *end != '\0') fail_at(l, tessera::detail::concat("expected an integer ", what, ", got '", t, "'"));
    return v;
  }
  real number(const char* what) {
    const int l = line();
    const std::string t = next(what);
    char* end = nullptr;
    const real v = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(v))
      fail_at(l, tessera::detail::concat("expected a finite number ", what, ", got '", t, "'"));
    return v;
  }
  /// A count in [lo, hi].
  index_t count(const char* what, long long lo, long long hi) {
    const int l = line();
    const long long v = integer(what);
    if (v < lo || v > hi) fail_at(l, tessera::detail::concat(what, " = ", v, " must be in [", lo, ", ", hi, "]"));
    return static_cast<index_t>(v);
  }
  void set_section(std::string s) { section_ = std::move(s); }
  [[noreturn]] void fail(const std::string& message) const { fail_at(line(), message); }
  [[noreturn]] void fail_at(int l, const std::string& message) const {
    throw io_error(tessera::detail::concat("read_neper_tess: ", name_, ":", l,
                                           section_.empty() ? std::string() : " (section " + section_ + ")", ": ",
                                           message));
  }

 private:
  struct token {
    std::string text;
    int line;
  };
  std::vector<token> tokens_;
  std::size_t pos_ = 0;
  std::string name_, section_;
};

}  // namespace detail

/// Reads a Neper .tess (format 3.x) tessellation from a stream; `name` labels error messages.
[[nodiscard]] TESSERA_INLINE geometry::tessellation read_neper_tess(std::istream& in, const std::string& name);

/// Reads a Neper .tess (format 3.x) file; throws io_error when it cannot be opened or parsed.
[[nodiscard]] inline geometry::tessellation read_neper_tess(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw io_error(tessera::detail::concat("read_neper_tess: cannot open '", path.string(), "'"));
  return read_neper_tess(in, path.string());
}

}  // namespace tessera::io

#ifndef TESSERA_SEPARATE_COMPILATION
#include "impl/neper.ipp"
#endif
