#pragma once
// The Brazilian disc of brazilian/main.cpp (the file comment there says what it measures), as a
// function of the disc's options and a concrete recipe, so that calibrate --targets runs the same
// scene: run_brazilian_disc builds the disc, loads it between the strips to the split (or to
// max_displacement) and returns the figures and the curve; main.cpp writes them.

#include <tessera/core/parallel.hpp>
#include <tessera/geometry/shapes.hpp>
#include <tessera/geometry/voronoi.hpp>
#include <tessera/geometry/zoning.hpp>
#include <tessera/presets/pulatsu2020.hpp>
#include <tessera/solver/recorders.hpp>
#include <tessera/solver/solver.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>

#include "common/scenes.hpp"

namespace tessera::scenes {

/// The disc and its loading (brazilian's flags, SI units).
struct disc_options {
  std::uint64_t seed = 1;
  int blocks = 0;                  ///< Voronoi blocks in the disc; 0 = the recipe's block size
  int sides = 36;                  ///< the disc's polygon, a multiple of 4 (flats at top and bottom)
  real diameter = 0.15, thickness = 0.06;  ///< m
  real rate = 5e-3;                ///< strip speed (m/s)
  real step_displacement = 2e-9;   ///< strip travel per step (m)
  real max_displacement = 3e-4;    ///< the run ends here if the disc has not split (m)
};

/// What one disc measures (SI; NaN where the event was not reached).
struct disc_result {
  std::vector<double> u, p_top, p_bottom, opening;  ///< the curve: strip travel (m), loads (N), opening (m)
  int blocks = 0;
  bool split = false;                                ///< the diametral split was found
  bool split_by_hinge = false;                       ///< found in the middle third after the load fell (not across the middle two thirds)
  real p_max = 0, u_peak = 0, p_bottom_at_peak = 0;  ///< largest load before the split (N), at (m), bottom's (N)
  real u_split = 0, p_split = 0, w_split = 0;        ///< at the split: travel (m), load (N), opening (m)
  real opening_end = 0;                              ///< m
  real p_crack = 0, w_crack = 0;                     ///< the diametral crack's opening: load (N), opening (m)
  real f_sp = 0, f_crack = 0, f_t = 0;               ///< 2 P / (pi D t) at P_max (NaN unless split), at the crack's opening; f_T (Pa)
  real mismatch = 0;                                 ///< (top - bottom) / top at the peak
  real cracked = 0, near = 0;                        ///< cracked area, and within D/6 of the loaded diameter (m^2)
  real phi_res_deg = 0, dt = 0, energy_error = 0, strip = 0;  ///< deg, s, -, strip width (m)
  std::int64_t steps = 0;
  std::string damping;
  double runtime_s = 0;
  /// f_sp / f_T: NaN for a disc that did not split (its largest load is the wedges', not a strength).
  [[nodiscard]] real ratio() const { return f_sp / f_t; }
};

/// The disc of `recipe`'s concrete (contacts, block size, zoning, block material as the recipe
/// has them). Throws invalid_input naming a bad option.
template <class joint_law>
disc_result run_brazilian_disc(const disc_options& o, const concrete_recipe<joint_law>& recipe) {
  using model = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<joint_law>>;
  require(o.sides % 4 == 0 && o.sides >= 8, "brazilian: --sides = ", o.sides, " must be a multiple of 4 (flats at top and bottom)");
  disc_result r;
  const real pi = std::numbers::pi, D = o.diameter, R = D / 2, a = R * std::cos(pi / o.sides);
  r.strip = 2 * R * std::sin(pi / o.sides);
  // phase pi / sides puts a face across x and, with sides = 4k, across y: the strips at y = +-a.
  const auto disc = geometry::cylinder_prism(vec3::Zero(), vec3::UnitZ(), R, o.thickness, static_cast<index_t>(o.sides), pi / o.sides);
  const real disc_volume = 0.5 * o.sides * R * R * std::sin(2 * pi / o.sides) * o.thickness;
  r.blocks = o.blocks > 0 ? o.blocks : static_cast<int>(recipe.blocks_in(disc_volume));  // the recipe's block size
  const typename joint_law::params joint = recipe.contact;
  joint_law::validate(joint);  // names a bad parameter (c_res, phi_res, G_II) before the scene is built
  r.phi_res_deg = joint.shear.phi_res.degrees();
  const auto tess = geometry::random_voronoi(disc, static_cast<index_t>(r.blocks), o.seed);
  const auto mesh = geometry::zone_blocks(tess, recipe.zoning());
  solver_options options;
  options.mass_scaling_dt = o.step_displacement / o.rate;  // quasi-static: the strip moves du per step
  model s(tess, mesh, recipe.block_material, contact::material_table<typename joint_law::params>(joint), {}, options);
  const auto bottom = s.gridpoints_on_plane(1, -a, 1e-9 * D), top = s.gridpoints_on_plane(1, a, 1e-9 * D);
  s.fix(bottom);                                   // bottom strip held
  s.prescribe_velocity(top, vec3(0, -o.rate, 0));  // top strip pushed down at the rate
  const auto start = std::chrono::steady_clock::now();
  bool done = false;
  const auto every = static_cast<index_t>(std::max<real>(1, std::round(2e-7 / o.step_displacement)));  // a sample per 0.2 um
  // Split: across the middle two thirds of the diameter (|y| < D/3; the strips' wedges aside) no chain of
  // intact contacts (tensile damage < 0.5, not slipped) joins a block on the flat x = -a to one on x = +a;
  // or, once the load has fallen to hinge_drop of its largest, no such chain across the middle third
  // (|y| < D/6): halves that turn apart about a compressed chain beside a strip have split (a 300-block
  // disc opened 1 mm that way, its load down a third, with a chain left in the middle two thirds).
  constexpr real hinge_drop = 0.9;
  const auto left = s.blocks_on_plane(0, -a, 1e-9 * D), right = s.blocks_on_plane(0, a, 1e-9 * D);
  std::vector<std::size_t> root(static_cast<std::size_t>(s.block_count()));
  const auto split = [&](const model& m, real band) {  // (no chain within |y| < band)
    std::iota(root.begin(), root.end(), std::size_t{0});
    const auto find = [&](index_t block) {  // union-find root, halving the path
      for (auto b = static_cast<std::size_t>(block);; b = root[b] = root[root[b]]) if (root[b] == b) return b;
    };
    const auto& c = m.contacts();
    for (index_t i = 0; i < c.size(); ++i)
      if (std::abs(c.position(i, m.gridpoints()).y()) < band &&
          joint_law::tensile_damage(c.subcontact_params(i), c.state(i)) < 0.5 &&
          !law::has(joint_law::status(c.state(i)), law::contact_status::slipped))
        root[find(c.block_a(i))] = find(c.block_b(i));
    for (index_t l : left)
      for (index_t rr : right)
        if (find(l) == find(rr)) return false;
    return true;
  };
  // The opening across the loaded diameter: the mean x displacement of the gridpoints on the flat
  // x = +a minus that on x = -a, over the middle third of the height (|y| < D/6).
  std::vector<index_t> flank[2];
  for (index_t g = 0; g < s.gridpoints().size(); ++g)
    if (const real x = s.gridpoints().reference(g, 0); std::abs(std::abs(x) - a) <= 1e-9 * D &&
                                                      std::abs(s.gridpoints().reference(g, 1)) < D / 6)
      flank[x > 0 ? 1 : 0].push_back(g);
  require(!flank[0].empty() && !flank[1].empty(), "brazilian: no gridpoint on the flats x = +-a across the middle");
  const auto opening = [&](const model& m) {
    real w = 0;
    for (int k = 0; k < 2; ++k) {
      real mean = 0;
      for (index_t g : flank[k]) mean += m.gridpoints().displacement(g, 0);
      w += (k == 1 ? 1 : -1) * mean / static_cast<real>(flank[k].size());
    }
    return w;
  };
  const auto observe = [&](const model& m) {
    const real p = -recorders::reaction_sum(m.gridpoints(), top).y(), pb = recorders::reaction_sum(m.gridpoints(), bottom).y();
    r.u.push_back(o.rate * m.time()), r.p_top.push_back(p), r.p_bottom.push_back(pb), r.opening.push_back(opening(m));
    if (p > r.p_max && r.u_split == 0) r.p_max = p, r.u_peak = r.u.back(), r.p_bottom_at_peak = pb;
    if (r.u_split == 0) {
      const bool across = split(m, D / 3);
      if (across || (p <= hinge_drop * r.p_max && split(m, D / 6)))
        r.u_split = r.u.back(), r.p_split = p, r.w_split = r.opening.back(), r.split_by_hinge = !across;
    }
    done = r.u.back() >= o.max_displacement || (r.u_split > 0 && r.u.back() > 1.2 * r.u_split);
  };
  s.run_until([&](const model&) { return done; }, static_cast<std::int64_t>(2 * o.max_displacement / o.step_displacement),
              recorders::every(every, observe));
  r.runtime_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // The crack: sub-contacts with tensile damage >= 0.5 by area; near: within D/6 of the loaded diameter.
  const auto& c = s.contacts();
  for (index_t i = 0; i < c.size(); ++i)
    if (joint_law::tensile_damage(c.subcontact_params(i), c.state(i)) >= 0.5)
      r.cracked += c.area(i), r.near += std::abs(c.position(i, s.gridpoints()).x()) <= D / 6 ? c.area(i) : 0;
  // f_sp only for a disc that split: the largest load of one that did not is the cap's, not a strength.
  r.split = r.u_split > 0;
  const real none = std::numeric_limits<real>::quiet_NaN(), area = pi * D * o.thickness;
  r.f_sp = r.split ? 2 * r.p_max / area : none;
  r.f_t = recipe.f_T;  // the concrete's tensile strength (the prism: its calibrated peak)
  r.mismatch = (r.p_max - r.p_bottom_at_peak) / r.p_max;
  // The diametral crack opening: the first load at which the opening across the diameter exceeds twice
  // its elastic value (the compliance w / P at the first sample above 20 % of P_max, before the split).
  // The load after it, up to P_max, is carried by the wedges under the strips as the crack opens.
  r.p_crack = none, r.w_crack = none;
  for (std::size_t k = 0, k0 = 0; k < r.u.size() && (!r.split || r.u[k] <= r.u_split); ++k) {
    if (k0 == 0 && r.p_top[k] >= 0.2 * r.p_max) k0 = k;
    if (k0 > 0 && r.p_top[k] > 0.2 * r.p_max && r.opening[k] > 2 * (r.opening[k0] / r.p_top[k0]) * r.p_top[k]) {
      r.p_crack = r.p_top[k], r.w_crack = r.opening[k];
      break;
    }
  }
  r.f_crack = 2 * r.p_crack / area;
  r.opening_end = opening(s);
  r.dt = s.dt();
  r.steps = s.step_count();
  r.damping = s.damping_in_force();
  r.energy_error = s.energies().error_rel();
  return r;
}

}  // namespace tessera::scenes
