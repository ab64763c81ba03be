// A scene of one's own, as docs/guide.md writes it and the README shows it: a semicircular
// masonry arch of 20 voussoirs on dry joints, standing under its own weight. Built against the
// installed package (tests/consumer), so the README cannot drift from the code. The arch is
// 0.4 m thick on a 2.2 m mean radius, t/R = 0.18, above the least thickness of a semicircular
// arch under self-weight (Heyman: t/R = 0.106), so it must stand: the run must settle, the held base
// must carry the whole weight, and the crown must sag by less than a millimetre.
#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/law.hpp>
#include <tessera/solver.hpp>
#include <tessera/instances.hpp>  // its solver compiled once: link tessera::instances

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

using namespace tessera;

int main() {
  // 1. geometry: a base slab (block 0) and 20 voussoirs between radii 2.0 and 2.4 m, 1 m deep
  constexpr int n = 20;
  std::vector<geometry::convex_polyhedron> blocks{geometry::convex_polyhedron::box(vec3(-3, -0.5, -0.5), vec3(3, 0.5, 0))};
  for (int k = 0; k < n; ++k)
    blocks.push_back(geometry::voussoir(vec3(0, 0, 0), 2.0, 2.4, std::numbers::pi * k / n, std::numbers::pi * (k + 1) / n, 1.0));
  const auto tess = geometry::separate_blocks(blocks);  // cell b is blocks[b]
  const auto mesh = geometry::zone_blocks(tess);

  // 2. materials: stone of 2400 kg/m^3 on dry joints (k_n = k_s = 10 GPa/m, friction 35 deg)
  using joints = contact::detected_contacts<law::dry_joint_law>;
  const joints::params joint(law::dry_joint(1e10, 1e10, law::friction_angle::from_degrees(35)), /*tolerance m*/ 1e-3);
  solver<blocks::rigid, joints> s(tess, mesh, blocks::rigid::params{2400}, joint);

  // 3. supports and loading: the base slab held, gravity
  s.fix_blocks(s.blocks_below(2, 0.0));
  s.set_gravity(vec3(0, 0, -9.81));

  // 4. run until the crown settles (or falls, or 3 s pass), recording it
  const index_t crown = n / 2;  // the voussoir right of the key joint
  recorders::csv_recorder curve(s, "arch.csv",
                                {{"uz_crown", "m", quantity::block_displacement(crown, 2)},
                                 {"Rz_base", "N", quantity::reaction_sum(s.gridpoints_of_block(0), 2)}},
                                recorders::every_steps(200));
  const auto r = s.run_until(stop::when_settled(quantity::block_displacement(crown, 2), 1e-8, stop::over_time(0.05)) ||
                                 stop::when_beyond(quantity::block_displacement_magnitude(crown), 0.05) ||
                                 stop::after_time(3.0),
                             100'000'000, curve);
  curve.close();

  // 5. results: the held base carries every block's weight (its own and the arch's); the crown
  //    barely moves
  real weight = 0;
  for (index_t b = 0; b <= n; ++b) weight += s.blocks().weight_mass(b) * 9.81;
  const real base = recorders::reaction_sum(s.gridpoints(), s.gridpoints_of_block(0)).z();
  const real sag = -s.block_displacement(crown).z();
  std::printf("%lld steps of %.3g s: %s\nbase reaction %.6g N against the weight %.6g N; crown sag %.3g mm\n",
              static_cast<long long>(r.steps), s.dt(), r.reason.c_str(), base, weight, sag * 1e3);
  const bool ok = !r.hit_max_steps && r.reason.rfind("settled", 0) == 0 && std::abs(base - weight) < 1e-3 * weight &&
                  std::abs(sag) < 1e-3;
  return ok ? 0 : 1;
}
