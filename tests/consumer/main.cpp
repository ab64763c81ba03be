// A separate project that only knows find_package(tessera). It is also the README's library
// example, compiled and run against the installed package so the README cannot drift from the
// code: the study's prism (100 Voronoi blocks, deformable, power softening) pulled for a few
// hundred steps; the mean axial stress must stay finite, positive and elastic.
#include <tessera/tessera.hpp>

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
  blocks.young = 280e9;
  blocks.poisson = 0.2;
  blocks.density = 2400;
  const auto concrete = law::study_prism_params(100);  // k_n, k_s, f_T, G_f, c, phi, alpha = 3
  contact::material_table<law::study_tie_law::params> contacts(concrete);  // one law for every material pair

  // 3. the solver: deformable blocks, the tessellation's bonded faces as contacts with the
  //    study's power-softening law, no bars, central differences with local damping
  using model = solver<blocks::deformable<zones::linear_elastic_tet>, contact::face_contacts<law::study_tie_law>>;
  solver_options options;
  options.mass_scaling_dt = 1e-6;  // quasi-static: masses scaled so this step is stable
  model s(tess, mesh, blocks, contacts, {}, options);

  // 4. supports and loading: bottom fixed, top pulled along z at 5 mm/s
  const auto bottom = s.gridpoints_on_plane(2, 0.0, 1e-9);
  const auto top = s.gridpoints_on_plane(2, 0.6, 1e-9);
  s.fix(bottom, bc::components::xyz);
  s.prescribe_velocity(top, vec3(0, 0, 5e-3), bc::components::xyz);

  // 5. run, recording the mean axial stress every 100 steps
  double stress = 0;
  s.run(500, recorders::every(100, [&](const auto& m) {
    stress = recorders::reaction_sum(m.gridpoints(), top).z() / (0.068 * 0.068);  // support force on the body
    std::printf("t = %.3e s  mean axial stress = %.4e Pa\n", m.time(), stress);
  }));

  std::printf("installed tessera %s: %d blocks, %d sub-contacts, dt = %.3e s\n", TESSERA_VERSION_STRING,
              static_cast<int>(tess.cell_count()), static_cast<int>(s.contacts().size()), s.dt());
  const bool ok = std::isfinite(stress) && stress > 0 && stress < concrete.tension.f_T;
  return ok ? 0 : 1;
}
