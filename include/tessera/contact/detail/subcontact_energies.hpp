#pragma once
// The energies of one sub-contact (contact_energies, contact/concepts.hpp) from its law state, for
// the contact sets' energies(): stored and dissipated (J) as the law gives them, and the split of
// the dissipation by mechanism for a law state that keeps one (has_dissipation_split).

#include <concepts>

#include "../../core/types.hpp"
#include "../concepts.hpp"

namespace tessera::contact::detail {

/// A law state that reports its dissipated energy (J/m^2) per mechanism.
template <class S>
concept has_dissipation_split = requires(const S& s) {
  { s.dissipated_tension } -> std::convertible_to<real>;
  { s.dissipated_shear } -> std::convertible_to<real>;
  { s.dissipated_compression } -> std::convertible_to<real>;
};

/// Adds to `e` (J) the energies of a sub-contact of tributary area `area` (m^2) with law
/// parameters `p` and state `st`: area x Law::stored_energy, area x Law::dissipated_energy and,
/// when Law::state has the fields, area x dissipated_tension / _shear / _compression (J/m^2).
template <class Law, class State>
void add_subcontact_energies(contact_energies& e, const typename Law::params& p, const State& st, real area) {
  e.stored += area * Law::stored_energy(p, st);
  e.dissipated += area * Law::dissipated_energy(st);
  if constexpr (has_dissipation_split<typename Law::state>) {
    e.dissipated_tension += area * st.dissipated_tension;
    e.dissipated_shear += area * st.dissipated_shear;
    e.dissipated_compression += area * st.dissipated_compression;
  }
}

}  // namespace tessera::contact::detail
