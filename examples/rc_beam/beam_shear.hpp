#pragma once
// Where the shear goes (issue #41 item 2): the vertical force carried across sections of the shear
// span, split by what carries it.
//
// A section at x_s cuts the half beam into a left part (the blocks whose centre, the mean of their
// cell's face vertices, lies at x < x_s, with the bar nodes at x < x_s) and a right part; the
// boundary between them is the jagged line of block faces nearest x_s. The shear it carries is
// the vertical force the right part puts on the left one, V = -sum F_left,y (N; positive: the
// support reaction carried up through the section), from
//   - the sub-contacts joining a left and a right block (their last force, face_contacts::force),
//     by their state: intact (neither softened, broken nor slipped: uncracked concrete, the
//     compression zone among it), softening (past the tensile peak, not broken nor slipped: the
//     cohesion of an opening crack), broken or slipped (friction and residual cohesion of a crack
//     that has failed in tension or in shear);
//   - the bars: the truss elements crossing x_s, N times the vertical component of their current
//     chord. Trusses carry axial force only, so this is zero but for the bars' kink where the
//     concrete moves their nodes apart vertically (no dowel action, as the study's cables);
//   - not counted: bond springs whose bar node and host zone lie on different sides (a bond
//     spring acts along the bar's axis, so it carries no vertical force either).
// In the full beam's right span (support_on_right) the support is on the right part, so the signs
// turn: V = +sum F_left,y, the force the left part puts on the right one.
// Quasi-static equilibrium of the left part asks V = the support reaction, P/2; the table gives
// both (their ratio, closure, shows what the split leaves out: inertia and damping of a
// mass-scaled run, the bond springs).

#include <array>
#include <cmath>
#include <vector>

#include "rc_beam/beam.hpp"

namespace tessera::scenes {

/// The shear across one section (N), by carrier (file comment).
struct beam_shear_split {
  real x = 0;                 ///< the section (m)
  real intact = 0, softening = 0, broken_or_slipped = 0, bars = 0;
  real reaction = 0;          ///< the support reaction at the same sample, P/2 (N)
  [[nodiscard]] real total() const { return intact + softening + broken_or_slipped + bars; }
};

/// The sections' crossing sub-contacts and truss elements, found once from the reference geometry.
class beam_shear_sections {
 public:
  template <class Contacts, class Bar>
  beam_shear_sections(const geometry::tessellation& tess, const Contacts& c, const Bar& bar, const node_set& bar_nodes,
                      const std::vector<real>& sections, bool support_on_right = false)
      : x_(sections), side_(support_on_right ? -1.0 : 1.0) {
    std::vector<real> centre_x(static_cast<std::size_t>(tess.cell_count()), 0);
    for (index_t cell = 0; cell < tess.cell_count(); ++cell) {
      real sum = 0;
      int count = 0;
      for (index_t f = tess.first_face(cell); f < tess.end_face(cell); ++f)
        for (index_t v : tess.face(f)) sum += tess.vertices[static_cast<std::size_t>(v)].x(), ++count;
      centre_x[static_cast<std::size_t>(cell)] = count > 0 ? sum / count : 0;
    }
    for (real xs : x_) {
      std::vector<crossing> list;
      for (index_t i = 0; i < c.size(); ++i) {
        const bool a_left = centre_x[static_cast<std::size_t>(c.block_a(i))] < xs;
        const bool b_left = centre_x[static_cast<std::size_t>(c.block_b(i))] < xs;
        if (a_left != b_left) list.push_back({i, (b_left ? 1.0 : -1.0) * side_});
      }
      contacts_.push_back(std::move(list));
      std::vector<index_t> elements;
      for (index_t e = 0; e < bar.element_count(); ++e) {
        const real xa = bar_nodes.reference(bar.element_node_a(e), 0), xb = bar_nodes.reference(bar.element_node_b(e), 0);
        if ((xa < xs) != (xb < xs)) elements.push_back(e);
      }
      elements_.push_back(std::move(elements));
    }
  }

  /// The split at every section now; `reaction` the support reaction P/2 (N).
  template <class Contacts, class Bar>
  [[nodiscard]] std::vector<beam_shear_split> split(const Contacts& c, const Bar& bar, const node_set& bar_nodes,
                                                    real reaction) const {
    std::vector<beam_shear_split> out;
    for (std::size_t k = 0; k < x_.size(); ++k) {
      beam_shear_split s;
      s.x = x_[k];
      s.reaction = reaction;
      for (const crossing& cr : contacts_[k]) {
        const real v = -cr.sign * c.force(cr.subcontact).y();  // -F_left,y: force on node_b is force(i)
        const law::contact_status f = c.state(cr.subcontact).flags;
        if (law::has(f, law::contact_status::broken_tension) || law::has(f, law::contact_status::slipped))
          s.broken_or_slipped += v;
        else if (law::has(f, law::contact_status::softening))
          s.softening += v;
        else
          s.intact += v;
      }
      for (index_t e : elements_[k]) {
        const index_t a = bar.element_node_a(e), b = bar.element_node_b(e);
        const vec3 chord = bar_nodes.position(b) - bar_nodes.position(a);
        const real n = chord.norm();
        // The left node pulls the element's left end; on the left part the element pulls towards
        // the right node with its tension N along the chord.
        const real toward_right = (bar_nodes.reference(b, 0) > bar_nodes.reference(a, 0) ? 1.0 : -1.0) * side_;
        if (n > 0) s.bars -= toward_right * bar.axial_force(e) * chord.y() / n;
      }
      out.push_back(s);
    }
    return out;
  }
  [[nodiscard]] const std::vector<real>& sections() const { return x_; }

 private:
  struct crossing {
    index_t subcontact;
    real sign;  ///< +1: block b is on the left, -1: block a is (turned in the right span)
  };
  std::vector<real> x_;
  real side_;  ///< +1, or -1 with the support on the right
  std::vector<std::vector<crossing>> contacts_;
  std::vector<std::vector<index_t>> elements_;
};

}  // namespace tessera::scenes
