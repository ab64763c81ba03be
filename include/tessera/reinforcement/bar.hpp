#pragma once
// Reinforcing steel and bar geometry (DESIGN.md §3 "Reinforcement", study Sec. 2.2).
//
// A bar is a straight segment [start, end] split into `elements` equal 2-node truss elements
// (3-DOF nodes, no rotational DOF). discretise_bars() turns a list of bars into one node list and
// one element list with CSR offsets per bar; node k of bar b sits at start + (k / N) (end - start).

#include <cmath>
#include <numbers>
#include <vector>

#include "../core/errors.hpp"
#include "../core/types.hpp"
#include "detail/format.hpp"

namespace tessera::reinforcement {

/// Reinforcing steel of a round bar. Elastic-perfectly plastic in tension and compression, no
/// rupture (study Sec. 2.2).
struct steel {
  real young_modulus = 0.0;   ///< E_s (Pa)
  real yield_stress = 0.0;    ///< f_y (Pa); yield force f_y A in tension and in compression
  real density = 7850.0;      ///< rho_s (kg/m^3), lumped onto the bar nodes
  real diameter = 0.0;        ///< d (m)

  [[nodiscard]] real area() const { return std::numbers::pi * diameter * diameter / 4.0; }  ///< A = pi d^2 / 4 (m^2)
  [[nodiscard]] real perimeter() const { return std::numbers::pi * diameter; }              ///< pi d (m)
  [[nodiscard]] real yield_force() const { return yield_stress * area(); }                  ///< f_y A (N)
  [[nodiscard]] real axial_rigidity() const { return young_modulus * area(); }              ///< E_s A (N)

  /// Throws invalid_input naming the first non-positive or non-finite property.
  void validate() const {
    require_positive(young_modulus, "steel: Young's modulus E_s (Pa)");
    require_positive(yield_stress, "steel: yield stress f_y (Pa)");
    require_positive(density, "steel: density (kg/m^3)");
    require_positive(diameter, "steel: bar diameter d (m)");
  }
};

/// One straight bar, discretised into `elements` equal truss elements.
struct bar {
  vec3 start = vec3::Zero();  ///< first node (m)
  vec3 end = vec3::Zero();    ///< last node (m)
  index_t elements = 1;         ///< number of truss elements N (>= 1); the bar gets N + 1 nodes
  /// true: every node is embedded in its host zone and bonded to it (the study's model).
  /// false: an unbonded bar (no host, no bond springs), e.g. the bare-bar reference response.
  bool bonded = true;
};

/// Nodes and 2-node elements of a list of bars (reference configuration).
struct bar_discretisation {
  std::vector<vec3> nodes;                   ///< reference positions (m)
  std::vector<index_t> node_bar;               ///< owning bar of each node
  std::vector<index_t> bar_node_offsets{0};    ///< CSR: nodes of bar b
  std::vector<index_t> element_node_a;         ///< first node of each element
  std::vector<index_t> element_node_b;         ///< second node (towards `end`)
  std::vector<real> element_length;          ///< reference length L_el (m)
  std::vector<index_t> bar_element_offsets{0}; ///< CSR: elements of bar b

  [[nodiscard]] index_t node_count() const { return static_cast<index_t>(nodes.size()); }  ///< Number of nodes
  [[nodiscard]] index_t element_count() const { return static_cast<index_t>(element_length.size()); }  ///< Number of elements
};

/// Splits every bar into equal elements. Throws invalid_input naming the bar when it has fewer
/// than one element, a non-finite end point or elements of zero length.
[[nodiscard]] inline bar_discretisation discretise_bars(const std::vector<bar>& bars) {
  bar_discretisation d;
  for (std::size_t b = 0; b < bars.size(); ++b) {
    const bar& br = bars[b];
    require(br.elements >= 1, "bar ", b, ": number of truss elements = ", br.elements, " must be >= 1");
    require(br.start.allFinite() && br.end.allFinite(), "bar ", b, ": end points ", detail::point_string(br.start),
            " and ", detail::point_string(br.end), " must be finite");
    const vec3 span = br.end - br.start;
    const real element_length = span.norm() / static_cast<real>(br.elements);
    require(element_length > 0.0, "bar ", b, ": element length = ", element_length, " m (bar from ",
            detail::point_string(br.start), " to ", detail::point_string(br.end), ", ", br.elements,
            " elements) must be > 0");
    const index_t first = d.node_count();
    for (index_t k = 0; k <= br.elements; ++k) {
      // The last node is `end` exactly, so bars meant to end on a face do.
      d.nodes.push_back(k == br.elements ? br.end
                                         : vec3(br.start + (static_cast<real>(k) / br.elements) * span));
      d.node_bar.push_back(static_cast<index_t>(b));
    }
    for (index_t k = 0; k < br.elements; ++k) {
      const index_t a = first + k;
      d.element_node_a.push_back(a);
      d.element_node_b.push_back(a + 1);
      const real length = (d.nodes[static_cast<std::size_t>(a) + 1] - d.nodes[static_cast<std::size_t>(a)]).norm();
      require(length > 0.0, "bar ", b, ": element ", k, " has zero length (", br.elements,
              " elements over ", span.norm(), " m)");
      d.element_length.push_back(length);
    }
    d.bar_node_offsets.push_back(d.node_count());
    d.bar_element_offsets.push_back(d.element_count());
  }
  return d;
}

}  // namespace tessera::reinforcement
