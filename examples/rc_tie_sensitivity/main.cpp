// rc_tie_sensitivity: the sensitivity studies of the reference study's RC tie (Pulatsu et al.
// 2020, Sec. 3.2, Figures 10-15 and Table 2; DESIGN.md §4).
//
// Studies (each varies one input of the baseline tie of examples/rc_tie: 100 blocks, 96
// elements, xi = 4, c_bond = 1e9 N/m, power softening, the loading of --rate / --dt):
//   softening  power (alpha = 3) vs linear                                  (Fig. 10)
//   xi         bond stiffness ratio 2, 4, 6                                  (Fig. 11)
//   elements   48, 96, 120 truss elements                                    (Fig. 12)
//   blocks     100, 250, 500 blocks (Table 1 stiffnesses), each at the step that keeps the
//              100-block added mass (scaled_tie_dt: --dt x (100/blocks)^0.55)  (Fig. 13, Table 2)
//   cbond      c_bond = 1e9, 1e8, 1e7, 1e6, 1e5, 1e4 N/m                     (Fig. 15)
//   rate       pull rate 4, 2, 1, 0.5 x --rate                              (Fig. 8)
// --quick runs a reduced set (xi 2 and 4, c_bond 1e9 and 1e4, 100 blocks, a coarser step).
//
// Outputs in --out DIR, per study S:
//   S.csv          common elongation grid (m) and one force column (N) per variant (nan past
//                  the end of a variant's run)
//   S.png          overlay of the variants and the bare bar
//   S_table.csv    per variant: first cracking, initial stiffness, load drops, cracks, yield
//                  force, curve error against the study's baseline variant and against the bare
//                  bar, steps, runtime
// and runtime_table.csv / .md (Table 2 counterpart: blocks, sub-contacts, zones, steps, runtime,
// the study's 3DEC minutes), trends.md (each trend the study reports, with our numbers and
// whether it holds), summary.json (run totals, and per variant k of study S the keys
// S_k_variant, S_k_first_crack_force_N, S_k_initial_stiffness_N_per_m, S_k_load_drops,
// S_k_yield_force_N, S_k_curve_error_vs_baseline_rel, S_k_curve_error_vs_bare_bar_rel).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/cli.hpp"
#include "common/rc_tie_run.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/run_record.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/plot.hpp"

namespace {

using tessera::real;
namespace fs = std::filesystem;
namespace sc = tessera::scenes;

struct variant {
  std::string label;       ///< legend / column name
  sc::tie_options tie;
  sc::tie_loading loading;
  sc::tie_result result;
};

/// Each variant's curve error (RMS force difference over the common elongation range / f_y A)
/// against the study's baseline variant and against the bare bar (curve_errors()).
struct variant_errors {
  std::vector<double> baseline, bare_bar;
};

struct study {
  std::string name, title, parameter;
  std::vector<variant> variants;
  std::size_t baseline = 0;  ///< the variant the others are compared with
  variant_errors errors;     ///< set by curve_errors() once the variants have run
};

struct inputs {
  tessera::cli::standard_options common;
  sc::tie_loading loading;
  std::string studies = "softening,xi,elements,blocks,cbond,rate";
};

/// The study's 3DEC run time (min) for the tie (Table 2), 0 where it gives none.
double study_minutes(int blocks) { return blocks == 100 ? 20 : blocks == 250 ? 54 : blocks == 500 ? 130 : 0; }

std::string number(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

study make_study(const std::string& name, const inputs& in) {
  study s;
  s.name = name;
  sc::tie_options base;
  base.seed = in.common.seed;
  const bool quick = in.common.quick;
  const auto add = [&](std::string label, auto modify) {
    variant v;
    v.label = std::move(label);
    v.tie = base;
    v.loading = in.loading;
    modify(v);
    s.variants.push_back(std::move(v));
  };
  if (name == "softening") {
    s.title = "contact softening (Fig. 10)";
    s.parameter = "softening";
    add("power", [](variant&) {});
    add("linear", [](variant& v) { v.loading.softening = "linear"; });
  } else if (name == "xi") {
    s.title = "bond stiffness ratio xi (Fig. 11)";
    s.parameter = "xi";
    for (real xi : quick ? std::vector<real>{2, 4} : std::vector<real>{2, 4, 6})
      add("xi=" + number(xi), [xi](variant& v) { v.tie.xi = xi; });
    s.baseline = 1;
  } else if (name == "elements") {
    s.title = "truss elements (Fig. 12)";
    s.parameter = "elements";
    for (int n : quick ? std::vector<int>{48, 96} : std::vector<int>{48, 96, 120})
      add(number(n) + " elements", [n](variant& v) { v.tie.elements = n; });
    s.baseline = 1;
  } else if (name == "blocks") {
    s.title = "number of blocks (Fig. 13, Table 2)";
    s.parameter = "blocks";
    for (int n : quick ? std::vector<int>{100} : std::vector<int>{100, 250, 500})
      add(number(n) + " blocks", [n](variant& v) {
        v.tie.blocks = n;
        v.loading.dt = tessera::scenes::scaled_tie_dt(n, v.loading.dt);  // same added mass as 100 blocks
      });
  } else if (name == "cbond") {
    s.title = "bond cohesion c_bond (Fig. 15)";
    s.parameter = "c_bond_N_per_m";
    for (real c : quick ? std::vector<real>{1e9, 1e4} : std::vector<real>{1e9, 1e8, 1e7, 1e6, 1e5, 1e4})
      add("c_bond=" + number(c), [c](variant& v) { v.tie.c_bond = c; });
  } else if (name == "rate") {
    s.title = "pull rate (Fig. 8)";
    s.parameter = "rate_m_per_s";
    for (real f : quick ? std::vector<real>{2, 1} : std::vector<real>{4, 2, 1, 0.5})
      add("rate=" + number(f * in.loading.rate) + " m/s", [f](variant& v) { v.loading.rate *= f; });
    s.baseline = s.variants.size() - 1;  // the slowest rate
  } else {
    throw tessera::invalid_input("rc_tie_sensitivity: unknown study '" + name +
                                 "' (expected softening, xi, elements, blocks, cbond or rate)");
  }
  return s;
}

/// Parameter value of a variant for the table (numeric).
double parameter_value(const study& s, const variant& v) {
  if (s.name == "softening") return v.loading.softening == "power" ? 1 : 0;
  if (s.name == "xi") return v.tie.xi;
  if (s.name == "elements") return static_cast<double>(v.tie.elements);
  if (s.name == "blocks") return v.tie.blocks;
  if (s.name == "cbond") return v.tie.c_bond;
  return v.loading.rate;
}

/// The study's curve errors (study::errors), for the table, trends.md and summary.json alike. The
/// bare bar is sampled every 10 µm up to 4 mm (or the longest run, if longer).
variant_errors curve_errors(const study& s, const sc::tie_hand_checks& hand) {
  const auto& base = s.variants[s.baseline].result;
  real u_max = 4e-3;
  for (const auto& v : s.variants) u_max = std::max(u_max, v.result.end_elongation);
  const int n = static_cast<int>(std::ceil(u_max / 1e-5 - 1e-9));
  std::vector<real> bare_u, bare_f;
  for (int i = 0; i <= n; ++i) {
    bare_u.push_back(u_max * i / n);
    bare_f.push_back(hand.bare_bar_force(bare_u.back()));
  }
  variant_errors e;
  for (const auto& v : s.variants) {
    const auto& r = v.result;
    const auto x = tessera::analysis::running_max(r.elongation);
    e.bare_bar.push_back(tessera::analysis::curve_error(x, r.force, bare_u, bare_f, hand.yield_force));
    e.baseline.push_back(tessera::analysis::curve_error(x, r.force, tessera::analysis::running_max(base.elongation), base.force, hand.yield_force));
  }
  return e;
}

void write_study(const study& s, const sc::tie_hand_checks& hand, const fs::path& out) {
  namespace io = tessera::io;
  // Common grid up to the longest run; nan past each variant's end.
  real u_max = 0;
  for (const auto& v : s.variants) u_max = std::max(u_max, v.result.end_elongation);
  constexpr int n = 400;
  std::vector<std::string> names{"elongation_m", "bare_bar_N"};
  std::vector<std::vector<double>> columns(2);
  for (int i = 0; i <= n; ++i) {
    const real u = u_max * i / n;
    columns[0].push_back(u);
    columns[1].push_back(hand.bare_bar_force(u));
  }
  for (std::size_t k = 0; k < s.variants.size(); ++k) {
    const auto& r = s.variants[k].result;
    const std::vector<real> x = tessera::analysis::running_max(r.elongation);
    names.push_back("force_" + std::to_string(k) + "_N");
    std::vector<double> col;
    for (int i = 0; i <= n; ++i) {
      const real u = columns[0][static_cast<std::size_t>(i)];
      col.push_back(x.empty() || u > x.back() ? std::numeric_limits<double>::quiet_NaN() : tessera::analysis::interpolate_curve(x, r.force, u));
    }
    columns.push_back(std::move(col));
  }
  io::write_csv(out / (s.name + ".csv"), names, columns);

  io::plot_spec plot;
  plot.title = "RC tie sensitivity: " + s.title;
  plot.xlabel = "elongation (mm)";
  plot.ylabel = "force (kN)";
  for (std::size_t k = 0; k < s.variants.size(); ++k)
    plot.series.push_back({.csv = out / (s.name + ".csv"), .x_column = "elongation_m",
                           .y_column = "force_" + std::to_string(k) + "_N", .title = s.variants[k].label,
                           .x_scale = 1e3, .y_scale = 1e-3});
  plot.series.push_back({.csv = out / (s.name + ".csv"), .x_column = "elongation_m", .y_column = "bare_bar_N",
                         .title = "bare bar", .style = "lines dt 2 lw 2 lc rgb 'black'", .x_scale = 1e3, .y_scale = 1e-3});
  io::plot_png(out / (s.name + ".png"), plot);

  io::csv_writer table(out / (s.name + "_table.csv"),
                       {"variant", s.parameter, "first_crack_force_N", "initial_stiffness_N_per_m", "load_drops",
                        "softened_cracks", "opened_cracks", "yield_force_N", "yield_elongation_m",
                        "curve_error_vs_baseline_rel", "curve_error_vs_bare_bar_rel", "max_end_force_imbalance_rel",
                        "subcontacts", "steps", "runtime_s"});
  for (std::size_t k = 0; k < s.variants.size(); ++k) {
    const auto& r = s.variants[k].result;
    table.row(static_cast<double>(k), parameter_value(s, s.variants[k]), r.first_crack_force, r.initial_stiffness,
              static_cast<double>(r.drops.size()), static_cast<double>(r.softened_cracks.cracks),
              static_cast<double>(r.cracks.cracks), r.yield_force, r.yield_elongation, s.errors.baseline[k],
              s.errors.bare_bar[k], r.max_imbalance,
              static_cast<double>(r.subcontacts), static_cast<double>(r.steps), r.runtime_s);
  }
  table.commit();
}

/// Trends the study states, checked with our numbers; appended to trends.md.
std::string trends(const study& s) {
  std::ostringstream os;
  os << "## " << s.title << "\n\n| variant | first crack (kN) | K0 (kN/mm) | drops | softened / opened cracks | "
        "yield (kN) | error vs baseline | error vs bare bar | runtime (s) |\n|---|---|---|---|---|---|---|---|---|\n";
  const std::vector<double>& bare_err = s.errors.bare_bar;
  const std::vector<double>& base_err = s.errors.baseline;
  std::vector<double> k0;
  for (std::size_t k = 0; k < s.variants.size(); ++k) {
    const auto& r = s.variants[k].result;
    const auto& v = s.variants[k];
    k0.push_back(r.initial_stiffness);
    char line[512];
    std::snprintf(line, sizeof line, "| %s | %.2f | %.1f | %zu | %d / %d | %.2f | %.2f %% | %.2f %% | %.1f |\n",
                  v.label.c_str(), r.first_crack_force * 1e-3, r.initial_stiffness * 1e-6, r.drops.size(),
                  r.softened_cracks.cracks, r.cracks.cracks, r.yield_force * 1e-3, 100 * base_err[k],
                  100 * bare_err[k], r.runtime_s);
    os << line;
  }
  os << "\n";
  const auto holds = [](bool b) { return b ? "**holds**" : "**does not hold**"; };
  char text[1024];
  if (s.name == "xi" && k0.size() >= 2) {
    const bool ok = std::is_sorted(k0.begin(), k0.end());
    std::snprintf(text, sizeof text,
                  "Study: lower xi softens the initial response. K0 rises with xi: %s (K0 = %.1f kN/mm at the lowest xi, "
                  "%.1f kN/mm at the highest).\n\n",
                  holds(ok), k0.front() * 1e-6, k0.back() * 1e-6);
    os << text;
  } else if (s.name == "elements" && k0.size() >= 2) {
    const bool ok = k0.front() < k0[1];
    std::snprintf(text, sizeof text,
                  "Study: fewer elements soften the initial response. K0(48) < K0(96): %s (%.1f vs %.1f kN/mm).\n\n",
                  holds(ok), k0.front() * 1e-6, k0[1] * 1e-6);
    os << text;
  } else if (s.name == "cbond") {
    const bool ok = bare_err.back() < 0.05 && bare_err.back() < bare_err.front();
    std::snprintf(text, sizeof text,
                  "Study: below c_bond = 1e5 N/m the response approaches the bare bar. Curve error against the bare bar "
                  "%.2f %% at c_bond = %g N/m vs %.2f %% at %g N/m (threshold 5 %%): %s.\n\n",
                  100 * bare_err.back(), s.variants.back().tie.c_bond, 100 * bare_err.front(),
                  s.variants.front().tie.c_bond, holds(ok));
    os << text;
  } else if (s.name == "rate") {
    bool ok = true;
    for (std::size_t k = 1; k + 1 < base_err.size(); ++k) ok = ok && base_err[k] <= base_err[k - 1];
    std::snprintf(text, sizeof text,
                  "Study: curves converge as the rate drops. Error against the slowest rate falls monotonically with "
                  "the rate: %s (%.2f %% at the fastest).\n\n",
                  holds(ok), 100 * base_err.front());
    os << text;
  } else if (s.name == "softening" && s.variants.size() == 2) {
    std::snprintf(text, sizeof text,
                  "Study: linear and power softening give close results with small differences at the local peaks. "
                  "Curve difference %.2f %% of f_y A; first cracking %.2f vs %.2f kN.\n\n",
                  100 * base_err.back(), s.variants[0].result.first_crack_force * 1e-3,
                  s.variants[1].result.first_crack_force * 1e-3);
    os << text;
  } else if (s.name == "blocks") {
    os << "Study: no severe block-size dependency of the macro response. Curve errors against 100 blocks above.\n\n";
  }
  return os.str();
}

/// The studies named by --studies (xi and cbond alone with --quick); throws invalid_input when
/// none is left.
std::vector<study> chosen_studies(const inputs& in) {
  std::vector<std::string> names = tessera::cli::split_list(in.studies, "rc_tie_sensitivity: --studies");
  if (in.common.quick) names.erase(std::remove_if(names.begin(), names.end(), [](const std::string& n) {
                                     return n != "xi" && n != "cbond";
                                   }), names.end());
  std::vector<study> studies;
  for (const auto& n : names) studies.push_back(make_study(n, in));
  tessera::require(!studies.empty(), "rc_tie_sensitivity: --studies '", in.studies, "' names no study",
                   in.common.quick ? " that --quick runs (xi, cbond)" : "");
  return studies;
}

/// summary.json: the run's settings and each variant's figures, flat (<study>_<k>_<figure>).
/// Returns the number of runs and steps.
std::pair<std::int64_t, std::int64_t> write_summary(const fs::path& out, const inputs& in,
                                                    const std::vector<study>& studies,
                                                    const tessera::cli::wall_timer& timer) {
  namespace io = tessera::io;
  io::summary_json js;
  js.set("example", "rc_tie_sensitivity")
      .set("quick", in.common.quick)
      .set("seed", in.common.seed)
      .set("studies", static_cast<std::int64_t>(studies.size()))
      .set("rate_m_per_s", in.loading.rate)
      .set("dt_s", in.loading.dt)
      .set("runtime_s", timer.seconds());
  std::int64_t runs = 0, steps = 0;
  for (const auto& s : studies)
    for (const auto& v : s.variants) ++runs, steps += v.result.steps;
  js.set("runs", runs).set("steps", steps);
  // Each variant's figures, flat: <study>_<k>_<figure> with k the variant's index in trends.md.
  for (const auto& s : studies) {
    for (std::size_t k = 0; k < s.variants.size(); ++k) {
      const auto& r = s.variants[k].result;
      const std::string key = s.name + "_" + std::to_string(k) + "_";
      js.set(key + "variant", s.variants[k].label)
          .set(key + "first_crack_force_N", r.first_crack_force)
          .set(key + "initial_stiffness_N_per_m", r.initial_stiffness)
          .set(key + "load_drops", static_cast<std::int64_t>(r.drops.size()))
          .set(key + "yield_force_N", r.yield_force)
          .set(key + "damping_in_force", r.damping_in_force)
          .set(key + "curve_error_vs_baseline_rel", s.errors.baseline[k])
          .set(key + "curve_error_vs_bare_bar_rel", s.errors.bare_bar[k]);
    }
  }
  for (const auto& s : studies) {
    if (s.name == "xi" || s.name == "elements")
      js.set(s.name + "_initial_stiffness_sorted",
             std::is_sorted(s.variants.begin(), s.variants.end(), [](const variant& a, const variant& b) {
               return a.result.initial_stiffness < b.result.initial_stiffness;
             }));
  }
  js.write(out / "summary.json");
  return {runs, steps};
}

int run(const inputs& in) {
  namespace io = tessera::io;
  const fs::path out = in.common.out;
  const tessera::cli::wall_timer timer;
  std::vector<study> studies = chosen_studies(in);
  io::ensure_directory(out);  // after the study names were checked: bad input leaves no directory

  sc::tie_hand_checks hand;
  std::string md = "# RC tie sensitivity (Pulatsu et al. 2020, Sec. 3.2) — measured trends\n\n";
  {
    std::ostringstream os;
    os << "Baseline: 100 blocks, seed " << in.common.seed << ", 96 elements, xi 4, c_bond 1e9 N/m, power softening, rate "
       << in.loading.rate << " m/s, mass-scaled dt " << in.loading.dt << " s, ramp " << in.loading.ramp_time
       << " s. Curve errors: RMS force difference over the common elongation range / f_y A.\n\n";
    md += os.str();
  }
  io::csv_writer runtime(out / "runtime_table.csv", {"blocks", "subcontacts", "zones", "steps", "runtime_s",
                                                     "study_3dec_min", "speedup_vs_3dec"});
  std::string runtime_md = "| blocks | sub-contacts (study: contact points) | zones | steps | runtime (s) | study 3DEC (min) | speed-up |\n|---|---|---|---|---|---|---|\n";
  for (auto& s : studies) {
    for (std::size_t k = 0; k < s.variants.size(); ++k) {
      variant& v = s.variants[k];
      v.loading.threads = in.common.threads;
      v.loading.progress_label = "rc_tie_sensitivity " + s.name + " " + v.label;
      const sc::tie_scene scene = sc::make_tie(v.tie);
      hand = scene.hand;
      v.result = sc::run_tie(scene, v.loading);
      const auto& r = v.result;
      std::printf("%s / %s: first crack %.2f kN, K0 %.1f kN/mm, drops %zu, cracks %d softened / %d opened, yield %.2f kN, "
                  "%lld steps, %.1f s\n",
                  s.name.c_str(), v.label.c_str(), r.first_crack_force * 1e-3, r.initial_stiffness * 1e-6, r.drops.size(),
                  r.softened_cracks.cracks, r.cracks.cracks, r.yield_force * 1e-3, static_cast<long long>(r.steps),
                  r.runtime_s);
      std::fflush(stdout);
      if (s.name == "blocks") {
        const double minutes = study_minutes(v.tie.blocks);
        runtime.row(v.tie.blocks, static_cast<double>(r.subcontacts), static_cast<double>(r.zones),
                    static_cast<double>(r.steps), r.runtime_s, minutes, minutes > 0 ? 60 * minutes / r.runtime_s : 0.0);
        char line[256];
        std::snprintf(line, sizeof line, "| %d | %lld (%s) | %lld | %lld | %.1f | %g | %.0fx |\n", v.tie.blocks,
                      static_cast<long long>(r.subcontacts),
                      v.tie.blocks == 100 ? "3808" : v.tie.blocks == 250 ? "11564" : v.tie.blocks == 500 ? "25960" : "-",
                      static_cast<long long>(r.zones), static_cast<long long>(r.steps), r.runtime_s, minutes,
                      minutes > 0 ? 60 * minutes / r.runtime_s : 0.0);
        runtime_md += line;
      }
    }
    s.errors = curve_errors(s, hand);
    write_study(s, hand, out);
    md += trends(s);
  }
  runtime.commit();
  md += "## Run time (Table 2 counterpart)\n\n" + runtime_md +
        "\nMeasured on a shared 2-core machine (load from other jobs); the study's times are 3DEC on a 2.1 GHz Xeon.\n";
  io::write_file_atomically(out / "trends.md", md);
  const auto [runs, steps] = write_summary(out, in, studies, timer);
  std::printf("rc_tie_sensitivity: %lld runs, %lld steps, %.1f s; wrote %s\n", static_cast<long long>(runs),
              static_cast<long long>(steps), timer.seconds(), out.string().c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  inputs in;
  tessera::cli::parser cli("rc_tie_sensitivity",
                           "Sensitivity studies of the RC tie (Pulatsu et al. 2020, Sec. 3.2): softening law, bond\n"
                           "stiffness ratio, truss elements, blocks, bond cohesion, pull rate; run-time table.");
  cli.add_standard(in.common);
  cli.option("--studies", in.studies, "comma-separated studies: softening,xi,elements,blocks,cbond,rate", "LIST");
  cli.option("--rate", in.loading.rate, "baseline pull velocity (m/s)", "V").greater_than(0);
  cli.option("--dt", in.loading.dt, "mass-scaled time step (s)", "DT").at_least(0);
  cli.option("--ramp", in.loading.ramp_time, "velocity ramp time (s)", "T").at_least(0);
  cli.option("--max-elongation", in.loading.max_elongation, "stop each run here at the latest (m)", "U").greater_than(0);
  cli.parse_or_exit(argc, argv);
  if (in.common.quick && !cli.given("--dt")) in.loading.dt = 4e-6;  // a given --dt is kept
  // run.json is written when the output directory is created (after the checks), listing each
  // file as it is written; "complete" after summary.json, "interrupted" on SIGINT/SIGTERM.
  tessera::io::run_record record(in.common.out, "rc_tie_sensitivity", argc, argv);
  try {
    const int status = run(in);
    if (status == 0) record.complete();
    return status;
  } catch (const std::exception& e) {
    tessera::cli::print_error("rc_tie_sensitivity", e);
    return 1;
  }
}
