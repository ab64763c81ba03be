// Microbenchmarks of the mechanics kernels on the study's 100-block prism (deformable blocks,
// power-softening contacts): the zone update (block rotations + zone stresses + corner forces +
// gather) and one full time step of the composed solver (zones, contacts, damped integrator).
// Reported: time per call; zone_rate = zone updates per second (1e9 / zone_rate = ns per zone);
// counters give zones, sub-contacts and gridpoints.
//
//   build/<dir>/benchmarks/bench_kernels --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include "common/scenes.hpp"
#include "tessera/presets.hpp"
#include "tessera/solver.hpp"

namespace {

using namespace tessera;

const scenes::prism_scene& prism(int blocks) {
  static const scenes::prism_scene s100 = scenes::make_prism({100, 1, vec3(0.068, 0.068, 0.6), 0});
  static const scenes::prism_scene s250 = scenes::make_prism({250, 1, vec3(0.068, 0.068, 0.6), 0});
  return blocks == 100 ? s100 : s250;
}

/// A loaded state: the prism stretched to half its elastic peak, so zones carry stress.
prism_solver loaded_solver(int blocks) {
  const auto& sc = prism(blocks);
  solver_options opt;
  opt.mass_scaling_dt = 5e-7;
  prism_solver s(sc.tess, sc.mesh, sc.block_material, sc.contact, {}, opt);
  s.fix(s.gridpoints_on_plane(2, 0, 1e-9));
  const auto top = s.gridpoints_on_plane(2, sc.length(), 1e-9);
  s.fix(top, bc::transverse_to(2));
  s.prescribe_velocity(top, vec3(0, 0, 0.005), bc::components::z);
  s.run(200);
  return s;
}

void zone_update(benchmark::State& state) {
  const int blocks = static_cast<int>(state.range(0));
  const prism_solver s = loaded_solver(blocks);
  auto model = s.blocks();
  node_set gp = s.gridpoints();
  for (auto _ : state) {
    model.accumulate_forces(gp);
    benchmark::DoNotOptimize(gp.force.data());
    benchmark::ClobberMemory();
  }
  const auto zones = static_cast<double>(model.zone_count());
  state.counters["zones"] = zones;
  // zone updates per second; 1e9 / this = ns per zone update
  state.counters["zone_rate"] = benchmark::Counter(zones, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(zone_update)->Arg(100)->Arg(250)->Unit(benchmark::kMicrosecond);

void full_step(benchmark::State& state) {
  const int blocks = static_cast<int>(state.range(0));
  prism_solver s = loaded_solver(blocks);
  for (auto _ : state) {
    s.step();
    benchmark::ClobberMemory();
  }
  state.counters["zones"] = static_cast<double>(s.blocks().zone_count());
  state.counters["subcontacts"] = static_cast<double>(s.contacts().size());
  state.counters["gridpoints"] = static_cast<double>(s.gridpoints().size());
}
BENCHMARK(full_step)->Arg(100)->Arg(250)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
