#pragma once
// Sub-contact states as columns and their update over packs of lanes, for a law with an elastic
// pack path (law::ElasticPackLaw; contact::subcontact_set uses this for such laws).
//
// state_columns holds the law state of sub-contact i field by field (one array per field), so a
// lanes::pack of consecutive sub-contacts loads and stores each field with one instruction.
// step_columns holds the inputs of Law::update per sub-contact for one step (du_n, du_s, n),
// written by subcontact_set's kinematics loop and read by advance_states.
//
// advance_states(p, states, step, area, first, last, force) advances sub-contacts [first, last):
//   1. packs of lanes::width consecutive sub-contacts through Law::update_elastic; the lanes it
//      accepts are committed, the others keep their state (blend) and are marked declined;
//      the sub-contacts after the last whole pack go one by one through update_elastic<real>;
//   2. each declined sub-contact through Law::update, from its unchanged state.
// Every sub-contact's arithmetic is that of Law::update whatever its lane or path, so the result
// does not depend on how [first, last) is cut into packs. force[c][i] = area_i (sigma_n n + tau)_c
// (N), the force on gridpoint A of sub-contact i. No allocation; writes only entries [first, last).

#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "../../core/lanes.hpp"
#include "../../core/types.hpp"
#include "../../law/concepts.hpp"

namespace tessera::contact::detail {

/// The states of sub-contacts as columns (fields as in law::ElasticPackLaw).
template <class Law>
struct state_columns {
  using state_type = typename Law::state;
  std::vector<real> sigma_n, tau0, tau1, tau2, u_n, u_p, u_soft, dissipated_tension, dissipated_shear,
      dissipated_compression;
  /// contact_status bits, widened to a mask lane so a pack of them loads with one instruction.
  std::vector<lanes::mask_lane> flags;

  /// n virgin states (state_type{}).
  void assign(std::size_t n) {
    const state_type v{};
    for (auto* column : real_columns()) column->assign(n, 0.0);
    flags.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) set(i, v);
  }
  [[nodiscard]] std::size_t size() const { return flags.size(); }
  [[nodiscard]] state_type get(std::size_t i) const noexcept {
    state_type s{};
    s.sigma_n = sigma_n[i];
    s.tau = vec3(tau0[i], tau1[i], tau2[i]);
    s.u_n = u_n[i];
    s.u_p = u_p[i];
    s.u_soft = u_soft[i];
    s.dissipated_tension = dissipated_tension[i];
    s.dissipated_shear = dissipated_shear[i];
    s.dissipated_compression = dissipated_compression[i];
    s.flags = static_cast<law::contact_status>(flags[i]);
    return s;
  }
  void set(std::size_t i, const state_type& s) noexcept {
    sigma_n[i] = s.sigma_n;
    tau0[i] = s.tau[0];
    tau1[i] = s.tau[1];
    tau2[i] = s.tau[2];
    u_n[i] = s.u_n;
    u_p[i] = s.u_p;
    u_soft[i] = s.u_soft;
    dissipated_tension[i] = s.dissipated_tension;
    dissipated_shear[i] = s.dissipated_shear;
    dissipated_compression[i] = s.dissipated_compression;
    flags[i] = static_cast<lanes::mask_lane>(s.flags);
  }

 private:
  std::array<std::vector<real>*, 10> real_columns() {
    return {&sigma_n, &tau0, &tau1, &tau2, &u_n, &u_p, &u_soft, &dissipated_tension, &dissipated_shear,
            &dissipated_compression};
  }
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
  // Lanes T (lanes::pack, or real for the sub-contacts after the last whole pack) starting at i.
  const auto lanes_at = [&]<class T>(std::size_t i) __attribute__((always_inline)) {
    using lanes::load;
    typename Law::template elastic_lanes<T> x{load<T>(&k.du_n[i]),  load<T>(&k.ds0[i]),     load<T>(&k.ds1[i]),
                                              load<T>(&k.ds2[i]),   load<T>(&k.n0[i]),      load<T>(&k.n1[i]),
                                              load<T>(&k.n2[i]),    load<T>(&s.sigma_n[i]), load<T>(&s.tau0[i]),
                                              load<T>(&s.tau1[i]),  load<T>(&s.tau2[i]),    load<T>(&s.u_n[i]),
                                              load<T>(&s.dissipated_tension[i]),
                                              load<T>(&s.dissipated_compression[i]),
                                              load<T>(&s.u_p[i]),   load<T>(&s.u_soft[i])};
    const auto old = x;
    const auto elastic = Law::update_elastic(p, lanes::load_is_zero<T>(&s.flags[i]), x);
    using lanes::select;
    using lanes::store;
    store(&s.sigma_n[i], select(elastic, x.sigma_n, old.sigma_n));
    store(&s.tau0[i], select(elastic, x.tau0, old.tau0));
    store(&s.tau1[i], select(elastic, x.tau1, old.tau1));
    store(&s.tau2[i], select(elastic, x.tau2, old.tau2));
    store(&s.u_n[i], select(elastic, x.u_n, old.u_n));
    store(&s.dissipated_tension[i], select(elastic, x.dissipated_tension, old.dissipated_tension));
    store(&s.dissipated_compression[i], select(elastic, x.dissipated_compression, old.dissipated_compression));
    const T a = load<T>(&area[i]);
    store(&force[0][i], a * (x.sigma_n * x.n0 + x.tau0));
    store(&force[1][i], a * (x.sigma_n * x.n1 + x.tau1));
    store(&force[2][i], a * (x.sigma_n * x.n2 + x.tau2));
    lanes::store_mask(&k.elastic[i], elastic);
  };
  std::size_t i = first;
  for (; i + lanes::width <= last; i += lanes::width) {
    // A pack without an intact sub-contact (cracked faces: past the peak, broken or slipped)
    // would be declined lane by lane; send it to Law::update directly.
    if (!lanes::any(lanes::load_is_zero<lanes::pack>(&s.flags[i]))) {
      for (std::size_t j = i; j < i + lanes::width; ++j) k.elastic[j] = 0;
      continue;
    }
    lanes_at.template operator()<lanes::pack>(i);
  }
  for (; i < last; ++i) lanes_at.template operator()<real>(i);

  // Lanes update_elastic declined: the full law from the unchanged state.
  for (std::size_t j = first; j < last; ++j) {
    if (k.elastic[j] != 0) [[likely]]
      continue;
    typename Law::state st = s.get(j);
    const vec3 n(k.n0[j], k.n1[j], k.n2[j]);
    Law::update(p, st, k.du_n[j], vec3(k.ds0[j], k.ds1[j], k.ds2[j]), n);
    s.set(j, st);
    const vec3 traction = st.sigma_n * n + vec3(st.tau);
    for (int c = 0; c < 3; ++c) force[c][j] = area[j] * traction[c];
  }
}

}  // namespace tessera::contact::detail
