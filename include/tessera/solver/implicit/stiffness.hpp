#pragma once
// The global stiffness of a model of deformable blocks and bonded face contacts, for the implicit
// quasi-static solve (quasi_static.hpp; issue #43, candidate 3): K (N/m) over 3 degrees of freedom
// per gridpoint, dof 3 i + c = component c of gridpoint i, as an Eigen::SparseMatrix.
//
// Zones (blocks::deformable<Zone>, constant-strain tetrahedra): K_z = V_z B_z^T C B_z in the
// reference frame, B_z the strain-displacement matrix of the zone's shape-function gradients
// (Voigt xx yy zz yz zx xy, engineering shears, as Zone::elasticity_matrix), the small-strain
// linearisation of the co-rotated zone kernel (blocks/detail/zone_kernel.hpp) about the
// reference state. The gradients and volumes are formed from the block_mesh by the function the
// blocks were built with (blocks::detail::linear_tet), so they are the blocks' own to the bit; the
// mesh is checked against the blocks (zone count, every zone volume).
//
// Sub-contacts (contact::face_contacts<Law>): each links gridpoint a of block A to the coincident
// gridpoint b of block B (contact/face_contacts.hpp), so the relative displacement is
// d = u_b - u_a (interpolation weights -1 on a, +1 on b, none elsewhere) and the traction on b is
// -(sigma_n n + tau). With secant normal and shear stiffnesses k_n, k_s (Pa/m) and tributary area
// A (m^2), the sub-contact adds
//     [ K  -K ]
//     [-K   K ]   on (a, b),   K = A (k_s I + (k_n - k_s) n n^T)   (N/m),
// n the sub-contact's unit normal A -> B.
//
// Secant stiffnesses of a sub-contact's present state (subcontact_secant): intact or closed,
// k_n and k_s; softening in tension, the secant sigma_n / u_n of the normal branch (sigma_n on the
// envelope, u_n the total opening); broken in tension and open, zero in both directions; slipped,
// the shear secant |tau| / |u_s| (at most k_s). They make K symmetric positive semi-definite for
// any state, which the Cholesky factorisation of the solve needs; the tangent of a softening
// branch would not be.
//
// Cost: zone_stiffness O(144 zones) triplets once; contact_stiffness O(36 sub-contacts) triplets
// per call. Pure functions of their arguments; thread-safe.

#include <algorithm>
#include <cmath>
#include <concepts>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>  // mat3::inverse in blocks::detail::linear_tet
#include <Eigen/SparseCore>

#include "../../blocks/deformable.hpp"
#include "../../blocks/detail/zone_layout.hpp"
#include "../../contact/face_contacts.hpp"
#include "../../core/errors.hpp"
#include "../../core/types.hpp"
#include "../../geometry/block_mesh.hpp"
#include "../../law/concepts.hpp"

namespace tessera::implicit {

using sparse_matrix = Eigen::SparseMatrix<real>;
using triplet = Eigen::Triplet<real>;

/// A contact law whose state the secant rule can read: cohesive_frictional and its wrappers.
/// | expression                    | meaning                                                        |
/// |-------------------------------|----------------------------------------------------------------|
/// | L::normal_stiffness(p)        | k_n (Pa/m)                                                     |
/// | L::shear_stiffness(p)         | k_s (Pa/m)                                                     |
/// | L::status(s)                  | law::contact_status bits: softening, broken_tension, slipped   |
/// | L::tensile_strength(p, s)     | current tensile strength f_t (Pa), lowered as the crack opens   |
/// | s.sigma_n, s.u_n, s.u_p       | normal stress (Pa), total and irreversible opening (m)          |
/// | s.tau                         | shear stress vector (Pa)                                       |
template <class L>
concept SecantLaw = law::ContactLaw<L> && requires(const typename L::params& p, const typename L::state& s) {
  { L::normal_stiffness(p) } -> std::convertible_to<real>;
  { L::shear_stiffness(p) } -> std::convertible_to<real>;
  { L::status(s) } -> std::same_as<law::contact_status>;
  { L::tensile_strength(p, s) } -> std::convertible_to<real>;
  { s.sigma_n } -> std::convertible_to<real>;
  { s.u_n } -> std::convertible_to<real>;
  { s.u_p } -> std::convertible_to<real>;
  { s.tau.norm() } -> std::convertible_to<real>;
};

/// Secant stiffnesses of one sub-contact (Pa/m).
struct secant_stiffness {
  real normal = 0;  ///< secant normal stiffness (Pa/m)
  real shear = 0;  ///< secant shear stiffness (Pa/m)
  friend bool operator==(const secant_stiffness&, const secant_stiffness&) = default;
};

/// The secant stiffnesses of a sub-contact in state s with total tangential relative
/// displacement of magnitude slip (m) (file comment): broken in tension and open (u_n > u_p):
/// zero; softening, in tension: sigma_n / u_n, at most k_n; otherwise k_n;
/// slipped: |tau| / slip, at most k_s (k_s for no slip); otherwise k_s.
template <SecantLaw L>
[[nodiscard]] secant_stiffness subcontact_secant(const typename L::params& p, const typename L::state& s,
                                                 real slip) noexcept {
  const real k_n = L::normal_stiffness(p), k_s = L::shear_stiffness(p);
  const law::contact_status flags = L::status(s);
  if (law::has(flags, law::contact_status::broken_tension) && s.u_n > s.u_p) return {0, 0};
  secant_stiffness k{k_n, k_s};
  // An intact contact keeps k_n exactly (sigma_n / u_n would differ from it by round-off, and the
  // solve refactorises when a secant changes).
  if (law::has(flags, law::contact_status::softening) && s.sigma_n > 0 && s.u_n > 0)
    k.normal = std::min(k_n, s.sigma_n / s.u_n);
  if (law::has(flags, law::contact_status::slipped) && slip > 0) k.shear = std::min(k_s, s.tau.norm() / slip);
  return k;
}

/// Appends to `out` the 144 entries K_z = V_z B_z^T C B_z (N/m) of every zone of `blocks`, in
/// global dofs (3 gridpoint + component). Throws invalid_input when `mesh` is not the mesh the
/// blocks were built from (zone count, a zone volume that differs).
template <zones::ZoneModel Zone>
void add_zone_stiffness(const geometry::block_mesh& mesh, const blocks::deformable<Zone>& blocks,
                        std::vector<triplet>& out) {
  const index_t n_z = mesh.zone_count();
  require(n_z == blocks.zone_count(), "implicit stiffness: the block_mesh has ", n_z, " zones, the blocks ",
          blocks.zone_count(), "; pass the mesh the blocks were built from");
  out.reserve(out.size() + static_cast<std::size_t>(144 * n_z));
  for (index_t z = 0; z < n_z; ++z) {
    const auto zs = static_cast<std::size_t>(z);
    const auto& c = mesh.zones[zs];
    std::array<vec3, 4> x;
    for (std::size_t a = 0; a < 4; ++a) x[a] = mesh.gridpoints[static_cast<std::size_t>(c[a])];
    const blocks::detail::tet_shape shape = blocks::detail::linear_tet(x, z, mesh.zone_block[zs]);
    require(shape.volume == blocks.zone_volume(z), "implicit stiffness: zone ", z, " has volume ", shape.volume,
            " m^3 in the block_mesh and ", blocks.zone_volume(z), " m^3 in the blocks; pass the mesh they were built from");
    const Eigen::Matrix<real, 6, 6> elasticity = Zone::elasticity_matrix(blocks.material_of_block(mesh.zone_block[zs]));
    Eigen::Matrix<real, 6, 12> b = Eigen::Matrix<real, 6, 12>::Zero();
    for (int a = 0; a < 4; ++a) {
      const auto g = [&](int k) { return shape.gradient[static_cast<std::size_t>(3 * a + k)]; };
      b(0, 3 * a) = g(0);
      b(1, 3 * a + 1) = g(1);
      b(2, 3 * a + 2) = g(2);
      b(3, 3 * a + 1) = g(2);
      b(3, 3 * a + 2) = g(1);
      b(4, 3 * a) = g(2);
      b(4, 3 * a + 2) = g(0);
      b(5, 3 * a) = g(1);
      b(5, 3 * a + 1) = g(0);
    }
    const Eigen::Matrix<real, 12, 12> k = shape.volume * b.transpose() * elasticity * b;
    for (int a = 0; a < 4; ++a)
      for (int bb = 0; bb < 4; ++bb)
        for (int r = 0; r < 3; ++r)
          for (int s = 0; s < 3; ++s)
            out.emplace_back(3 * c[static_cast<std::size_t>(a)] + r, 3 * c[static_cast<std::size_t>(bb)] + s,
                             k(3 * a + r, 3 * bb + s));
  }
}

/// Appends to `out` the 36 entries of one sub-contact spring between gridpoints a and b (file
/// comment): K = area (k_s I + (k_n - k_s) n n^T) (N/m), n a unit normal, area (m^2) > 0, the
/// secant stiffnesses k (Pa/m) >= 0. Entries are written even when k is zero, so the sparsity
/// pattern of an assembled K does not depend on the contact states.
inline void add_subcontact_stiffness(index_t a, index_t b, const vec3& n, real area, const secant_stiffness& k,
                                     std::vector<triplet>& out) {
  const mat3 block = area * (k.shear * mat3::Identity() + (k.normal - k.shear) * n * n.transpose());
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) {
      const real v = block(r, s);
      out.emplace_back(3 * a + r, 3 * a + s, v);
      out.emplace_back(3 * b + r, 3 * b + s, v);
      out.emplace_back(3 * a + r, 3 * b + s, -v);
      out.emplace_back(3 * b + r, 3 * a + s, -v);
    }
}

/// Appends the springs of every sub-contact of `contacts` with the secant stiffnesses `secants`
/// (one per sub-contact, Pa/m) and the normals `normals` (one unit vector per sub-contact).
/// Throws invalid_input when a list does not have one entry per sub-contact.
template <class Law>
void add_contact_stiffness(const contact::face_contacts<Law>& contacts, const std::vector<vec3>& normals,
                           const std::vector<secant_stiffness>& secants, std::vector<triplet>& out) {
  const auto n = static_cast<std::size_t>(contacts.size());
  require(secants.size() == n && normals.size() == n, "implicit stiffness: ", secants.size(), " secant stiffnesses and ",
          normals.size(), " normals for ", n, " sub-contacts");
  out.reserve(out.size() + 36 * n);
  for (index_t i = 0; i < contacts.size(); ++i)
    add_subcontact_stiffness(contacts.node_a(i), contacts.node_b(i), normals[static_cast<std::size_t>(i)],
                             contacts.area(i), secants[static_cast<std::size_t>(i)], out);
}

/// The elastic stiffness (N/m, 3 dofs per gridpoint, no supports) of zones and intact
/// sub-contacts at the reference state: zones + every sub-contact with its k_n, k_s and its
/// current normal. The matrix the first increment of a quasi-static solve factorises.
template <zones::ZoneModel Zone, SecantLaw Law>
[[nodiscard]] sparse_matrix elastic_stiffness(const geometry::block_mesh& mesh, const blocks::deformable<Zone>& blocks,
                                              const contact::face_contacts<Law>& contacts) {
  std::vector<triplet> t;
  add_zone_stiffness(mesh, blocks, t);
  std::vector<vec3> normals;
  std::vector<secant_stiffness> secants;
  for (index_t i = 0; i < contacts.size(); ++i) {
    normals.push_back(contacts.normal(i));
    const auto& p = contacts.subcontact_params(i);
    secants.push_back({Law::normal_stiffness(p), Law::shear_stiffness(p)});
  }
  add_contact_stiffness(contacts, normals, secants, t);
  const index_t n = 3 * mesh.gridpoint_count();
  sparse_matrix k(n, n);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

}  // namespace tessera::implicit
