// Cost of the per-step contact kernel, contact::face_contacts::update (frames per face, law
// update and force buffer per sub-contact, gather onto gridpoints), on the study's plain
// concrete prism.
//
// Workload: 68 x 68 x 600 mm prism, random Voronoi tessellation of 100 blocks (seed 1), zoned by
// geometry::zone_blocks (no refinement), law::study_tie_law with law::study_prism_params(100);
// BM_subcontact_update is the default layout, BM_subcontact_update_packed the opt-in elastic
// pack path (law::with_elastic_packs).
// Gridpoints get random velocities (up to 1 mm/s, dt = 1e-6 s: relative increments ~1e-9 m,
// elastic) whose effect alternates sign every step (through the sign of dt), so the contacts cycle about the unloaded
// state instead of drifting to failure. Positions are fixed, which does not change the work done. Reported:
// ns_per_subcontact = CPU time of one update / number of sub-contacts, and the sub-contact count (the study's 3DEC
// model of the 100-block tie had 3808 contact points).
//
//   cmake -S . -B build/contacts -DCMAKE_BUILD_TYPE=Release -DTESSERA_BUILD_BENCHMARKS=ON
//   cmake --build build/contacts --target bench_contacts
//   build/contacts/benchmarks/bench_contacts --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>
#include <tessera/contact.hpp>
#include <tessera/geometry.hpp>
#include <tessera/presets.hpp>

// Nested in tessera so `index` is tessera::index, not POSIX ::index.
namespace tessera::bench_contacts {
namespace {

struct prism_scene {
  geometry::tessellation tess;
  geometry::block_mesh mesh;
  node_set gridpoints;

  explicit prism_scene(index_t blocks) {
    aabb box;
    box.expand(vec3::Zero());
    box.expand(vec3(0.068, 0.068, 0.6));
    tess = geometry::random_voronoi(box, blocks, 1);
    mesh = geometry::zone_blocks(tess);
    gridpoints.resize(mesh.gridpoint_count());
    for (index_t i = 0; i < mesh.gridpoint_count(); ++i)
      gridpoints.reference.row(i) = mesh.gridpoints[static_cast<std::size_t>(i)].transpose();
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<real> uni(-1e-3, 1e-3);
    for (index_t i = 0; i < gridpoints.size(); ++i)
      for (int c = 0; c < 3; ++c) gridpoints.velocity(i, c) = uni(rng);
  }
};

template <class Law>
void subcontact_update(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const int previous_threads = max_threads();
  set_threads(threads);
  prism_scene scene(100);
  contact::face_contacts<Law> contacts(scene.tess, scene.mesh, law::study_prism_params(100));
  const real dt = 1e-6;
  real signed_dt = dt;
  for (auto _ : state) {
    contacts.update(scene.gridpoints, signed_dt);  // du = v dt: alternate the sign through dt
    signed_dt = -signed_dt;
    benchmark::ClobberMemory();
  }
  set_threads(previous_threads);
  const auto n = static_cast<double>(contacts.size());
  state.counters["subcontacts"] = n;
  state.counters["faces"] = static_cast<double>(contacts.face_count());
  // Seconds per sub-contact-step (printed with an SI prefix, e.g. "18.5n" = 18.5 ns).
  state.counters["time_per_subcontact"] =
      benchmark::Counter(n, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
/// The default layout (an array of law states, Law::update per sub-contact).
void BM_subcontact_update(benchmark::State& state) { subcontact_update<law::study_tie_law>(state); }
/// The opt-in elastic pack path (law::with_elastic_packs): all contacts here stay intact and elastic.
void BM_subcontact_update_packed(benchmark::State& state) {
  subcontact_update<law::with_elastic_packs<law::study_tie_law>>(state);
}
BENCHMARK(BM_subcontact_update)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_subcontact_update_packed)->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace tessera::bench_contacts

BENCHMARK_MAIN();
