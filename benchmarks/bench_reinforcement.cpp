// Microbenchmarks of the reinforcement: one accumulate_forces call (axial + bond forces) for bars
// of 96 and 960 nodes in a zoned box, and host location (build) for many bar nodes.
#include <benchmark/benchmark.h>

#include <array>
#include <vector>

#include "tessera/presets.hpp"
#include "tessera/reinforcement.hpp"

using namespace tessera;
using namespace tessera::reinforcement;
using idx = tessera::index_t;

namespace {

/// Box [0, size] split into n^3 cubes of 6 Kuhn tetrahedra each (one block).
geometry::block_mesh kuhn_box(const vec3& size, std::array<int, 3> n) {
  geometry::block_mesh m;
  auto id = [&](int i, int j, int k) { return static_cast<idx>((k * (n[1] + 1) + j) * (n[0] + 1) + i); };
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        m.gridpoints.emplace_back(size.x() * i / n[0], size.y() * j / n[1], size.z() * k / n[2]);
        m.gridpoint_block.push_back(0);
        m.gridpoint_vertex.push_back(invalid_index);
      }
  const std::array<std::array<int, 3>, 6> orders{{{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}}};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        for (const auto& o : orders) {
          std::array<int, 3> c{i, j, k};
          std::array<idx, 4> t{};
          t[0] = id(c[0], c[1], c[2]);
          for (std::size_t s = 0; s < 3; ++s) {
            ++c[static_cast<std::size_t>(o[s])];
            t[s + 1] = id(c[0], c[1], c[2]);
          }
          auto x = [&](std::size_t q) { return m.gridpoints[static_cast<std::size_t>(t[q])]; };
          if ((x(1) - x(0)).cross(x(2) - x(0)).dot(x(3) - x(0)) < 0) std::swap(t[2], t[3]);
          m.zones.push_back(t);
          m.zone_block.push_back(0);
        }
  m.block_gridpoint_offsets.push_back(m.gridpoint_count());
  m.block_zone_offsets.push_back(m.zone_count());
  return m;
}

node_set gridpoints_of(const geometry::block_mesh& m) {
  node_set s;
  s.resize(m.gridpoint_count());
  for (idx g = 0; g < m.gridpoint_count(); ++g) s.reference.row(g) = m.gridpoints[static_cast<std::size_t>(g)].transpose();
  return s;
}

}  // namespace

/// One accumulate_forces over a bar of N elements in the RC-tie prism (68 x 68 x 600 mm), with
/// zone stresses present (confinement evaluated), small random displacements.
static void bm_accumulate_forces(benchmark::State& state) {
  const auto elements = static_cast<idx>(state.range(0));
  const auto mesh = kuhn_box(vec3(0.068, 0.068, 0.6), {4, 4, 30});
  node_set gp = gridpoints_of(mesh);
  embedded_truss<coulomb_bond> r;
  auto p = pulatsu2020::tie_reinforcement(vec3(0.0341, 0.0339, 0.0), vec3(0.0341, 0.0339, 0.6), elements);
  p.bond.friction_angle = 0.5;
  r.build(p, mesh, gp);
  zone_stress_matrix stress = zone_stress_matrix::Constant(mesh.zone_count(), 6, -1e6);
  for (idx i = 0; i < r.node_count(); ++i) r.nodes().displacement(i, 2) = 1e-6 * i;
  for (auto _ : state) {
    r.accumulate_forces(gp, stress);
    benchmark::DoNotOptimize(r.nodes().force.data());
    benchmark::DoNotOptimize(gp.force.data());
  }
  state.SetItemsProcessed(state.iterations() * r.node_count());
  state.counters["nodes"] = static_cast<double>(r.node_count());
}
BENCHMARK(bm_accumulate_forces)->Arg(96)->Arg(960)->Arg(9600);

/// build(): discretisation + host location of every node (zone grid) in a 20^3-cube box (48k zones).
static void bm_build_locate(benchmark::State& state) {
  const auto mesh = kuhn_box(vec3(1, 1, 1), {20, 20, 20});
  node_set gp = gridpoints_of(mesh);
  embedded_truss<coulomb_bond>::params p{pulatsu2020::tie_steel(), pulatsu2020::tie_bond(), {}};
  const int bars = static_cast<int>(state.range(0));
  for (int b = 0; b < bars; ++b) {
    const real y = 0.05 + 0.9 * (b + 0.5) / bars;
    p.bars.push_back(bar{vec3(0.013, y, 0.31), vec3(0.987, 0.97 - y * 0.9, 0.77), 100, true});
  }
  for (auto _ : state) {
    embedded_truss<coulomb_bond> r;
    r.build(p, mesh, gp);
    benchmark::DoNotOptimize(r.host(0).zone);
  }
  state.SetItemsProcessed(state.iterations() * bars * 101);
}
BENCHMARK(bm_build_locate)->Arg(10)->Arg(100)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
