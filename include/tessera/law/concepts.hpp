#pragma once
// The ContactLaw concept: a pure evaluator of one sub-contact (HOOMD-style evaluator). The
// solver owns the loops and the storage (one `state` per sub-contact) and calls `update` once
// per sub-contact per step.
//
// | expression                         | meaning                                                        |
// |------------------------------------|----------------------------------------------------------------|
// | L::params                          | plain struct of parameters, SI units (k_n, k_s in Pa/m, ...)   |
// | L::state                           | per-sub-contact history; value-initialised = virgin contact    |
// | L::validate(p)                     | throws tessera::invalid_input naming a bad parameter and value |
// | L::normal_stiffness(p)             | k_n (Pa/m), used for the stable time step                      |
// | L::shear_stiffness(p)              | k_s (Pa/m)                                                     |
// | L::update(p, s, du_n, du_s, n)     | advances s by one step: du_n = increment of normal opening (m, |
// |                                    | + opens), du_s = increment of tangential relative displacement |
// |                                    | (m, 3-vector in the plane of the current unit normal n, A->B). |
// |                                    | The stored shear stress is first rotated into the plane of n.  |
// | s.sigma_n                          | normal stress (Pa, + tension)                                  |
// | s.tau                              | shear stress vector (Pa, global frame, in the contact plane)   |
// | s.u_n                              | total normal opening (m, + opens)                              |
// | L::status(s)                       | contact_status flags (softening, broken in tension, slipped)   |
// | L::tensile_damage(p, s)            | 0 (intact) .. 1 (broken in tension)                            |
// | L::dissipated_energy(s)            | energy dissipated so far per unit area (J/m^2), all mechanisms |
// | L::stored_energy(p, s)             | recoverable elastic energy per unit area (J/m^2)               |
// | L::state_fields        (optional)  | every field of the state, declared once (state_field: name, |
// |                                    | unit, member); required for the packed column storage       |
// | L::unbonded_state(p)   (optional)  | state of a never-bonded sub-contact (contact::material_table:: |
// |                                    | never_bonded): no tensile strength, residual friction          |

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <utility>

#include "../core/lanes.hpp"
#include "../core/types.hpp"

namespace tessera::law {

/// Damage state of a sub-contact as bit flags (a contact can be both broken and slipped).
enum class contact_status : std::uint8_t {
  intact = 0,
  softening = 1,       ///< past the tensile strength, on the softening branch
  broken_tension = 2,  ///< tensile strength exhausted for good
  slipped = 4,         ///< failed in shear, on the residual Coulomb limit
  crushed = 8,         ///< past the compressive cap of a softening_cap (compression.hpp), which softens with u_crush
};
[[nodiscard]] constexpr contact_status operator|(contact_status a, contact_status b) {
  return static_cast<contact_status>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}
[[nodiscard]] constexpr bool has(contact_status s, contact_status flag) {
  return (static_cast<std::uint8_t>(s) & static_cast<std::uint8_t>(flag)) != 0;
}

/// One field of a law's state, declared once by the law (L::state_fields): its name, unit and
/// member. Contact sets store the state as columns from this list (contact/detail/packed_states.hpp),
/// and io::vtk::contact_snapshot writes one array per entry, named "<name>" (unit in the array's
/// documentation, docs/architecture.md), so a new field reaches storage and output by its
/// declaration alone. Three kinds: a real, a 3-vector (stored as three real columns, components
/// 0..2) and the contact_status flags.
template <class S>
struct state_field {
  /** a real, a 3-vector or the flags */ enum class kind : std::uint8_t { scalar, vector, flags };
  const char* name;  ///< field name, e.g. "sigma_n"
  const char* unit;  ///< SI unit, e.g. "Pa"
  kind type;  ///< which member below is set
  real S::*scalar = nullptr;  ///< the real member (kind scalar)
  vec3 S::*vector = nullptr;  ///< the vector member (kind vector)
  contact_status S::*flags = nullptr;  ///< the flags member (kind flags)
  constexpr state_field() : name(""), unit(""), type(kind::scalar) {}  ///< An empty entry (a law's list fills it in)
  constexpr state_field(const char* n, const char* u, real S::*m) : name(n), unit(u), type(kind::scalar), scalar(m) {}  ///< A real field
  constexpr state_field(const char* n, const char* u, vec3 S::*m) : name(n), unit(u), type(kind::vector), vector(m) {}  ///< A 3-vector field
  /// The flags field
  constexpr state_field(const char* n, const char* u, contact_status S::*m)
      : name(n), unit(u), type(kind::flags), flags(m) {}
  /// Real columns the field takes (1, 3, or 0 for the flags).
  [[nodiscard]] constexpr int real_columns() const { return type == kind::scalar ? 1 : type == kind::vector ? 3 : 0; }
};

/// A law that declares its state fields: L::state_fields, a constexpr array of
/// state_field<L::state> listing every field of the state exactly once.
template <class L>
concept DeclaresStateFields = requires {
  { L::state_fields.size() } -> std::convertible_to<std::size_t>;
  { L::state_fields[0] } -> std::convertible_to<state_field<typename L::state>>;
};

/// Index of the first real column of the field called `name` in the columns built from `fields`
/// (fields in declaration order, each taking real_columns() columns); throws in a constant
/// expression when no field has that name.
template <class Fields>
[[nodiscard]] constexpr std::size_t real_column_of(const Fields& fields, std::string_view name) {
  std::size_t column = 0;
  for (const auto& f : fields) {
    if (std::string_view(f.name) == name) return column;
    column += static_cast<std::size_t>(f.real_columns());
  }
  throw "law state field not declared";
}
/// Number of real columns of `fields`.
template <class Fields>
[[nodiscard]] constexpr std::size_t real_column_count(const Fields& fields) {
  std::size_t column = 0;
  for (const auto& f : fields) column += static_cast<std::size_t>(f.real_columns());
  return column;
}

/// Saves or loads n states of a law that declares its fields through a checkpoint archive
/// (io/checkpoint.hpp): one record per declared field, "<prefix><name>" (a vector field's n x 3
/// components as one record, component-major), read with get(i) -> L::state and, when loading,
/// written back with set(i, const L::state&). The same declaration as the contact storage and
/// the VTK arrays, so a new field reaches checkpoints by being declared.
template <class L, class Archive, class Get, class Set>
  requires DeclaresStateFields<L>
void checkpoint_states(Archive& ar, const std::string& prefix, std::size_t n, Get&& get, Set&& set) {
  using S = typename L::state;
  using kind = typename state_field<S>::kind;
  std::vector<S> states(n);
  if (ar.saving())
    for (std::size_t i = 0; i < n; ++i) states[i] = get(i);
  std::vector<real> reals;
  std::vector<contact_status> flags;
  for (const auto& f : L::state_fields) {
    const std::string name = prefix + f.name;
    if (f.type == kind::flags) {
      flags.resize(n);
      if (ar.saving())
        for (std::size_t i = 0; i < n; ++i) flags[i] = states[i].*f.flags;
      ar.array(name, flags);
      if (ar.loading())
        for (std::size_t i = 0; i < n; ++i) states[i].*f.flags = flags[i];
      continue;
    }
    const std::size_t width = f.type == kind::vector ? 3 : 1;
    reals.resize(n * width);
    if (ar.saving())
      for (std::size_t i = 0; i < n; ++i) {
        if (f.type == kind::scalar)
          reals[i] = states[i].*f.scalar;
        else
          for (std::size_t c = 0; c < 3; ++c) reals[c * n + i] = (states[i].*f.vector)[static_cast<int>(c)];
      }
    ar.array(name, reals);
    if (ar.loading())
      for (std::size_t i = 0; i < n; ++i) {
        if (f.type == kind::scalar)
          states[i].*f.scalar = reals[i];
        else
          for (std::size_t c = 0; c < 3; ++c) (states[i].*f.vector)[static_cast<int>(c)] = reals[c * n + i];
      }
  }
  if (ar.loading())
    for (std::size_t i = 0; i < n; ++i) set(i, static_cast<const S&>(states[i]));
}

template <class L>
concept ContactLaw = requires(const typename L::params& p, typename L::state& s,
                              const typename L::state& cs, real du_n, const vec3& du_s, const vec3& n) {
  typename L::params;
  typename L::state;
  { L::validate(p) } -> std::same_as<void>;
  { L::normal_stiffness(p) } -> std::convertible_to<real>;
  { L::shear_stiffness(p) } -> std::convertible_to<real>;
  { L::update(p, s, du_n, du_s, n) } noexcept -> std::same_as<void>;
  { cs.sigma_n } -> std::convertible_to<real>;
  { cs.tau } -> std::convertible_to<vec3>;
  { cs.u_n } -> std::convertible_to<real>;
  { L::status(cs) } -> std::same_as<contact_status>;
  { L::tensile_damage(p, cs) } -> std::convertible_to<real>;
  { L::dissipated_energy(cs) } -> std::convertible_to<real>;
  { L::stored_energy(p, cs) } -> std::convertible_to<real>;
};

/// A ContactLaw with an elastic path over packs of sub-contacts (law::cohesive_frictional):
/// contact::face_contacts then stores the states as columns (one array per field) and updates
/// them with L::update_elastic over lanes::pack's, running L::update on the lanes it declines.
/// | expression                          | meaning                                                     |
/// |-------------------------------------|-------------------------------------------------------------|
/// | L::elastic_pack                     | constexpr bool, true                                        |
/// | L::elastic_lanes<T>                 | aggregate of T: du_n, ds0..2, n0..2 (update()'s arguments), |
/// |                                     | sigma_n, tau0..2, u_n, dissipated_tension, dissipated_shear,|
/// |                                     | dissipated_compression, u_p, u_soft (state fields), f_t     |
/// |                                     | (L::tensile_strength of the state)                          |
/// | L::update_elastic(p, flags, x)      | update() of the lanes of `x` that stay elastic; returns     |
/// |                                     | their mask (see cohesive_frictional.hpp); flags: the lanes' |
/// |                                     | contact_status bits as mask lanes                           |
/// | L::tensile_strength(p, s)           | a function of s.u_soft and s.flags alone                    |
/// | s.u_p, s.u_soft, s.dissipated_*,    | the other state fields (sigma_n, tau, u_n above); these     |
/// | s.flags                             | fields are the whole state                                  |
template <class L>
concept ElasticPackLaw =
    ContactLaw<L> && DeclaresStateFields<L> && L::elastic_pack &&
    requires(const typename L::params& p, lanes::mask flags, typename L::template elastic_lanes<lanes::pack>& x,
             const typename L::state& s) {
      { L::update_elastic(p, flags, x) } noexcept -> std::same_as<lanes::mask>;
      { L::update_elastic(p, lanes::mask_lane{}, std::declval<typename L::template elastic_lanes<real>&>()) } noexcept
          -> std::same_as<bool>;
      { L::tensile_strength(p, s) } noexcept -> std::convertible_to<real>;
      { s.u_p } -> std::convertible_to<real>;
      { s.u_soft } -> std::convertible_to<real>;
      { s.dissipated_tension } -> std::convertible_to<real>;
      { s.dissipated_shear } -> std::convertible_to<real>;
      { s.dissipated_compression } -> std::convertible_to<real>;
      { s.flags } -> std::convertible_to<contact_status>;
    };

}  // namespace tessera::law
