#pragma once
// Steel bars in the implicit quasi-static solve (quasi_static.hpp, its Bars parameter): the truss
// elements and bond springs of reinforcement::embedded_truss<Bond> (reinforcement/embedded_truss.hpp),
// linearised about the reference state as the zones and sub-contacts are, their forces from the
// explicit solver's own laws (truss_element::update, Bond::update) in total form.
//
// Degrees of freedom: bar node n's component c is dof offset + 3 n + c, after the gridpoints'.
//
// Element e from node a to node b, reference unit chord t_e = (x_b - x_a) / L_e: elongation
// e = t_e . (u_b - u_a) (the explicit solver's chord length to first order), axial force N from
// truss_element::update (elastic-perfectly plastic, K_axial = E_s A / L_e), force -N t_e on b and
// +N t_e on a; secant stiffness k_e [t t^T, -t t^T; -t t^T, t t^T] on (a, b).
//
// Bond of bonded node n with host zone corners g_i, weights w_i and unit axis a: relative
// displacement d = u_n - sum w_i u_gi, slip s = a . d, axial bond force F_a from Bond::update with
// the node's K_bond and strength F_max = Bond::strength(p, 0, pi d, L_trib): no confining stress,
// so a bond law with a friction angle is refused (the zones' stress is not read here). Force on the
// node -(F_a a + K_bond (d - s a)), on the host corners -w_i times it; secant stiffness
// B^T (k_a a a^T + K_bond (I - a a^T)) B with B = [I, -w_1 I, ..., -w_4 I].
//
// Secants: on the elastic branch the law's own stiffness (K_axial, K_bond), exact there; on the
// yield or slip plateau N / e and F_a / s (positive on the plateau, at least floor x the elastic
// one), so K stays symmetric positive definite.
//
// no_bars (the default) adds nothing. Not thread-safe.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "../../core/errors.hpp"
#include "../../core/nodes.hpp"
#include "../../core/types.hpp"
#include "../../reinforcement/truss.hpp"
#include "stiffness.hpp"

namespace tessera::implicit {

/// The Bars parameter of a model without bars.
struct no_bars {};

/// Appends the three components of every node of `nodes` to a dof numbering: per dof its index
/// among the free dofs (-1 if prescribed) in free_index, the free dofs in free_dofs, the prescribed
/// velocity (m/s, 0 on free dofs) in velocity (resized).
inline void append_node_dofs(const node_set& nodes, std::vector<index_t>& free_index, std::vector<index_t>& free_dofs,
                             Eigen::VectorXd& velocity) {
  const auto first = static_cast<index_t>(free_index.size());
  velocity.conservativeResize(first + 3 * nodes.size());
  constexpr auto prescribed = static_cast<std::uint8_t>(dof_constraint::prescribed);
  for (index_t i = 0; i < nodes.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const index_t dof = first + 3 * i + c;
      velocity[dof] = 0;
      if (nodes.constraint(i, c) == prescribed) {
        velocity[dof] = nodes.prescribed_velocity(i, c);
        free_index.push_back(-1);
      } else {
        free_index.push_back(static_cast<index_t>(free_dofs.size()));
        free_dofs.push_back(dof);
      }
    }
}

/// The bars' part of the model (file comment). Primary template: Bars = embedded_truss<Bond>.
template <class Bars>
class bar_part {
 public:
  using bond_law = typename Bars::bond_type;  ///< the bond law of the bars
  using bond_state = typename Bars::bond_state;  ///< the bond state per bar node
  using element_state = reinforcement::truss_element::state;  ///< the axial state per bar element

  /// The bars, their node dofs starting at `offset`. Copies their present states as the committed
  /// ones. Throws invalid_input for displaced bar nodes or a bond law with a friction angle.
  bar_part(const Bars& bars, index_t offset) : bars_(&bars), offset_(offset) {
    const node_set& nodes = bars.nodes();
    require(nodes.size() == 0 || nodes.displacement.cwiseAbs().maxCoeff() == 0, "quasi_static: the bar nodes are ",
            "displaced; the model starts from the reference state");
    const auto& p = bars.parameters().bond;
    if constexpr (requires { p.friction_angle; })
      require(p.friction_angle == 0, "quasi_static: bond friction angle phi_bond = ", p.friction_angle, " rad: the ",
              "implicit solve reads no confining stress, so only a bond without friction (phi_bond = 0) is modelled");
    const index_t n_e = bars.element_count(), n_n = bars.node_count();
    chord_.resize(static_cast<std::size_t>(n_e));
    elements_.resize(static_cast<std::size_t>(n_e));
    for (index_t e = 0; e < n_e; ++e) {
      const vec3 d = nodes.reference.row(bars.element_node_b(e)).transpose() - nodes.reference.row(bars.element_node_a(e)).transpose();
      chord_[static_cast<std::size_t>(e)] = d / d.norm();
      element_state& s = elements_[static_cast<std::size_t>(e)];
      s.axial_force = bars.axial_force(e);
      s.plastic_elongation = bars.plastic_elongation(e);
    }
    bonds_.resize(static_cast<std::size_t>(n_n));
    strength_.assign(static_cast<std::size_t>(n_n), 0);
    const real perimeter = bars.parameters().steel.perimeter();
    for (index_t n = 0; n < n_n; ++n) {
      bonds_[static_cast<std::size_t>(n)] = bars.bond(n);
      if (bars.bonded(n))
        strength_[static_cast<std::size_t>(n)] = bond_law::strength(p, 0, perimeter, bars.tributary_length(n));
    }
    trial_elements_ = elements_;
    trial_bonds_ = bonds_;
  }

  /// Trial states from the committed ones at displacements u (dofs of the whole model), and
  /// their forces (N) added to f.
  void evaluate(const Eigen::VectorXd& u, Eigen::VectorXd& f) {
    const Bars& b = *bars_;
    for (index_t e = 0; e < b.element_count(); ++e) {
      const auto k = static_cast<std::size_t>(e);
      const index_t na = b.element_node_a(e), nb = b.element_node_b(e);
      const real elongation = chord_[k].dot(node_u(u, nb) - node_u(u, na));
      element_state s = elements_[k];
      reinforcement::truss_element::update(s, elongation, b.axial_stiffness(e), b.yield_force());
      trial_elements_[k] = s;
      f.segment<3>(dof(nb)) -= s.axial_force * chord_[k];
      f.segment<3>(dof(na)) += s.axial_force * chord_[k];
    }
    for (index_t n = 0; n < b.node_count(); ++n) {
      if (!b.bonded(n)) continue;
      const auto k = static_cast<std::size_t>(n);
      const auto& h = b.host(n);
      vec3 d = node_u(u, n);
      for (int i = 0; i < 4; ++i) d -= h.weights[static_cast<std::size_t>(i)] * u.segment<3>(3 * h.gridpoints[static_cast<std::size_t>(i)]);
      const vec3 a = b.tangent(n);
      const real slip = a.dot(d);
      bond_state s = bonds_[k];
      bond_law::update(b.parameters().bond, s, slip, b.bond_stiffness(n), strength_[k]);
      trial_bonds_[k] = s;
      const vec3 fn = -(s.force * a + b.bond_stiffness(n) * (d - slip * a));
      f.segment<3>(dof(n)) += fn;
      for (int i = 0; i < 4; ++i)
        f.segment<3>(3 * h.gridpoints[static_cast<std::size_t>(i)]) -= h.weights[static_cast<std::size_t>(i)] * fn;
    }
  }

  /// The secants (N/m) of the committed (trial = false) or trial states, elements then bonded
  /// nodes, at least floor x the elastic stiffness (file comment).
  [[nodiscard]] std::vector<real> secants(bool trial, real floor) const {
    const Bars& b = *bars_;
    const auto& es = trial ? trial_elements_ : elements_;
    const auto& bs = trial ? trial_bonds_ : bonds_;
    std::vector<real> k;
    k.reserve(es.size() + bs.size());
    for (index_t e = 0; e < b.element_count(); ++e) {
      const element_state& s = es[static_cast<std::size_t>(e)];
      const real elastic = b.axial_stiffness(e);
      const real elongation = s.plastic_elongation + s.axial_force / elastic;
      k.push_back(plateau_secant(s.yielding, s.axial_force, elongation, elastic, floor));
    }
    for (index_t n = 0; n < b.node_count(); ++n)
      if (b.bonded(n)) {
        const bond_state& s = bs[static_cast<std::size_t>(n)];
        k.push_back(plateau_secant(s.slipping, s.force, s.slip, b.bond_stiffness(n), floor));
      }
    return k;
  }

  /// K of the secants `k` (from secants()) as triplets on the model's dofs.
  void add_stiffness(const std::vector<real>& k, std::vector<triplet>& t) const {
    const Bars& b = *bars_;
    std::size_t j = 0;
    for (index_t e = 0; e < b.element_count(); ++e, ++j) {
      const mat3 m = k[j] * chord_[static_cast<std::size_t>(e)] * chord_[static_cast<std::size_t>(e)].transpose();
      const index_t na = dof(b.element_node_a(e)), nb = dof(b.element_node_b(e));
      add_block(t, na, na, m);
      add_block(t, nb, nb, m);
      add_block(t, na, nb, -m);
      add_block(t, nb, na, -m);
    }
    for (index_t n = 0; n < b.node_count(); ++n) {
      if (!b.bonded(n)) continue;
      const vec3 a = b.tangent(n);
      const mat3 aa = a * a.transpose();
      const mat3 m = k[j++] * aa + b.bond_stiffness(n) * (mat3::Identity() - aa);
      const auto& h = b.host(n);
      std::array<index_t, 5> dofs{dof(n)};
      std::array<real, 5> w{1};
      for (std::size_t i = 0; i < 4; ++i) dofs[i + 1] = 3 * h.gridpoints[i], w[i + 1] = -h.weights[i];
      for (std::size_t r = 0; r < 5; ++r)
        for (std::size_t c = 0; c < 5; ++c) add_block(t, dofs[r], dofs[c], w[r] * w[c] * m);
    }
  }

  void commit() {  ///< Accepts the trial states of the converged increment
    elements_ = trial_elements_;
    bonds_ = trial_bonds_;
  }
  /// Committed axial force (N, tension +) of element e and bond force F_a (N) of node n.
  [[nodiscard]] real axial_force(index_t e) const { return elements_[static_cast<std::size_t>(e)].axial_force; }
  [[nodiscard]] real bond_force(index_t n) const { return bonds_[static_cast<std::size_t>(n)].force; }  ///< Bond force of bar node n (N) in the committed state
  [[nodiscard]] index_t dof(index_t node) const { return offset_ + 3 * node; }  ///< First global degree of freedom of bar node node

 private:
  [[nodiscard]] vec3 node_u(const Eigen::VectorXd& u, index_t n) const { return u.segment<3>(dof(n)); }
  [[nodiscard]] static real plateau_secant(bool on_plateau, real force, real displacement, real elastic, real floor) {
    real k = elastic;
    if (on_plateau && displacement != 0 && force / displacement > 0) k = std::min(elastic, force / displacement);
    return std::max(k, floor * elastic);
  }
  static void add_block(std::vector<triplet>& t, index_t r, index_t c, const mat3& m) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (m(i, j) != 0) t.emplace_back(r + i, c + j, m(i, j));
  }

  const Bars* bars_;
  index_t offset_;
  std::vector<vec3> chord_;  ///< per element: reference unit chord a -> b
  std::vector<element_state> elements_, trial_elements_;
  std::vector<bond_state> bonds_, trial_bonds_;
  std::vector<real> strength_;  ///< per node: F_max (N), 0 on unbonded nodes
};

/// No bars: nothing to add.
template <>
class bar_part<no_bars> {
 public:
  bar_part(const no_bars&, index_t) {}  ///< No bars, no degrees of freedom
  void evaluate(const Eigen::VectorXd&, Eigen::VectorXd&) {}  ///< Adds nothing
  [[nodiscard]] std::vector<real> secants(bool, real) const { return {}; }  ///< No secants
  void add_stiffness(const std::vector<real>&, std::vector<triplet>&) const {}  ///< Adds nothing
  void commit() {}  ///< Nothing to commit
};

}  // namespace tessera::implicit
