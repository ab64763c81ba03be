// Cost of one contact-law update per sub-contact, for each named law (presets/pulatsu2020.hpp).
//
// Workload: 4096 sub-contact states (a few solver faces' worth, 352 KiB of state, so the loop runs
// from L2 as it would in a solver sweep) with precomputed random unit normals and increments. Each
// benchmark iteration is one sweep over all of them; successive sweeps alternate the sign of the
// increments, so the states cycle about a fixed mix instead of drifting to failure.
//   elastic: every contact intact, normal stress within +-0.9 f_T, shear well below the limit.
//   mixed:   about 55 % elastic, 25 % on the softening branch (envelope evaluated every sweep),
//            10 % broken in tension, 10 % slipped on the residual Coulomb limit.
//   crushed: the mixed set with the slipped tenth replaced by contacts closed to 1.2 times the
//            compressive cap's closure (beam laws: at the cap every other sweep; study_beam_law's
//            is perfectly plastic, crushing_beam_law's softens with u_crush).
// Reported: time_per_update = CPU time of a sweep / 4096 (single thread), e.g. "15.2n" = 15.2 ns.
// bench_update runs Law::update one sub-contact at a time; bench_packed runs the same states as
// columns through contact::detail::advance_states (law::with_elastic_packs: the path
// contact::face_contacts takes, update_elastic over lanes::pack's and Law::update on the lanes it
// declines), the cost per sub-contact-step of a solver sweep without its kinematics.
// slip_softening_beam_law (G_II = 500 J/m^2, s_u = 0.2 mm) against study_beam_law: the cost of the
// plastic slip u_slip and its softening limit (issue #63; docs/performance.md). crushing_beam_law
// (the same with softening_cap, G_c = 10 kJ/m^2, residual 0.1) against slip_softening_beam_law: the
// cost of the plastic closure u_crush and its softening cap (issue #63). presets::mixed_mode_beam_law
// (law/mixed_mode.hpp, G_II = 120 J/m^2) against study_beam_law: the cost of one damage for tension
// and shear (issue #63's target: within 20 % per sub-contact-step, packed). presets::
// mixed_crushing_beam_law (the same with softening_cap, G_c = 10 kJ/m^2, residual 0.1) against
// mixed_mode_beam_law: the cost of the softening cap in the mixed law.
//
//   cmake -S . -B build/laws -DCMAKE_BUILD_TYPE=Release -DTESSERA_BUILD_BENCHMARKS=ON
//   cmake --build build/laws --target bench_laws && build/laws/benchmarks/bench_laws --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <array>
#include <random>
#include <tessera/contact/detail/packed_states.hpp>
#include <tessera/law.hpp>
#include <tessera/presets.hpp>
#include <vector>

namespace {

using namespace tessera;
using namespace tessera::law;

constexpr int subcontact_count = 4096;

enum class mix { elastic = 0, mixed = 1, crushed = 2 };
const char* mix_label(std::int64_t m) { return m == 0 ? "elastic" : m == 1 ? "mixed" : "crushed"; }

linear_tie_law::params linear_tie_params() {
  return with_linear_softening(study_prism_params(100));
}

study_beam_law::params beam_params() { return study_beam_params(250); }

template <class Law>
typename Law::params params_for() {
  if constexpr (std::is_same_v<Law, study_tie_law>) return study_prism_params(100);
  else if constexpr (std::is_same_v<Law, linear_tie_law>) return linear_tie_params();
  else if constexpr (std::is_same_v<Law, slip_softening_beam_law>) return with_slip_softening(beam_params(), 500);
  else if constexpr (std::is_same_v<Law, presets::mixed_mode_beam_law>) return presets::with_mixed_mode(beam_params());
  else if constexpr (std::is_same_v<Law, presets::mixed_crushing_beam_law>)
    return presets::with_softening_cap(presets::with_mixed_mode(beam_params()), 1e4, 0.1);
  else if constexpr (std::is_same_v<Law, crushing_beam_law>)
    return with_softening_cap(with_slip_softening(beam_params(), 500), 1e4, 0.1);
  else return beam_params();
}

template <class Law>
struct workload {
  typename Law::params p = params_for<Law>();
  std::vector<typename Law::state> states;
  std::vector<real> du_n;
  std::vector<vec3> du_s;
  std::vector<vec3> normal;

  explicit workload(mix kind) : states(subcontact_count), du_n(subcontact_count), du_s(subcontact_count),
                                normal(subcontact_count) {
    Law::validate(p);
    std::mt19937_64 rng(2020);
    std::uniform_real_distribution<real> unit(0, 1);
    std::normal_distribution<real> gauss(0, 1);
    const real f_T = p.tension.f_T;
    const real eta = f_T / p.k_n;
    const real cutoff = Law::tension_policy::cutoff_opening(p.tension, p.k_n);
    const real tau_slip = p.shear.c_0 / p.k_s;  // shear displacement at the intact limit, sigma_n = 0
    for (int i = 0; i < subcontact_count; ++i) {
      vec3 n(gauss(rng), gauss(rng), gauss(rng));
      n.normalize();
      const vec3 t = n.unitOrthogonal();
      const real pick = kind == mix::elastic ? 0 : unit(rng);
      real opening = (1.8 * unit(rng) - 0.9) * eta;  // elastic, |sigma_n| <= 0.9 f_T
      real slip = 0.3 * unit(rng) * tau_slip;
      if (pick > 0.9 && kind == mix::crushed) {  // closed past the cap (a beam law's)
        if constexpr (Law::compression_policy::bounded) opening = -1.2 * Law::compression_policy::strength(p.compression) / p.k_n;
      } else if (pick > 0.9) slip = 1.5 * tau_slip;                                 // slipped
      else if (pick > 0.8) opening = 1.2 * cutoff;                                  // broken in tension
      else if (pick > 0.55) opening = eta + (0.05 + 0.4 * unit(rng)) * (cutoff - eta);  // softening
      // Bring the contact there in 20 steps, then fix its per-sweep increments.
      for (int k = 0; k < 20; ++k) Law::update(p, states[i], opening / 20, t * (slip / 20), n);
      normal[i] = n;
      du_n[i] = 1e-3 * eta * gauss(rng);
      du_s[i] = 1e-3 * eta * (gauss(rng) * t + gauss(rng) * n.cross(t));
    }
  }
};

template <class Law>
void bench_update(benchmark::State& bench) {
  workload<Law> w(static_cast<mix>(bench.range(0)));
  real sign = 1;
  for (auto _ : bench) {
    for (int i = 0; i < subcontact_count; ++i)
      Law::update(w.p, w.states[i], sign * w.du_n[i], sign * w.du_s[i], w.normal[i]);
    sign = -sign;
    benchmark::DoNotOptimize(w.states.data());
    benchmark::ClobberMemory();
  }
  bench.SetItemsProcessed(bench.iterations() * subcontact_count);
  // Seconds of CPU time per sub-contact update, printed with an SI prefix (e.g. 15.2n = 15.2 ns).
  bench.counters["time_per_update"] = benchmark::Counter(
      subcontact_count, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  bench.SetLabel(mix_label(bench.range(0)));
}

template <class Law>
void bench_packed(benchmark::State& bench) {
  using packed = with_elastic_packs<Law>;
  workload<Law> w(static_cast<mix>(bench.range(0)));
  contact::detail::state_columns<packed> columns;
  columns.assign(subcontact_count, w.p);
  std::array<contact::detail::step_columns, 2> steps;  // the increments and their opposites
  for (auto& k : steps) k.resize(subcontact_count);
  for (int i = 0; i < subcontact_count; ++i) {
    const auto j = static_cast<std::size_t>(i);
    columns.set(j, w.states[j], w.p);
    for (int side = 0; side < 2; ++side) {
      auto& k = steps[static_cast<std::size_t>(side)];
      const real sign = side == 0 ? 1 : -1;
      k.du_n[j] = sign * w.du_n[j];
      k.ds0[j] = sign * w.du_s[j][0], k.ds1[j] = sign * w.du_s[j][1], k.ds2[j] = sign * w.du_s[j][2];
      k.n0[j] = w.normal[j][0], k.n1[j] = w.normal[j][1], k.n2[j] = w.normal[j][2];
    }
  }
  const std::vector<real> area(subcontact_count, 1e-4);
  std::array<std::vector<real>, 3> force;
  for (auto& column : force) column.assign(subcontact_count, 0.0);
  real* const f[3] = {force[0].data(), force[1].data(), force[2].data()};
  std::size_t side = 0;
  for (auto _ : bench) {
    contact::detail::advance_states<packed>(w.p, columns, steps[side], area.data(), 0, subcontact_count, f);
    side = 1 - side;
    benchmark::DoNotOptimize(force[0].data());
    benchmark::ClobberMemory();
  }
  bench.SetItemsProcessed(bench.iterations() * subcontact_count);
  bench.counters["time_per_update"] = benchmark::Counter(
      subcontact_count, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  bench.SetLabel(mix_label(bench.range(0)));
}

}  // namespace

BENCHMARK_TEMPLATE(bench_update, tessera::law::study_tie_law)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(bench_update, tessera::law::linear_tie_law)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(bench_update, tessera::law::study_beam_law)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(bench_update, tessera::law::slip_softening_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_update, tessera::law::crushing_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_update, tessera::presets::mixed_mode_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_update, tessera::presets::mixed_crushing_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_packed, tessera::law::study_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_packed, tessera::presets::mixed_mode_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_packed, tessera::presets::mixed_crushing_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_packed, tessera::law::slip_softening_beam_law)->Arg(0)->Arg(1)->Arg(2);
BENCHMARK_TEMPLATE(bench_packed, tessera::law::crushing_beam_law)->Arg(0)->Arg(1)->Arg(2);

BENCHMARK_MAIN();
