#pragma once
// What detected_contacts (contact/detected_contacts.hpp) refuses at construction (issue #40
// items 3 and 5): a material pair whose residual friction is 0 beside a non-zero phi_0 (or,
// starting unbonded, whose residual cohesion is 0 beside c_0 > 0), since every detected corner
// starts on the residual limit; and two blocks that overlap by more than the tolerance
// (params::allow_initial_overlap opts in); and a tolerance above max_tolerance_fraction of the
// thinnest block's width (refuse_large_tolerance). During a run, prepare_step refuses a step that
// moved a vertex farther than the rebuild trigger can follow (refuse_fast_motion). Not a public
// interface, but for max_tolerance_fraction.
//
// Cost: O(materials^2), O(candidate pairs) and O(faces x vertices) per block, once. Thread
// safety: they read their arguments only.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../../geometry/block_mesh.hpp"
#include "../../geometry/convex_polyhedron.hpp"
#include "../detection/detect.hpp"
#include "../material_table.hpp"

namespace tessera::contact {

/// The largest contact tolerance detected_contacts accepts, as a fraction of the thinnest block's
/// width (the least distance between a face's plane and the farthest vertex from it). A vertex
/// within the tolerance of a supporting plane joins the contact patch, and a rebuild comes every
/// tolerance / 2 of motion: a tolerance that reaches across a block puts corners of its far side
/// into its patches and lets a step carry it through a thin neighbour. A quarter keeps every
/// scene of the tests and examples with room for coarser tolerances: the largest share measured
/// is 6.5 % (rubble's default tolerance, 2 % of the mean block, against its thinnest Voronoi cell,
/// seeds 1 to 8); the 2 cm slab of test_rigid under 1 mm takes 5 %, the examples' other scenes
/// at most 2 %.
inline constexpr real max_tolerance_fraction = 0.25;

}  // namespace tessera::contact

namespace tessera::contact::detail {

/// Refuses a tolerance (m) above max_tolerance_fraction x the thinnest width of the blocks'
/// reference shapes, naming the block, its width and the fraction allowed.
inline void refuse_large_tolerance(const std::vector<geometry::convex_polyhedron>& shapes, real tolerance) {
  real thinnest = std::numeric_limits<real>::infinity();
  std::size_t which = 0;
  for (std::size_t b = 0; b < shapes.size(); ++b)
    for (index_t f = 0; f < shapes[b].face_count(); ++f) {
      const vec3 n = shapes[b].face_normal(f), c = shapes[b].face_centroid(f);
      real width = 0;  // farthest vertex behind the face's plane (outward normal)
      for (const vec3& v : shapes[b].vertices()) width = std::max(width, n.dot(c - v));
      if (width < thinnest) {
        thinnest = width;
        which = b;
      }
    }
  require(shapes.empty() || tolerance <= max_tolerance_fraction * thinnest, "detected_contacts: contact tolerance ",
          tolerance, " m is ", tolerance / thinnest, " x the width ", thinnest, " m of block ", which,
          ", the thinnest block; at most contact::max_tolerance_fraction = ", max_tolerance_fraction, " of it (",
          max_tolerance_fraction * thinnest, " m) is accepted, since vertices within the tolerance of a face join its "
          "contact patch. Typical tolerances are 1e-3 to 1e-2 of a block's size");
}

/// The trap of a detected set (issue #40 item 3): its corners start unbonded, on the residual
/// Coulomb limit c_res + sigma_c tan(phi_res), so a residual value left at 0 beside a non-zero
/// initial one silently gives joints weaker than the user wrote. Refused, per material pair in
/// use (the blocks' material ids), when the law has those fields:
///   phi_res = 0 while phi_0 > 0: always (new corners, and broken bonds, slide on phi_res);
///   c_res = 0 while c_0 > 0: when the pair starts unbonded (bond_faces off, or never_bonded),
///     since then c_0 is never used.
/// Frictionless joints are phi_0 = phi_res = 0; law::dry_joint fills both angles.
/// `table`: the law parameters per material pair; `bond_faces`: params::bond_faces.
template <class LawParams>
void refuse_unused_strengths(const material_table<LawParams>& table, const geometry::block_mesh& mesh,
                             bool bond_faces) {
  if constexpr (requires(const LawParams& q) {
                  q.shear.phi_0.radians();
                  q.shear.phi_res.radians();
                  real(q.shear.c_0);
                  real(q.shear.c_res);
                }) {
    std::vector<int> ids;
    for (index_t b = 0; b < mesh.block_count(); ++b) ids.push_back(mesh.material(b));
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (std::size_t i = 0; i < ids.size(); ++i)
      for (std::size_t j = i; j < ids.size(); ++j) {
        const auto& e = table.get(ids[i], ids[j]);
        const auto& sh = e.params.shear;
        require(!(sh.phi_res.radians() == 0 && sh.phi_0.radians() > 0), "detected_contacts: material pair (",
                ids[i], ", ", ids[j], ") has residual friction phi_res = 0 deg while phi_0 = ", sh.phi_0.degrees(),
                " deg: detected contacts start unbonded and slide at phi_res (so do broken bonds), which makes "
                "these joints frictionless. Set shear.phi_res (e.g. = phi_0), or build the params with "
                "law::dry_joint(k_n, k_s, phi); for frictionless joints write phi_0 = phi_res = 0");
        const bool starts_bonded = bond_faces && e.bonded;
        require(starts_bonded || !(sh.c_res == 0 && sh.c_0 > 0), "detected_contacts: material pair (", ids[i],
                ", ", ids[j], ") has residual cohesion c_res = 0 Pa while c_0 = ", sh.c_0,
                " Pa, and its contacts start unbonded (",
                bond_faces ? "the table declares the pair never_bonded" : "bond_faces is false",
                "), on the residual cohesion c_res: c_0 would never be used. Set shear.c_res, or "
                "c_0 = 0 for a cohesionless joint (law::dry_joint), or bond_faces = true for faces that start "
                "bonded (law::bonded_joint)");
      }
  }
}

/// params::allow_initial_overlap is false: refuses, after the construction's detection pass,
/// a candidate pair whose penetration depth -g (the common plane's gap, exact for overlapping
/// convex blocks: common_plane.hpp) exceeds the tolerance. Names the deepest such pair.
/// `workspace`: that pass's (its candidate pairs and their common planes); `tolerance` in m.
inline void refuse_initial_overlaps(const detection::detection_workspace& workspace, real tolerance) {
  const auto& planes = workspace.planes;
  const auto& pairs = workspace.candidates;
  std::size_t deepest = planes.size();
  for (std::size_t k = 0; k < planes.size(); ++k)
    if (-planes[k].gap > tolerance && (deepest == planes.size() || planes[k].gap < planes[deepest].gap))
      deepest = k;
  if (deepest == planes.size()) return;
  throw invalid_input(tessera::detail::concat(
      "detected_contacts: blocks ", pairs[deepest].a, " and ", pairs[deepest].b, " overlap by ", -planes[deepest].gap,
      " m at the start, more than the contact tolerance ", tolerance,
      " m (a placement error: the overlap's springs would push them apart with energy no force supplied); move "
      "them apart, or set params::allow_initial_overlap = true if the overlap is meant"));
}

/// prepare_step's refusal during a run. The rebuild comes at the first step whose motion since the
/// block was last detected passes the trigger (`trigger`, m: 0.39 x the tolerance for rigid blocks,
/// detected/incremental.hpp; tolerance / 2 less the deformable fit's deviation), so every gap of
/// up to the tolerance is seen before it closes; a watched vertex already past the tolerance
/// (deformable: twice the trigger) covered more than the tolerance less the trigger in ONE step, so
/// blocks may overlap by more than the tolerance unseen (the same depth the constructor refuses),
/// and the rebuild would load a spring by the overlap. `moved2`: per block, the squared largest
/// motion (m^2) of its watched gridpoints; `largest`: their maximum; `steps`: steps since the last
/// rebuild; `tolerance`: params::tolerance (m).
[[noreturn]] inline void refuse_fast_motion(const std::vector<real>& moved2, real largest, index_t steps, real tolerance,
                                            real trigger) {
  // A split run's vote (set_motion_vote): the largest motion may be another rank's block's.
  const auto found = std::find(moved2.begin(), moved2.end(), largest);
  const std::string block = found == moved2.end() ? std::string("a block of another MPI rank")
                                                  : tessera::detail::concat("block ", found - moved2.begin());
  throw invalid_input(tessera::detail::concat(
      "detected_contacts: a vertex of ", block, " moved ", std::sqrt(largest),
      " m since the block was last detected (", steps, " step(s) after the last contact rebuild), more than the "
      "tolerance ", tolerance, " m (a rebuild comes once it passes ", trigger,
      " m, so one step covered more than the difference): blocks may overlap "
      "by more than the tolerance unseen. Either the blocks move too fast for the step (a thrown or driven block: "
      "lower the time step, solver_options::safety or dt, or raise the contact tolerance), or a contact stiffness "
      "too soft for the loads lets a block sink more than the tolerance into what it rests on (its overlap "
      "W / (k_n A) near or above the tolerance: raise k_n; a smaller step does not help)"));
}

}  // namespace tessera::contact::detail
