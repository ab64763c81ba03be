// The rigid-block scene of the compile-time benchmark (benchmarks/compile_time.sh, issue #40):
// a fixed base slab and a stack of cubes (0.1 m, 2400 kg/m^3) that meet through detected dry
// joints (no tension, elastic compression, Coulomb friction at 30 deg), falling under gravity
// for 100 undamped central-difference steps. It includes only the headers a rigid scene needs
// (docs/guide.md, "Keeping compile times short"), not <tessera/tessera.hpp>, and with
// -DTESSERA_USE_INSTANCES it takes the solver from the tessera::instances library instead of
// compiling it here. Exits 0 when the stack's weight is finite and the top cube has moved down.
#include <cmath>
#include <cstdio>
#include <vector>

#include <tessera/blocks/rigid.hpp>
#include <tessera/contact/detected_contacts.hpp>
#include <tessera/geometry/convex_polyhedron.hpp>
#include <tessera/geometry/tessellation_queries.hpp>
#include <tessera/geometry/zoning.hpp>
#include <tessera/integrator/central_difference.hpp>
#include <tessera/law/cohesive_frictional.hpp>
#include <tessera/solver.hpp>
#ifdef TESSERA_USE_INSTANCES
#include <tessera/instances/rigid.hpp>
#endif

int main() {
  using namespace tessera;
  using joint = law::cohesive_frictional<law::no_tension, law::elastic_compression, law::coulomb_residual>;
  using model = solver<blocks::rigid, contact::detected_contacts<joint>, reinforcement::none,
                       integrator::central_difference<integrator::no_damping>>;

  // 1. geometry: a 0.4 m x 0.4 m x 0.05 m base and 4 cubes of 0.1 m stacked on it
  const real s = 0.1;
  std::vector<geometry::convex_polyhedron> cells{geometry::convex_polyhedron::box({-2 * s, -2 * s, -s / 2}, {2 * s, 2 * s, 0})};
  for (int k = 0; k < 4; ++k) cells.push_back(geometry::convex_polyhedron::box({-s / 2, -s / 2, k * s}, {s / 2, s / 2, (k + 1) * s}));
  const geometry::tessellation tess = geometry::separate_blocks(cells);
  const geometry::block_mesh mesh = geometry::zone_blocks(tess);

  // 2. dry joints: k_n = k_s = 1e10 Pa/m, phi = 30 deg, detected within 1 mm
  joint::params p;
  p.k_n = 1e10;
  p.k_s = 1e10;
  p.shear.phi_0 = law::friction_angle::from_degrees(30);
  p.shear.phi_res = p.shear.phi_0;

  // 3. the solver, gravity, the base fixed, 100 steps
  model m(tess, mesh, blocks::rigid::params{2400}, model::contact_set_type::params(p, 1e-3));
  m.set_gravity(vec3(0, 0, -9.81));
  m.fix(m.gridpoints_on_plane(2, -s / 2, 1e-9));
  m.run(100);

  const real dz = m.blocks().displacement(m.block_count() - 1).z();
  std::printf("rigid scene: %d blocks, %d sub-contacts, dt = %.3e s, top cube dz = %.3e m\n",
              static_cast<int>(m.block_count()), static_cast<int>(m.contacts().subcontact_count()), m.dt(), dz);
  return std::isfinite(dz) && dz < 0 ? 0 : 1;
}
