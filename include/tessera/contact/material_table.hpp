#pragma once
// contact::material_table<P>: contact-law parameters per pair of block materials (DESIGN.md §2
// "Materials"). Blocks carry a material id (geometry::block_mesh::block_material, all 0 when
// empty); the face between blocks of materials a and b uses the entry of the unordered pair
// {a, b}, or the table's default when the pair has no entry of its own. A pair can be declared
// never bonded: its sub-contacts start with the law's unbonded state (Law::unbonded_state:
// no tensile strength, on the residual Coulomb limit), so that interface carries compression and
// friction only, as a steel plate resting on concrete.
//
//     contact::material_table<law::study_beam_law::params> table(concrete);   // every pair
//     table.set(0, 1, plate_interface);                                        // concrete-plate
//     table.never_bonded(1, 2, plate_on_support);                              // plate-support
//
// One entry a pair, looked up when a contact set is built (never per step). Not thread-safe for
// writes; concurrent reads are safe.

#include <algorithm>
#include <utility>
#include <vector>

#include "../core/errors.hpp"

namespace tessera::contact {

/// The law's parameters per pair of block materials, and whether the pair's contacts start bonded; a plain params converts to a table for every pair
template <class P>
class material_table {
 public:
  /// The parameters of one pair and whether its contacts start bonded.
  struct entry {
    P params{};  ///< the law's parameters
    bool bonded = true;  ///< contacts start bonded (face contacts)
  };

  material_table() = default;
  /// One law for every pair (implicit, so a plain parameter struct is a one-material table).
  material_table(const P& all) : default_{all, true} {}  // NOLINT(google-explicit-constructor)

  /// Bonded parameters for the pair {a, b} (either order). Throws invalid_input for a negative id.
  material_table& set(int a, int b, const P& p) { return put(a, b, entry{p, true}); }
  /// The pair {a, b} is never bonded: its sub-contacts start unbonded (see the file comment).
  material_table& never_bonded(int a, int b, const P& p) { return put(a, b, entry{p, false}); }

  /// The entry of pair {a, b}: its own, else the default.
  [[nodiscard]] const entry& get(int a, int b) const {
    const auto key = ordered(a, b);
    for (const auto& [k, e] : pairs_)
      if (k == key) return e;
    return default_;
  }
  /// Index of the entry of {a, b} in entries(): 0 the default, 1 + k the k-th pair set.
  [[nodiscard]] std::size_t entry_index(int a, int b) const {
    const auto key = ordered(a, b);
    for (std::size_t k = 0; k < pairs_.size(); ++k)
      if (pairs_[k].first == key) return k + 1;
    return 0;
  }
  /// Every entry: the default first, then the pairs in the order they were set.
  [[nodiscard]] std::vector<entry> entries() const {
    std::vector<entry> all{default_};
    for (const auto& [k, e] : pairs_) all.push_back(e);
    return all;
  }

 private:
  static std::pair<int, int> ordered(int a, int b) { return {std::min(a, b), std::max(a, b)}; }
  material_table& put(int a, int b, const entry& e) {
    require(a >= 0 && b >= 0, "material_table: material ids (", a, ", ", b, ") must be >= 0");
    const auto key = ordered(a, b);
    for (auto& [k, old] : pairs_)
      if (k == key) {
        old = e;
        return *this;
      }
    pairs_.emplace_back(key, e);
    return *this;
  }

  entry default_{};
  std::vector<std::pair<std::pair<int, int>, entry>> pairs_;
};

}  // namespace tessera::contact
