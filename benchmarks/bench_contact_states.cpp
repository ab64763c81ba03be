// Cost of the contact kernel per sub-contact and step by damage state, on the RC beam's law
// (presets::study_beam_law, study_beam_params(250); issue #41 item 5: does a beam with many
// damaged contacts leave a fast path?).
//
// Kernel: what face_contacts runs on the beam's states, contact::detail::advance_states of
// law::with_elastic_packs<study_beam_law> (the column layout: packs of lanes::width sub-contacts
// through update_elastic, the lanes it declines through update), over 4096 sub-contacts with
// their per-step increments precomputed (the kinematics, which does not depend on the state, is
// not timed); and, for comparison, Law::update over an array of states (the default layout).
// Every sub-contact of a population is brought into its state by Law::update from a virgin
// state along a path of 20 steps; its per-step increments then either alternate in sign from
// sweep to sweep (the state cycles about a fixed point) or repeat (it keeps advancing along its
// envelope or sliding); increments are 1e-3 eta (eta = f_T/k_n = 5 um) or less, so no state
// leaves its population within a run.
//   intact            elastic, |sigma_n| <= 0.9 f_T, |tau| < 0.3 c_0
//   softening_advance on the envelope, opening further every step (envelope return every step)
//   softening_elastic softened, unloaded to half its current strength, elastic below the envelope
//   broken_open       broken in tension, faces apart (no stress, shear stress dropped)
//   broken_stick      broken, closed at sigma_n = -0.5 f_T, shear within the residual limit
//   broken_slide      broken and slipped, closed, sliding on the residual limit every step
//   slipped_slide     slipped (tension intact, the study's law), closed, sliding every step
//   slip_broken_slide slipped with slip_breaks_tension (so broken too), closed, sliding
//   slip_broken_open  slipped with slip_breaks_tension under tension: broken and open
//   crushing          at the compressive cap f_c, closing further every step (declined by the
//                     packs every step: the full law, one sub-contact at a time)
//   late_beam         70 % intact, 5 % softening_advance, 5 % softening_elastic, 10 % broken_open,
//                     4 % broken_stick, 3 % broken_slide, 3 % slip_broken_slide
//   quarter_mix       25 % each of intact, softening_advance, broken_open, broken_slide
// The two mixes come shuffled (random order, the branches of the packs unpredictable) and sorted
// by state (Arg 1).
// Reported: time_per_subcontact = CPU time of a sweep / 4096, e.g. "15.2n" = 15.2 ns.
//
//   cmake --preset bench-portable && cmake --build build/bench-portable --target bench_contact_states
//   build/bench-portable/benchmarks/bench_contact_states --benchmark_repetitions=3
// Instructions per sub-contact-step, which a loaded machine cannot change: run the sweeps alone
// under callgrind, collecting only inside them,
//   valgrind --tool=callgrind --toggle-collect='*run_sweeps*' --callgrind-out-file=cg.out
//     build/bench-portable/benchmarks/bench_contact_states --instructions <population> <layout> <sweeps>
//   callgrind_annotate cg.out | head      # Ir / (sweeps x 4096)
// with <layout> packed or scalar and <population> a name above (mixes: late_beam, late_beam_sorted,
// quarter_mix, quarter_mix_sorted); --branch-sim=yes adds simulated branch mispredictions.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <string_view>
#include <tessera/contact.hpp>
#include <tessera/law.hpp>
#include <tessera/presets.hpp>
#include <vector>

// Nested in tessera so `index` is tessera::index, not POSIX ::index.
namespace tessera::bench_contact_states {
namespace {

using base_law = presets::study_beam_law;
using packed_law = law::with_elastic_packs<base_law>;
using state_type = base_law::state;
using params_type = base_law::params;

constexpr std::size_t subcontact_count = 4096;

enum class population {
  intact,
  softening_advance,
  softening_elastic,
  broken_open,
  broken_stick,
  broken_slide,
  slipped_slide,
  slip_broken_slide,
  slip_broken_open,
  crushing,
  count
};
constexpr std::array<std::string_view, static_cast<std::size_t>(population::count)> population_names{
    "intact",        "softening_advance", "softening_elastic", "broken_open",      "broken_stick",
    "broken_slide",  "slipped_slide",     "slip_broken_slide", "slip_broken_open", "crushing"};

params_type beam_params(bool slip_breaks_tension) {
  params_type p = presets::study_beam_params(250);
  p.shear.slip_breaks_tension = slip_breaks_tension;
  base_law::validate(p);
  return p;
}

/// One sub-contact: its state and its increments for even and odd sweeps.
struct subcontact {
  state_type state{};
  real du_n[2] = {0, 0};
  vec3 du_s[2] = {vec3::Zero(), vec3::Zero()};
  vec3 n = vec3::UnitX();
};

/// Brings a virgin sub-contact with normal n into population `kind` and fixes its increments.
subcontact make_subcontact(population kind, const params_type& p, std::mt19937_64& rng) {
  std::uniform_real_distribution<real> unit(0, 1);
  std::normal_distribution<real> gauss(0, 1);
  subcontact c;
  vec3 n(gauss(rng), gauss(rng), gauss(rng));
  n.normalize();
  const vec3 t = n.unitOrthogonal(), b = n.cross(t);
  c.n = n;
  const real f_T = p.tension.f_T, k_n = p.k_n, k_s = p.k_s;
  const real eta = f_T / k_n, zeta = base_law::tension_policy::cutoff_opening(p.tension, k_n);
  const auto path = [&](real opening, const vec3& slip) {  // 20 steps from where it is
    for (int k = 0; k < 20; ++k) base_law::update(p, c.state, opening / 20, slip / 20, n);
  };
  // Small increments: alternating (the state cycles) unless `monotone`.
  const auto increments = [&](real dn, const vec3& ds, bool monotone) {
    c.du_n[0] = dn;
    c.du_s[0] = ds;
    c.du_n[1] = monotone ? dn : -dn;
    c.du_s[1] = monotone ? ds : vec3(-ds);
  };
  const vec3 wobble = 1e-3 * eta * (gauss(rng) * t + gauss(rng) * b);
  const real slip_intact = p.shear.c_0 / k_s;  // shear displacement at the intact limit, sigma_n = 0
  switch (kind) {
    case population::intact:
      path((1.8 * unit(rng) - 0.9) * eta, t * (0.3 * unit(rng) * slip_intact));
      increments(1e-3 * eta * gauss(rng), wobble, false);
      break;
    case population::softening_advance:
      path(eta + (0.05 + 0.4 * unit(rng)) * (zeta - eta), vec3::Zero());
      increments(1e-6 * eta * (1 + unit(rng)), 1e-3 * wobble, true);
      break;
    case population::softening_elastic: {
      path(eta + (0.05 + 0.4 * unit(rng)) * (zeta - eta), vec3::Zero());
      path(-0.5 * c.state.sigma_n / k_n, vec3::Zero());
      increments(1e-4 * eta * gauss(rng), 1e-3 * wobble, false);
      break;
    }
    case population::broken_open:
      path((1.1 + unit(rng)) * zeta, vec3::Zero());
      increments(1e-3 * eta * gauss(rng), wobble, false);
      break;
    case population::broken_stick:
    case population::broken_slide: {
      path((1.1 + unit(rng)) * zeta, vec3::Zero());
      path(-c.state.u_n - 0.5 * eta, vec3::Zero());  // closed: sigma_n = -0.5 f_T
      const real residual = p.shear.c_res + 0.5 * f_T * p.shear.phi_res.tan();
      if (kind == population::broken_stick) {
        path(0, t * (0.3 * unit(rng) * residual / k_s));
        increments(1e-4 * eta * gauss(rng), 1e-2 * wobble, false);
      } else {
        path(0, t * (3 * residual / k_s));
        increments(0, t * (1e-3 * eta), true);
      }
      break;
    }
    case population::slipped_slide:
    case population::slip_broken_slide:
      path(-0.5 * eta, vec3::Zero());
      path(0, t * (2 * slip_intact));
      increments(0, t * (1e-3 * eta), true);
      break;
    case population::slip_broken_open:
      path(0.3 * eta, vec3::Zero());
      path(0, t * (2 * slip_intact));
      increments(1e-4 * eta * gauss(rng), wobble, false);
      break;
    case population::crushing: {
      const real f_c = p.compression.f_c;
      path(-1.05 * f_c / k_n, vec3::Zero());
      increments(-1e-3 * eta, vec3::Zero(), true);
      break;
    }
    case population::count:
      break;
  }
  return c;
}

/// The flags a population must hold (so the benchmark does not time something else).
void check_population(population kind, const subcontact& c) {
  using law::contact_status;
  const auto f = c.state.flags;
  const bool soft = law::has(f, contact_status::softening), broken = law::has(f, contact_status::broken_tension),
             slipped = law::has(f, contact_status::slipped);
  bool ok = true;
  switch (kind) {
    case population::intact:
    case population::crushing: ok = !soft && !broken && !slipped; break;
    case population::softening_advance:
    case population::softening_elastic: ok = soft && !broken && !slipped; break;
    case population::broken_open:
    case population::broken_stick: ok = broken && !slipped; break;
    case population::slipped_slide: ok = slipped && !broken; break;
    case population::broken_slide:
    case population::slip_broken_slide:
    case population::slip_broken_open: ok = broken && slipped; break;
    case population::count: break;
  }
  if (!ok) {
    std::fprintf(stderr, "bench_contact_states: population %s has flags %d\n",
                 population_names[static_cast<std::size_t>(kind)].data(), static_cast<int>(f));
    std::abort();
  }
}

/// Parameters a population is built and run with: slip_breaks_tension for the slip_broken ones.
bool needs_slip_breaks_tension(population kind) {
  return kind == population::slip_broken_slide || kind == population::slip_broken_open;
}

/// A workload: 4096 sub-contacts of the populations `shares` (fractions summing to 1), shuffled
/// or sorted by population.
struct workload {
  params_type p;
  std::vector<subcontact> subcontacts;

  workload(const std::vector<std::pair<population, real>>& shares, bool sorted) {
    bool sbt = false;
    for (const auto& share : shares) sbt = sbt || needs_slip_breaks_tension(share.first);
    p = beam_params(sbt);
    std::mt19937_64 rng(41);
    std::size_t made = 0;
    for (std::size_t k = 0; k < shares.size(); ++k) {
      const std::size_t n = k + 1 == shares.size()
                                ? subcontact_count - made
                                : static_cast<std::size_t>(shares[k].second * static_cast<real>(subcontact_count) + 0.5);
      for (std::size_t i = 0; i < n; ++i) {
        subcontacts.push_back(make_subcontact(shares[k].first, p, rng));
        check_population(shares[k].first, subcontacts.back());
      }
      made += n;
    }
    if (!sorted) std::shuffle(subcontacts.begin(), subcontacts.end(), rng);
  }
};

/// The column layout of face_contacts (packed_law): states as columns and the per-step columns of
/// even and odd sweeps.
struct packed_kernel {
  params_type p;
  contact::detail::state_columns<packed_law> states;
  contact::detail::step_columns steps[2];
  std::vector<real> area;
  std::array<std::vector<real>, 3> force;

  explicit packed_kernel(const workload& w) : p(w.p) {
    const std::size_t n = w.subcontacts.size();
    states.resize(n);
    for (auto& s : steps) s.resize(n);
    area.assign(n, 1e-4);
    for (auto& f : force) f.assign(n, 0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const subcontact& c = w.subcontacts[i];
      states.reset(i, c.state, p);
      for (int e = 0; e < 2; ++e) {
        steps[e].du_n[i] = c.du_n[e];
        steps[e].ds0[i] = c.du_s[e].x();
        steps[e].ds1[i] = c.du_s[e].y();
        steps[e].ds2[i] = c.du_s[e].z();
        steps[e].n0[i] = c.n.x();
        steps[e].n1[i] = c.n.y();
        steps[e].n2[i] = c.n.z();
      }
    }
  }
  void sweep(int parity) noexcept {
    real* const f[3] = {force[0].data(), force[1].data(), force[2].data()};
    contact::detail::advance_states<packed_law>(p, states, steps[parity], area.data(), 0, area.size(), f);
  }
};

/// The default layout: an array of states, Law::update per sub-contact.
struct scalar_kernel {
  params_type p;
  std::vector<state_type> states;
  std::vector<real> du_n[2];
  std::vector<vec3> du_s[2];
  std::vector<vec3> normal;
  std::vector<real> area;
  std::array<std::vector<real>, 3> force;

  explicit scalar_kernel(const workload& w) : p(w.p) {
    const std::size_t n = w.subcontacts.size();
    for (const subcontact& c : w.subcontacts) {
      states.push_back(c.state);
      for (int e = 0; e < 2; ++e) du_n[e].push_back(c.du_n[e]), du_s[e].push_back(c.du_s[e]);
      normal.push_back(c.n);
    }
    area.assign(n, 1e-4);
    for (auto& f : force) f.assign(n, 0.0);
  }
  void sweep(int parity) noexcept {
    for (std::size_t i = 0; i < states.size(); ++i) {
      base_law::update(p, states[i], du_n[parity][i], du_s[parity][i], normal[i]);
      const vec3 traction = states[i].sigma_n * normal[i] + states[i].tau;
      for (int c = 0; c < 3; ++c) force[static_cast<std::size_t>(c)][i] = area[i] * traction[c];
    }
  }
};

std::vector<std::pair<population, real>> late_beam_mix() {
  return {{population::intact, 0.70},         {population::softening_advance, 0.05},
          {population::softening_elastic, 0.05}, {population::broken_open, 0.10},
          {population::broken_stick, 0.04},   {population::broken_slide, 0.03},
          {population::slip_broken_slide, 0.03}};
}
std::vector<std::pair<population, real>> quarter_mix() {
  return {{population::intact, 0.25}, {population::softening_advance, 0.25},
          {population::broken_open, 0.25}, {population::broken_slide, 0.25}};
}

/// The sweeps that callgrind's --toggle-collect='*run_sweeps*' counts.
template <class Kernel>
[[gnu::noinline]] void run_sweeps(Kernel& kernel, long sweeps) {
  for (long k = 0; k < sweeps; ++k) kernel.sweep(static_cast<int>(k & 1));
  benchmark::DoNotOptimize(kernel.force[0].data());
}

template <class Kernel>
void time_kernel(benchmark::State& bench, const workload& w) {
  Kernel kernel(w);
  int parity = 0;
  for (auto _ : bench) {
    kernel.sweep(parity);
    parity ^= 1;
    benchmark::DoNotOptimize(kernel.force[0].data());
    benchmark::ClobberMemory();
  }
  // Seconds of CPU time per sub-contact-step, printed with an SI prefix (e.g. 15.2n = 15.2 ns).
  bench.counters["time_per_subcontact"] = benchmark::Counter(
      static_cast<double>(subcontact_count), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

template <class Kernel>
void BM_population(benchmark::State& bench) {
  const auto kind = static_cast<population>(bench.range(0));
  time_kernel<Kernel>(bench, workload({{kind, 1.0}}, true));
  bench.SetLabel(std::string(population_names[static_cast<std::size_t>(kind)]));
}
template <class Kernel>
void BM_late_beam(benchmark::State& bench) {
  time_kernel<Kernel>(bench, workload(late_beam_mix(), bench.range(0) != 0));
  bench.SetLabel(bench.range(0) != 0 ? "sorted" : "shuffled");
}
template <class Kernel>
void BM_quarter_mix(benchmark::State& bench) {
  time_kernel<Kernel>(bench, workload(quarter_mix(), bench.range(0) != 0));
  bench.SetLabel(bench.range(0) != 0 ? "sorted" : "shuffled");
}

BENCHMARK_TEMPLATE(BM_population, packed_kernel)->DenseRange(0, static_cast<int>(population::count) - 1);
BENCHMARK_TEMPLATE(BM_late_beam, packed_kernel)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_quarter_mix, packed_kernel)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_population, scalar_kernel)->DenseRange(0, static_cast<int>(population::count) - 1);
BENCHMARK_TEMPLATE(BM_late_beam, scalar_kernel)->Arg(0)->Arg(1);
BENCHMARK_TEMPLATE(BM_quarter_mix, scalar_kernel)->Arg(0)->Arg(1);

/// --instructions <population> <packed|scalar> <sweeps>: runs the sweeps alone (for callgrind).
int count_instructions(std::string_view name, std::string_view layout, long sweeps) {
  std::vector<std::pair<population, real>> shares;
  bool sorted = name.ends_with("_sorted");
  const std::string_view base = sorted ? name.substr(0, name.size() - 7) : name;
  if (base == "late_beam") {
    shares = late_beam_mix();
  } else if (base == "quarter_mix") {
    shares = quarter_mix();
  } else {
    for (std::size_t k = 0; k < population_names.size(); ++k)
      if (population_names[k] == name) shares = {{static_cast<population>(k), 1.0}};
    sorted = true;
  }
  if (shares.empty() || (layout != "packed" && layout != "scalar") || sweeps < 1) {
    std::fprintf(stderr, "bench_contact_states --instructions: unknown population '%.*s' or layout '%.*s', or sweeps %ld < 1\n",
                 static_cast<int>(name.size()), name.data(), static_cast<int>(layout.size()), layout.data(), sweeps);
    return 2;
  }
  const workload w(shares, sorted);
  // A hash of the bits of every state and force after the sweeps: two builds of the kernel agree
  // to the bit when their hashes do.
  std::uint64_t hash = 1469598103934665603ull;
  const auto mix_in = [&hash](const auto& value) {
    unsigned char bytes[sizeof value];
    std::memcpy(bytes, &value, sizeof value);
    for (unsigned char b : bytes) hash = (hash ^ b) * 1099511628211ull;
  };
  if (layout == "packed") {
    packed_kernel k(w);
    run_sweeps(k, sweeps);
    for (std::size_t i = 0; i < subcontact_count; ++i) {
      const state_type s = k.states.get(i);
      for (const real v : {s.sigma_n, s.tau.x(), s.tau.y(), s.tau.z(), s.u_n, s.u_p, s.u_soft, s.dissipated_tension,
                           s.dissipated_shear, s.dissipated_compression, k.states.f_t[i], k.force[0][i], k.force[1][i],
                           k.force[2][i]})
        mix_in(v);
      mix_in(static_cast<int>(s.flags));
    }
  } else {
    scalar_kernel k(w);
    run_sweeps(k, sweeps);
    for (std::size_t i = 0; i < subcontact_count; ++i) {
      const state_type& s = k.states[i];
      for (const real v : {s.sigma_n, s.tau.x(), s.tau.y(), s.tau.z(), s.u_n, s.u_p, s.u_soft, s.dissipated_tension,
                           s.dissipated_shear, s.dissipated_compression, k.force[0][i], k.force[1][i], k.force[2][i]})
        mix_in(v);
      mix_in(static_cast<int>(s.flags));
    }
  }
  std::printf("%.*s %.*s: %ld sweeps of %zu sub-contacts, state hash %016llx\n", static_cast<int>(name.size()),
              name.data(), static_cast<int>(layout.size()), layout.data(), sweeps, subcontact_count,
              static_cast<unsigned long long>(hash));
  return 0;
}

}  // namespace
}  // namespace tessera::bench_contact_states

int main(int argc, char** argv) {
  if (argc == 5 && std::string_view(argv[1]) == "--instructions")
    return tessera::bench_contact_states::count_instructions(argv[2], argv[3], std::strtol(argv[4], nullptr, 10));
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
