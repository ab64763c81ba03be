#pragma once
// Sub-contact states as columns and their update over packs of lanes, for a law with an elastic
// pack path (law::ElasticPackLaw; contact::face_contacts uses this for such laws).
//
// state_columns holds the law state of sub-contact i field by field (one array per declared field,
// Law::state_fields; three for a vector), so a
// lanes::pack of consecutive sub-contacts loads and stores each field with one instruction, and
// one column more than the state: its current tensile strength Law::tensile_strength (the
// envelope f_t(u_soft) while softening, a pure function of u_soft and the flags), re-evaluated
// by set() exactly when u_soft or the flags change and advanced by update_elastic with u_soft,
// so a pack reads the envelope of its softened lanes instead of evaluating it.
// step_columns holds the inputs of Law::update per sub-contact for one step (du_n, du_s, n),
// written by face_contacts' kinematics loop and read by advance_states.
//
// advance_states(p, states, step, area, first, last, force) advances sub-contacts [first, last):
//   1. packs of lanes::width consecutive sub-contacts through Law::update_elastic; the lanes it
//      accepts (all whose damage flags the step leaves unchanged: elastic ones whatever their
//      damage, softening ones advancing along their envelope, slipped ones sliding; see
//      cohesive_frictional::update_elastic) are committed, the others (reaching the peak, breaking,
//      slipping for the first time, at a compressive cap) keep their state (blend) and are marked
//      declined;
//      the sub-contacts after the last whole pack go one by one through update_elastic<real>;
//   2. each declined sub-contact through Law::update, from its unchanged state.
// Every sub-contact's arithmetic is that of Law::update whatever its lane or path, so the result
// does not depend on how [first, last) is cut into packs. force[c][i] = area_i (sigma_n n + tau)_c
// (N), the force on gridpoint A of sub-contact i. No allocation; writes only entries [first, last).

#include <array>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <vector>

#include "../../core/lanes.hpp"
#include "../../core/types.hpp"
#include "../../law/concepts.hpp"
#include "../../law/lane_masks.hpp"

namespace tessera::contact::detail {

/// The states of sub-contacts as columns, built from the law's declaration of its state
/// (Law::state_fields, law::state_field): one real column per scalar field, three per vector
/// field, in declaration order, and the flags as mask lanes; plus the tensile strengths.
/// column<"name">-style access is by index: col(c) with c = law::real_column_of(fields, "name"),
/// a constant expression.
template <class Law>
struct state_columns {
  using state_type = typename Law::state;
  static constexpr auto& fields = Law::state_fields;
  static constexpr std::size_t real_count = law::real_column_count(Law::state_fields);
  /// Real column of the field `name` (its first component for a vector field).
  static constexpr std::size_t column(std::string_view name) { return law::real_column_of(Law::state_fields, name); }

  std::array<std::vector<real>, real_count> reals;
  /// contact_status bits, widened to a mask lane so a pack of them loads with one instruction.
  std::vector<lanes::mask_lane> flags;
  /// Law::tensile_strength(p, state) (Pa): set() re-evaluates it when u_soft or the flags change.
  std::vector<real> f_t;

  [[nodiscard]] std::vector<real>& col(std::size_t c) noexcept { return reals[c]; }
  [[nodiscard]] const std::vector<real>& col(std::size_t c) const noexcept { return reals[c]; }

  /// n zeroed states; reset() each before use.
  void resize(std::size_t n) {
    for (auto& column : reals) column.assign(n, 0.0);
    flags.assign(n, 0);
    f_t.assign(n, 0.0);
  }
  /// Sub-contact i holds s, under parameters p (its tensile strength evaluated).
  void reset(std::size_t i, const state_type& s, const typename Law::params& p) noexcept {
    f_t[i] = Law::tensile_strength(p, s);
    reals[u_soft_column][i] = s.u_soft;
    flags[i] = static_cast<lanes::mask_lane>(s.flags);
    set(i, s, p);
  }
  /// n virgin states (state_type{}) of a law with parameters p.
  void assign(std::size_t n, const typename Law::params& p) {
    resize(n);
    for (std::size_t i = 0; i < n; ++i) reset(i, state_type{}, p);
  }
  [[nodiscard]] std::size_t size() const { return flags.size(); }
  /// The state of sub-contact i, assembled field by field from the declaration.
  [[nodiscard]] state_type get(std::size_t i) const noexcept {
    state_type s{};
    std::size_t c = 0;
    for (const auto& f : fields) {
      using kind = typename law::state_field<state_type>::kind;
      if (f.type == kind::scalar) {
        s.*f.scalar = reals[c++][i];
      } else if (f.type == kind::vector) {
        s.*f.vector = vec3(reals[c][i], reals[c + 1][i], reals[c + 2][i]);
        c += 3;
      } else {
        s.*f.flags = static_cast<law::contact_status>(flags[i]);
      }
    }
    return s;
  }
  /// Stores s for sub-contact i, whose parameters are p (its tensile strength is re-evaluated
  /// when u_soft or the flags change).
  void set(std::size_t i, const state_type& s, const typename Law::params& p) noexcept {
    if (s.u_soft != reals[u_soft_column][i] || static_cast<lanes::mask_lane>(s.flags) != flags[i])
      f_t[i] = Law::tensile_strength(p, s);
    std::size_t c = 0;
    for (const auto& f : fields) {
      using kind = typename law::state_field<state_type>::kind;
      if (f.type == kind::scalar) {
        reals[c++][i] = s.*f.scalar;
      } else if (f.type == kind::vector) {
        for (int k = 0; k < 3; ++k) reals[c++][i] = (s.*f.vector)[k];
      } else {
        flags[i] = static_cast<lanes::mask_lane>(s.*f.flags);
      }
    }
  }

 private:
  static constexpr std::size_t u_soft_column = column("u_soft");
};

/// Per sub-contact and step: the arguments of Law::update, du_n (m), du_s (m) and the unit normal
/// n, and whether update_elastic accepted the sub-contact (mask lane: -1 accepted, 0 declined).
struct step_columns {
  std::vector<real> du_n, ds0, ds1, ds2, n0, n1, n2;
  std::vector<lanes::mask_lane> elastic;
  void resize(std::size_t n) {
    for (auto* column : {&du_n, &ds0, &ds1, &ds2, &n0, &n1, &n2}) column->assign(n, 0.0);
    elastic.assign(n, 0);
  }
};

/// Advances sub-contacts [first, last) by one step (see the file comment) and writes
/// force[c][i] = area[i] (sigma_n n + tau)_c.
template <law::ElasticPackLaw Law>
void advance_states(const typename Law::params& p, state_columns<Law>& s, step_columns& k, const real* area,
                    std::size_t first, std::size_t last, real* const force[3]) noexcept {
  // Lanes T (lanes::pack, or real for the sub-contacts after the last whole pack) starting at i,
  // with their contact_status bits `flags`. Damaged = false: all lanes are intact (flags zero, a
  // constant the law's damage branches fold away), their f_t is that of a virgin state, and an
  // intact lane that update_elastic accepts leaves u_p, u_soft, f_t and dissipated_shear
  // unchanged, so those are not stored.
  const real f_t_virgin = Law::tensile_strength(p, typename Law::state{});
  // Column indices as constants (called in place, column() would compare the names every call).
  using columns = state_columns<Law>;
  constexpr std::size_t sigma_n_column = columns::column("sigma_n"), tau_column = columns::column("tau"),
                        u_n_column = columns::column("u_n"), u_p_column = columns::column("u_p"),
                        u_soft_column = columns::column("u_soft"),
                        dissipated_tension_column = columns::column("dissipated_tension"),
                        dissipated_shear_column = columns::column("dissipated_shear"),
                        dissipated_compression_column = columns::column("dissipated_compression");
  real* const sigma_n = s.col(sigma_n_column).data();
  real* const tau0 = s.col(tau_column).data();
  real* const tau1 = s.col(tau_column + 1).data();
  real* const tau2 = s.col(tau_column + 2).data();
  real* const u_n = s.col(u_n_column).data();
  real* const u_p = s.col(u_p_column).data();
  real* const u_soft = s.col(u_soft_column).data();
  real* const dissipated_tension = s.col(dissipated_tension_column).data();
  real* const dissipated_shear = s.col(dissipated_shear_column).data();
  real* const dissipated_compression = s.col(dissipated_compression_column).data();
  real* const f_t = s.f_t.data();
  // The plastic slip of a law whose shear limit softens with it (slip_softening.hpp).
  constexpr bool with_slip = requires { requires Law::softens_with_slip; };
  [[maybe_unused]] real* u_slip = nullptr;
  if constexpr (with_slip) u_slip = s.col(columns::column("u_slip")).data();
  // The plastic closure of a law whose cap softens with it (compression.hpp softening_cap).
  constexpr bool with_crush = requires { requires Law::softens_with_crushing; };
  [[maybe_unused]] real* u_crush = nullptr;
  if constexpr (with_crush) u_crush = s.col(columns::column("u_crush")).data();
  const auto lanes_at = [&]<class T, bool Damaged>(std::size_t i, auto flags) __attribute__((always_inline)) {
    using lanes::load;
    typename Law::template elastic_lanes<T> x{load<T>(&k.du_n[i]),  load<T>(&k.ds0[i]),     load<T>(&k.ds1[i]),
                                              load<T>(&k.ds2[i]),   load<T>(&k.n0[i]),      load<T>(&k.n1[i]),
                                              load<T>(&k.n2[i]),    load<T>(&sigma_n[i]),   load<T>(&tau0[i]),
                                              load<T>(&tau1[i]),    load<T>(&tau2[i]),      load<T>(&u_n[i]),
                                              load<T>(&dissipated_tension[i]),
                                              load<T>(&dissipated_shear[i]),
                                              load<T>(&dissipated_compression[i]),
                                              load<T>(&u_p[i]),     load<T>(&u_soft[i]),
                                              Damaged ? load<T>(&f_t[i]) : lanes::splat<T>(f_t_virgin)};
    if constexpr (with_slip) x.u_slip = Damaged ? load<T>(&u_slip[i]) : T{};
    if constexpr (with_crush) x.u_crush = Damaged ? load<T>(&u_crush[i]) : T{};
    const auto old = x;
    const auto elastic = Law::update_elastic(p, flags, x);
    using law::detail::mask_blend;  // xor, and, xor: `elastic` is no comparison (lane_masks.hpp)
    using lanes::store;
    store(&sigma_n[i], mask_blend(elastic, x.sigma_n, old.sigma_n));
    store(&tau0[i], mask_blend(elastic, x.tau0, old.tau0));
    store(&tau1[i], mask_blend(elastic, x.tau1, old.tau1));
    store(&tau2[i], mask_blend(elastic, x.tau2, old.tau2));
    store(&u_n[i], mask_blend(elastic, x.u_n, old.u_n));
    store(&dissipated_tension[i], mask_blend(elastic, x.dissipated_tension, old.dissipated_tension));
    store(&dissipated_compression[i], mask_blend(elastic, x.dissipated_compression, old.dissipated_compression));
    if constexpr (Damaged) {
      store(&dissipated_shear[i], mask_blend(elastic, x.dissipated_shear, old.dissipated_shear));
      store(&u_p[i], mask_blend(elastic, x.u_p, old.u_p));
      store(&u_soft[i], mask_blend(elastic, x.u_soft, old.u_soft));
      store(&f_t[i], mask_blend(elastic, x.f_t, old.f_t));
      if constexpr (with_slip) store(&u_slip[i], mask_blend(elastic, x.u_slip, old.u_slip));
      if constexpr (with_crush) store(&u_crush[i], mask_blend(elastic, x.u_crush, old.u_crush));
    }
    const T a = load<T>(&area[i]);
    store(&force[0][i], a * (x.sigma_n * x.n0 + x.tau0));
    store(&force[1][i], a * (x.sigma_n * x.n1 + x.tau1));
    store(&force[2][i], a * (x.sigma_n * x.n2 + x.tau2));
    lanes::store_mask(&k.elastic[i], elastic);
  };
  std::size_t i = first;
  for (; i + lanes::width <= last; i += lanes::width) {
    const auto flags = lanes::load_lanes<lanes::pack>(&s.flags[i]);
    if (lanes::any(flags))  // any lane with a damage bit
      lanes_at.template operator()<lanes::pack, true>(i, flags);
    else
      lanes_at.template operator()<lanes::pack, false>(i, decltype(flags){});
  }
  for (; i < last; ++i) lanes_at.template operator()<real, true>(i, lanes::load_lanes<real>(&s.flags[i]));

  // Lanes update_elastic declined: the full law from the unchanged state.
  for (std::size_t j = first; j < last; ++j) {
    if (k.elastic[j] != 0) [[likely]]
      continue;
    typename Law::state st = s.get(j);
    const vec3 n(k.n0[j], k.n1[j], k.n2[j]);
    Law::update(p, st, k.du_n[j], vec3(k.ds0[j], k.ds1[j], k.ds2[j]), n);
    s.set(j, st, p);
    const vec3 traction = st.sigma_n * n + vec3(st.tau);
    for (int c = 0; c < 3; ++c) force[c][j] = area[j] * traction[c];
  }
}

}  // namespace tessera::contact::detail
