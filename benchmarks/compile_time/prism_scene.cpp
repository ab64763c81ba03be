// The deformable-block scene of the compile-time benchmark (benchmarks/compile_time.sh): the
// README's prism program (tests/consumer/main.cpp: 100 Voronoi blocks split into tetrahedra,
// bonded faces with the study's power-softening law, pulled at 5 mm/s for 500 steps) written as
// docs/guide.md writes a scene: per-role headers, not <tessera/tessera.hpp>, and its solver taken
// from tessera::instances (tessera::instances::prism_solver is this solver type). Exits 0 when
// the mean axial stress is finite, positive and below the tensile strength.
#include <tessera/blocks.hpp>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/law.hpp>
#include <tessera/presets.hpp>
#include <tessera/solver.hpp>
#include <tessera/instances.hpp>  // its solver compiled once: link tessera::instances

#include <cmath>
#include <cstdio>

int main() {
  using namespace tessera;

  // 1. geometry: the study's prism as 100 random Voronoi blocks, each split into tetrahedra
  aabb box;
  box.lo = vec3(0, 0, 0);
  box.hi = vec3(0.068, 0.068, 0.6);
  const auto tess = geometry::random_voronoi(box, 100, /*rng seed*/ 1);
  const auto mesh = geometry::zone_blocks(tess);

  // 2. materials: semi-rigid blocks (10 x the macro modulus) and the study's Table 1 contacts
  zones::linear_elastic_tet::params blocks;
  blocks.young = 280e9;     // Pa
  blocks.poisson = 0.2;
  blocks.density = 2400;    // kg/m^3
  const auto concrete = law::study_prism_params(100);  // k_n, k_s, f_T, G_f, c, phi, alpha = 3
  contact::material_table<law::study_tie_law::params> contacts(concrete);

  // 3. the solver: deformable blocks on the tessellation's bonded faces, central differences
  //    with local damping, masses scaled for a 1 us step (quasi-static)
  solver_options options;
  options.mass_scaling_dt = 1e-6;  // s
  instances::prism_solver s(tess, mesh, blocks, contacts, {}, options);

  // 4. supports and loading: bottom fixed, top pulled along z at 5 mm/s
  const auto bottom = s.gridpoints_on_plane(2, 0.0, 1e-9);
  const auto top = s.gridpoints_on_plane(2, 0.6, 1e-9);
  s.fix(bottom, bc::components::xyz);
  s.prescribe_velocity(top, vec3(0, 0, 5e-3), bc::components::xyz);

  // 5. run, recording the mean axial stress (Pa) every 100 steps
  double stress = 0;
  s.run(500, recorders::every(100, [&](const auto& m) {
    stress = recorders::reaction_sum(m.gridpoints(), top).z() / (0.068 * 0.068);
    std::printf("t = %.3e s  mean axial stress = %.4e Pa\n", m.time(), stress);
  }));
  const bool ok = std::isfinite(stress) && stress > 0 && stress < concrete.tension.f_T;
  return ok ? 0 : 1;
}
