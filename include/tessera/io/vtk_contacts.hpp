#pragma once
// VTK output of contact sets and bars, in the configuration every tessera VTK file uses: points
// at their REFERENCE positions with a "displacement" point array (ParaView's Warp By Vector with
// factor 1 shows the deformed shape; docs/architecture.md "VTK output").
//
// contact_snapshot: the sub-contacts of any contact::ContactSet at one instant, one VTK vertex
// each at the midpoint of its gridpoint pair (detected contacts: of its two contact points), with
// point arrays
//     displacement (m), normal (unit, A -> B, current), area_m2, status (law::contact_status bits),
//     tensile_damage (0 intact .. 1 broken), and one array per field the law declares
//     (Law::state_fields, law::state_field) except the flags, which status already shows,
//     named "<field>_<unit>" with '/' written "_per_" and '^' dropped: sigma_n_Pa, tau_Pa (3
//     components), u_n_m, u_p_m, u_soft_m, dissipated_tension_J_per_m2, ...
// So a field added to a law reaches the files by its declaration alone, and every driver writes
// the same names. take() reuses its storage (no allocation after the first call at a given size).
//
// write_bar_vtp: the nodes of an embedded bar (reinforcement::embedded_truss) as points with
// displacement, slip_m and bond_force_N; its elements as lines with axial_force_N and yielded.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "../contact/concepts.hpp"  // subcontact_position
#include "../core/nodes.hpp"
#include "../core/types.hpp"
#include "../law/concepts.hpp"
#include "vtk.hpp"

namespace tessera::io::vtk {

/// VTK array name of a declared law state field: "<name>_<unit>", '/' -> "_per_", '^' dropped.
template <class S>
[[nodiscard]] std::string state_array_name(const law::state_field<S>& f) {
  std::string name = std::string(f.name) + "_";
  for (const char c : std::string_view(f.unit)) {
    if (c == '/')
      name += "_per_";
    else if (c != '^' && c != ' ')
      name += c;
  }
  return name;
}

/// Sub-contacts of a contact set at one instant (file comment).
struct contact_snapshot {
  /// One declared state field: `components` values per sub-contact (1 or 3), sub-contact-major.
  struct array {
    std::string name;  ///< field name
    int components = 1;  ///< 1 or 3
    std::vector<double> values;  ///< values, sub-contact-major
  };
  /** reference position (m), displacement (m), unit normal A->B */ /**@{*/ std::vector<vec3> reference, displacement, normal; /**@}*/
  /** area (m^2), tensile damage (-) */ /**@{*/ std::vector<double> area, tensile_damage; /**@}*/
  std::vector<std::int32_t> status;                   ///< law::contact_status bits
  std::vector<array> state;                           ///< Law::state_fields in declaration order, flags excluded

  [[nodiscard]] std::size_t size() const { return reference.size(); }  ///< Number of sub-contacts

  /// Copies the sub-contacts of `c` (gridpoints `gp`). Contacts: a contact::ContactSet whose law
  /// declares its state fields (law::DeclaresStateFields).
  template <class Contacts>
  void take(const Contacts& c, const node_set& gp) {
    using Law = typename Contacts::law_type;
    static_assert(law::DeclaresStateFields<Law>, "contact_snapshot needs a law that declares state_fields");
    using field = law::state_field<typename Law::state>;
    const auto n = static_cast<std::size_t>(c.subcontact_count());
    reference.resize(n), displacement.resize(n), normal.resize(n);
    area.resize(n), tensile_damage.resize(n), status.resize(n);
    state.resize(0);
    for (const field& f : Law::state_fields) {
      if (f.type == field::kind::flags) continue;
      state.push_back({state_array_name(f), f.real_columns(), {}});
      state.back().values.resize(n * static_cast<std::size_t>(f.real_columns()));
    }
    for (std::size_t k = 0; k < n; ++k) {
      const auto i = static_cast<index_t>(k);
      const index_t a = c.node_a(i), b = c.node_b(i);
      displacement[k] = 0.5 * (gp.displacement.row(a) + gp.displacement.row(b)).transpose();
      if constexpr (requires { c.position_a(i, gp); }) {
        // Detected contacts: node_a/node_b are frame gridpoints of the blocks (for rigid blocks
        // their centroids), not points of the contact; the point is the mean of the two sides'
        // current contact points (contact::subcontact_position), written as reference +
        // displacement like every other point.
        reference[k] = contact::subcontact_position(c, i, gp) - displacement[k];
      } else {  // face contacts: the reference midpoint (the current one is reference + displacement)
        reference[k] = 0.5 * (gp.reference.row(a) + gp.reference.row(b)).transpose();
      }
      normal[k] = c.normal(i);
      area[k] = c.area(i);
      const auto& st = c.state(i);
      tensile_damage[k] = Law::tensile_damage(c.subcontact_params(i), st);
      status[k] = static_cast<std::int32_t>(Law::status(st));
      std::size_t j = 0;
      for (const field& f : Law::state_fields) {
        if (f.type == field::kind::scalar) {
          state[j++].values[k] = st.*f.scalar;
        } else if (f.type == field::kind::vector) {
          for (int d = 0; d < 3; ++d) state[j].values[3 * k + static_cast<std::size_t>(d)] = (st.*f.vector)[d];
          ++j;
        }
      }
    }
  }

  /// The state array called `name` (state_array_name), or nullptr.
  [[nodiscard]] const array* find(std::string_view name) const {
    for (const array& a : state)
      if (a.name == name) return &a;
    return nullptr;
  }

  /// Writes the snapshot as a .vtp of vertices (file comment). Throws io_error.
  void write(const std::filesystem::path& path, format fmt = format::binary) const {
    poly_data pd;
    pd.set_points(reference);
    for (std::size_t k = 0; k < size(); ++k) pd.add_vertex(static_cast<index_t>(k));
    pd.point_data.add_vector("displacement", std::span<const vec3>(displacement));
    pd.point_data.add_vector("normal", std::span<const vec3>(normal));
    pd.point_data.add_scalar("area_m2", std::span<const double>(area));
    pd.point_data.add_scalar("status", std::span<const std::int32_t>(status));
    pd.point_data.add_scalar("tensile_damage", std::span<const double>(tensile_damage));
    std::vector<vec3> vectors;
    for (const array& a : state) {
      if (a.components == 1) {
        pd.point_data.add_scalar(a.name, std::span<const double>(a.values));
      } else {
        vectors.resize(size());
        for (std::size_t k = 0; k < size(); ++k)
          vectors[k] = vec3(a.values[3 * k], a.values[3 * k + 1], a.values[3 * k + 2]);
        pd.point_data.add_vector(a.name, std::span<const vec3>(vectors));
      }
    }
    pd.write(path, fmt);
  }
};

/// Writes an embedded bar (reinforcement::embedded_truss: nodes(), bonded(n), slip(n),
/// bond_force(n), element_count(), element_node_a/b(e), axial_force(e), yielded(e)) as a .vtp of
/// one line per element (file comment). Throws io_error.
template <class Bar>
void write_bar_vtp(const std::filesystem::path& path, const Bar& bar, format fmt = format::binary) {
  const node_set& nodes = bar.nodes();
  std::vector<vec3> points;
  std::vector<double> slip, bond_force;
  for (index_t n = 0; n < nodes.size(); ++n) {
    points.push_back(nodes.reference.row(n).transpose());
    slip.push_back(bar.bonded(n) ? bar.slip(n) : 0.0);
    bond_force.push_back(bar.bonded(n) ? bar.bond_force(n) : 0.0);
  }
  poly_data pd;
  pd.set_points(std::move(points));
  std::vector<double> axial;
  std::vector<std::int32_t> yielded;
  for (index_t e = 0; e < bar.element_count(); ++e) {
    const index_t ends[2] = {bar.element_node_a(e), bar.element_node_b(e)};
    pd.add_line(ends);
    axial.push_back(bar.axial_force(e));
    yielded.push_back(bar.yielded(e) ? 1 : 0);
  }
  pd.point_data.add_vector("displacement", nodes.displacement);
  pd.point_data.add_scalar("slip_m", std::span<const double>(slip));
  pd.point_data.add_scalar("bond_force_N", std::span<const double>(bond_force));
  pd.cell_data.add_scalar("axial_force_N", std::span<const double>(axial));
  pd.cell_data.add_scalar("yielded", std::span<const std::int32_t>(yielded));
  pd.write(path, fmt);
}

}  // namespace tessera::io::vtk
