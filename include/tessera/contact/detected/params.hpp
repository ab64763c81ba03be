#pragma once
// What contact::detected_contacts<Law> (contact/detected_contacts.hpp) takes at construction:
// detected_contacts<Law>::params is detected_params<Law::params>. Header-only, no state beyond
// its fields; copyable.

#include <utility>

#include "../../core/types.hpp"
#include "../material_table.hpp"

namespace tessera::contact {

/// Which contacts detected_contacts::add_stiffness_bounds covers for rigid blocks
/// (detected/step_bound.hpp): those present until the next rebuild, or every contact a block could
/// carry.
enum class step_bound_scope { present_contacts, whole_surface };

/// What detected_contacts<Law>'s constructor takes; LawParams = Law::params.
template <class LawParams>
struct detected_params {
  /// Law parameters per pair of block materials. A detected sub-contact starts unbonded
  /// (Law::unbonded_state: no tension, residual cohesion c_res and friction phi_res) unless
  /// bond_faces says otherwise. The constructor refuses a pair whose phi_res is 0 while phi_0 > 0,
  /// and one that starts unbonded with c_res = 0 while c_0 > 0 (values that would be silently
  /// unused); law::dry_joint and law::bonded_joint (law/joints.hpp) fill them all.
  material_table<LawParams> law{};
  /// Contact tolerance (m, > 0): pairs whose gap is at most this touch, and vertices within it
  /// of a block's supporting plane form the patch. Typically 1e-3 to 1e-2 of a block's size; above
  /// contact::max_tolerance_fraction (1/4) of the thinnest block's width it is refused.
  real tolerance = 0;
  /// A rebuild at least every this many steps (>= 1), besides the motion trigger.
  index_t max_rebuild_interval = 1000;
  /// true: at construction, the corners of every face-to-face patch whose faces coincide (each
  /// corner's |gap| <= bond_gap_fraction x tolerance) between a material pair the table
  /// declares bonded start intact (state_type{}: the law's tensile strength and cohesion), as
  /// face_contacts bonds a tessellation's faces. Such a bonded face, once broken, keeps its
  /// residual state through every rebuild, so the crack can open, slide onto new neighbours,
  /// close and reopen. Corners born later start unbonded. false: every corner starts unbonded.
  bool bond_faces = false;
  /// true for blocks::deformable (the solver checks that it matches its block model): a
  /// sub-contact's material point is located in a surface zone of each block (its four
  /// gridpoints, barycentric weights), a face-to-face patch puts its sub-contacts at the surface
  /// gridpoints of the side whose tributary areas fit the patch, detection reads each block's
  /// affine fit and the stable step a bound per surface gridpoint (detected/deformable_fit.hpp).
  /// false: rigid blocks (blocks::rigid), one frame per block.
  bool deformable_blocks = false;
  /// false (default): at construction, two blocks that overlap by more than the tolerance
  /// (penetration depth -g of their common plane > tolerance, common_plane.hpp) are refused
  /// (invalid_input naming both blocks, the depth and the tolerance): such an overlap is a
  /// placement error, and its springs would push the blocks apart with energy no force supplied.
  /// An overlap within the tolerance (a block placed at its static overlap W/(k_n A), faces
  /// that coincide up to round-off) is accepted. true: any initial overlap is accepted, its
  /// springs loaded from the start (the run's initial energy), for scenes that mean it.
  bool allow_initial_overlap = false;
  /// Rigid blocks: the stable step from the sub-contacts present until the next rebuild
  /// (present_contacts; the solver chooses dt again after each rebuild) or from every contact a
  /// block could carry (whole_surface; a dt that holds for the whole run). detected/step_bound.hpp,
  /// "Stable step". Deformable blocks keep their per-gridpoint bound either way.
  step_bound_scope step_bound = step_bound_scope::present_contacts;

  detected_params() = default;
  /// The table (a plain law params converts), tolerance (m, > 0), rebuild interval (steps), bonded start and block kind; checked when the contact set is built
  detected_params(material_table<LawParams> table, real tol, index_t interval = 1000, bool bond = false,
         bool deformable = false)
      : law(std::move(table)), tolerance(tol), max_rebuild_interval(interval), bond_faces(bond),
        deformable_blocks(deformable) {}
};

}  // namespace tessera::contact
