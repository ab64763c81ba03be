// rc_beam: the reference study's reinforced-concrete beam in four-point bending (Pulatsu et al.
// 2020, Sec. 4, Figures 16-18; DESIGN.md §6): flexural cracks in the constant-moment zone, yield
// of the bars, failure by diagonal tension. The default geometry is PROVISIONAL (DESIGN.md §6: not in
// the study's text; Walraven's series-A1 beam is assumed) and every output says so. The scene:
// rc_beam/beam.hpp; the run: beam_run.hpp; cracks and failure mode: beam_cracks.hpp; plates: beam_plates.hpp.
//
// Outputs in --out DIR:
//   curve.csv     midspan_deflection_m, load_N (total load P, both half-spans: twice the half
//                 model's support reaction, or of the force the support plate puts on the
//                 concrete; the sum of the full beam's two), smoothed_load_N (over 0.02 mm of deflection),
//                 plate_load_N (twice the force on the loading plate: larger by the local damping's
//                 drag, beam_run.hpp), load_point_deflection_m (of the loading plate)
//   curve.png     load against mid-span deflection with the hand cracking, yield and shear loads
//   cracks.csv    cracked sub-contacts (past their tensile peak) at the end: x_m, y_m, width_m
//                 (the separation of their two gridpoints), point_size; cracks.png the side view of
//                 the beam with them drawn by width
//   <tag>_zones.vtu, <tag>_contacts.vtp, <tag>_bar.vtp for tag = first_crack, yield, end; beam.pvd
//   summary.json  provisional_geometry, inputs, hand values (cracking, stiffness, yield, shear: EC2 and
//                 Zsutty), first crack, stiffness, yield, peak, cracks, energy balance, failure_reached
//                 (the load fell by --failure-drop, held over --failure-confirm or, with --failure-crack diagonal,
//                 a diagonal crack opening, else a dip: dip_deflections_m; failure_deflection_m where it fell;
//                 without it peak_over_* are null, peak_load_N is the highest load before the stop, load_at_stop_N the last), failure_mode (the widest
//                 crack's classification at the end, reached or not: beam_cracks.hpp),
//                 sizes, runtime_s; model_young_Pa and hand_initial_stiffness_model_modulus_* with --params
//                 (the file's whole concrete: beam_law.hpp load_beam_params);
//                 scheme and relaxation_* (--scheme relaxation: null energy balance and boundary work);
//                 with --plates contact, each plate's sub-contacts, those in contact at the end and
//                 its rotation (support_plate_*, loading_plate_*); boundary_work_J is the work
//                 the supports and plates did on the beam; the law options (cohesion, slip_breaks_tension;
//                 law, g_ii_J_per_m2, phi_*_deg, cap_Pa: beam_law.hpp), steel_yield_Pa; inclined_after_peak_* the fastest-opening
//                 inclined crack after the peak and diagonal_crack_after_peak (beam_post_peak.hpp);
//                 span, elastic_check_* (the load at half the hand first-cracking deflection); with
//                 --span full, failing_span and the left_* / right_* figures of each span
//                 (beam_span.hpp), right_support_plate_* / right_loading_plate_* with its plates;
//                 checkpoint_file, checkpoints_written, resumed_from, resumed_at_step, runtime_before_resume_s
//   --checkpoint FILE: the run's state (io/checkpoint.hpp) at the end and every --checkpoint-every s;
//                 --resume FILE continues it (beam_run.hpp); beam.pvd lists this process's snapshots.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "common/calibration.hpp"
#include "common/cli.hpp"
#include "common/relaxed_scheme.hpp"
#include "rc_beam/beam_law.hpp"
#include "rc_beam/beam_run.hpp"
#include "rc_beam/beam_shear_figure.hpp"
#include "rc_beam/beam_snapshots.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/plot.hpp"
#include "tessera/io/run_record.hpp"

namespace {

using tessera::index_t;
using tessera::real;
namespace fs = std::filesystem;

struct inputs {
  tessera::cli::standard_options common;
  tessera::scenes::beam_options beam;
  tessera::scenes::beam_loading loading;
  std::string scheme = "explicit";                    ///< explicit | relaxation (kinetic dynamic relaxation)
  std::string failure_crack = "any";                  ///< any | diagonal (beam_failure_rule.hpp)
  std::vector<std::string> explicit_given, relax_given;  ///< flags of either scheme on the command line
  bool write_vtk = true;
  std::string params;  ///< --params FILE (calibrate --material beam), empty = the study verbatim
  /// The modulus the contacts give the beam's blocks, from the --params entry (calibrate measures
  /// it on the recipe prism); 0 = not known (no --params, or a file written before it was recorded).
  real model_young = 0;
};

double rel(double value, double reference) { return (value - reference) / reference; }

void write_outputs(const fs::path& out, const inputs& in, const tessera::scenes::beam_scene& scene,
                   const tessera::scenes::beam_result& r, const tessera::scenes::beam_snapshot_writer& snaps,
                   const tessera::cli::wall_timer& timer) {
  namespace io = tessera::io;
  const auto& h = scene.hand;
  const auto& o = scene.options;
  const auto& p = r.after_peak;
  io::write_csv(out / "curve.csv",
                {"midspan_deflection_m", "load_N", "smoothed_load_N", "plate_load_N", "load_point_deflection_m"},
                {r.deflection, r.load, r.smoothed_load, r.plate_load, r.load_point_deflection});
  {
    const real d_end = std::max(r.deflection.empty() ? 0.0 : r.deflection.back(), 1e-3);
    std::vector<real> x{0, d_end}, pcr{h.first_crack_load, h.first_crack_load},
        pfl{h.flexural_crack_load, h.flexural_crack_load}, py{h.yield_load, h.yield_load},
        pv{h.shear_capacity_load, h.shear_capacity_load}, k0x{0, std::min(d_end, 1.5 * h.yield_load / h.initial_stiffness)};
    std::vector<real> k0y{0, k0x[1] * h.initial_stiffness};
    io::write_csv(out / "hand.csv", {"deflection_m", "first_crack_N", "flexural_crack_N", "yield_N", "shear_capacity_N"},
                  {x, pcr, pfl, py, pv});
    io::write_csv(out / "hand_stiffness.csv", {"deflection_m", "load_N"}, {k0x, k0y});
  }
  io::plot_spec plot;
  plot.title = tessera::detail::concat("RC beam (provisional geometry), ", o.span, " beam, ", o.blocks,
                                       o.full() ? " blocks per half" : " blocks", ", seed ", o.seed, ", ",
                                       o.compression, " compression", o.law == "study" ? "" : ", " + o.law + " law",
                                       in.params.empty() ? "" : tessera::detail::concat(", strength x ", o.strength_scale));
  plot.xlabel = "mid-span deflection (mm)";
  plot.ylabel = "total load P (kN)";
  plot.series.push_back({.csv = out / "curve.csv", .x_column = "midspan_deflection_m", .y_column = "load_N",
                         .title = "tessera, P = 2 x support reaction", .style = "lines lw 1 lc rgb '#b0b0b0'", .x_scale = 1e3,
                         .y_scale = 1e-3});
  plot.series.push_back({.csv = out / "curve.csv", .x_column = "midspan_deflection_m", .y_column = "smoothed_load_N",
                         .title = "tessera, smoothed", .x_scale = 1e3, .y_scale = 1e-3});
  plot.series.push_back({.csv = out / "hand_stiffness.csv", .x_column = "deflection_m", .y_column = "load_N",
                         .title = "uncracked, hand", .style = "lines dt 3", .x_scale = 1e3, .y_scale = 1e-3});
  plot.series.push_back({.csv = out / "hand.csv", .x_column = "deflection_m", .y_column = "first_crack_N",
                         .title = "first cracking at f_T, hand", .style = "lines dt 2", .x_scale = 1e3, .y_scale = 1e-3});
  plot.series.push_back({.csv = out / "hand.csv", .x_column = "deflection_m", .y_column = "flexural_crack_N",
                         .title = "first cracking at the flexural strength (MC2010), hand", .style = "lines dt 2",
                         .x_scale = 1e3, .y_scale = 1e-3});
  if (h.yield_load < 3 * std::max(r.peak_load, h.shear_capacity_load))  // bars that cannot yield: off the chart
    plot.series.push_back({.csv = out / "hand.csv", .x_column = "deflection_m", .y_column = "yield_N",
                           .title = "yield A_s f_y z, hand", .style = "lines dt 2", .x_scale = 1e3, .y_scale = 1e-3});
  plot.series.push_back({.csv = out / "hand.csv", .x_column = "deflection_m", .y_column = "shear_capacity_N",
                         .title = "shear capacity (EC2 form), hand", .style = "lines dt 4", .x_scale = 1e3,
                         .y_scale = 1e-3});
  io::plot_png(out / "curve.png", plot);

  real w_max = 0;
  for (real w : snaps.crack_w) w_max = std::max(w_max, w);
  std::vector<real> point_size;
  for (real w : snaps.crack_w) point_size.push_back(0.25 + 2.5 * (w_max > 0 ? w / w_max : 0));
  io::write_csv(out / "cracks.csv", {"x_m", "y_m", "width_m", "point_size"},
                {snaps.crack_x, snaps.crack_y, snaps.crack_w, point_size});
  tessera::scenes::plot_beam_crack_map(out, o, w_max);
  const real L = o.half_length();

  std::vector<real> crack_x, crack_angle, crack_width, crack_top;
  for (const auto& c : r.final_cracks)
    crack_x.push_back(c.x), crack_angle.push_back(c.angle_deg), crack_width.push_back(c.width), crack_top.push_back(c.y_max);
  io::summary_json js;
  js.set("example", "rc_beam")
      .set("provisional_geometry", true)
      .set("plates", o.plates)
      .set("plates_model", std::string(o.plates == "contact"
                                            ? "rigid steel plates, hinged, touching the concrete through frictional "
                                              "never-bonded contacts (contact::rigid_platen)"
                                            : "rigid, hinged: the gridpoints under each plate move as one plate "
                                              "turning about its axis"))
      .set("blocks", o.blocks)
      .set("span", o.span)
      .set("model_blocks", o.model_blocks())
      .set("seed", o.seed)
      .set("compression", o.compression)
      .set("cohesion", o.cohesion).set("slip_breaks_tension", o.slip_breaks_tension)
      .set("steel_yield_Pa", o.steel_yield)
      .set("parameters", in.params.empty() ? "verbatim" : "calibrated")
      .set("params_file", in.params)
      .set("strength_scale", o.strength_scale)
      .set("fracture_energy_scale", o.fracture_energy_scale)
      .set("width_m", o.width).set("height_m", o.height)
      .set("effective_depth_m", o.effective_depth).set("shear_span_m", o.shear_span)
      .set("moment_zone_m", o.moment_zone).set("overhang_m", o.overhang)
      .set("plate_m", o.plate).set("plate_thickness_m", o.plate_thickness);
  tessera::scenes::set_beam_law_figures(js, scene);
  if (o.plates == "contact")
    js.set("support_plate_subcontacts", static_cast<std::int64_t>(r.plate_subcontacts[0]))
        .set("loading_plate_subcontacts", static_cast<std::int64_t>(r.plate_subcontacts[1]))
        .set("support_plate_in_contact_at_end", static_cast<std::int64_t>(r.plate_in_contact[0]))
        .set("loading_plate_in_contact_at_end", static_cast<std::int64_t>(r.plate_in_contact[1]))
        .set("support_plate_rotation_rad", r.plate_rotation[0])
        .set("loading_plate_rotation_rad", r.plate_rotation[1])
        .set("plate_added_mass_kg", r.plate_added_mass);
  if (o.plates == "contact" && o.full())
    js.set("right_support_plate_subcontacts", static_cast<std::int64_t>(r.plate_subcontacts[2]))
        .set("right_loading_plate_subcontacts", static_cast<std::int64_t>(r.plate_subcontacts[3]))
        .set("right_support_plate_in_contact_at_end", static_cast<std::int64_t>(r.plate_in_contact[2]))
        .set("right_loading_plate_in_contact_at_end", static_cast<std::int64_t>(r.plate_in_contact[3]))
        .set("right_support_plate_rotation_rad", r.plate_rotation[2])
        .set("right_loading_plate_rotation_rad", r.plate_rotation[3]);
  js.set("bars", o.bars)
      .set("bar_diameter_m", o.bar_diameter)
      .set("half_length_m", L)
      .set("span_m", h.span)
      .set("rate_m_per_s", in.loading.rate)
      .set("quick", in.common.quick)
      .set("threads", tessera::max_threads())
      .set("zone_edge_m", o.face_zone_edge())
      .set("contact_points_over_depth", r.contact_points_over_depth)
      .set("trusses_per_block", r.trusses_per_block)
      .set("truss_elements_per_bar", scene.elements_per_bar)
      .set("subcontacts", r.subcontacts)
      .set("study_subcontacts", o.blocks == 500 ? 55228 : 27274)
      .set("zones", r.zones)
      .set("gridpoints", r.gridpoints)
      .set("hand_first_crack_load_N", h.first_crack_load)
      .set("first_crack_load_N", r.first_crack_load)
      .set("first_crack_error_rel", rel(r.first_crack_load, h.first_crack_load))
      .set("hand_flexural_crack_load_N", h.flexural_crack_load)
      .set("first_crack_flexural_error_rel", rel(r.first_crack_load, h.flexural_crack_load))
      .set("first_crack_deflection_m", r.first_crack_deflection)
      .set("soffit_peak_stress_Pa", r.soffit_peak_stress)
      .set("developed_crack_load_N", r.developed_crack_load)
      .set("developed_crack_deflection_m", r.developed_crack_deflection)
      .set("first_crack_x_m", r.first_crack_x)
      .set("first_crack_angle_deg", r.first_crack_angle_deg)
      .set("first_crack_in_moment_zone", r.first_crack_x >= o.load_x() - 0.5 * h.mean_block_size &&
                                             (!o.full() || r.first_crack_x <= o.mirror(o.load_x()) + 0.5 * h.mean_block_size))
      .set("first_inclined_crack_load_N", r.first_inclined_crack_load)
      .set("first_inclined_crack_deflection_m", r.first_inclined_crack_deflection)
      .set("first_inclined_crack_x_m", r.first_inclined_crack_x)
      .set("first_inclined_crack_span", r.first_inclined_crack_span < 0 ? "none" : (r.first_inclined_crack_span == 0 ? "left" : "right"))
      .set("vertical_cracks_first", r.developed_crack_load > 0 && !r.inclined_before_vertical)
      .set("hand_initial_stiffness_N_per_m", h.initial_stiffness)
      .set("initial_stiffness_N_per_m", r.initial_stiffness)
      .set("initial_stiffness_error_rel", rel(r.initial_stiffness, h.initial_stiffness))
      .set("elastic_check_deflection_m", r.elastic.deflection)
      .set("elastic_check_load_N", r.elastic.load)
      .set("elastic_check_samples", r.elastic.samples);
  if (o.full())
    js.set("elastic_check_reaction_asymmetry_rel", r.elastic.reaction_asymmetry)
        .set("elastic_check_plate_load_asymmetry_rel", r.elastic.plate_load_asymmetry)
        .set("failing_span", r.failing_span);
  if (in.model_young > 0) {
    // The hand stiffness is proportional to E (bending and shear, G = E / 2.4).
    const real k_model = h.initial_stiffness * in.model_young / tessera::scenes::beam_concrete_young;
    js.set("model_young_Pa", in.model_young)
        .set("hand_initial_stiffness_model_modulus_N_per_m", k_model)
        .set("initial_stiffness_model_modulus_error_rel", rel(r.initial_stiffness, k_model));
  }
  js.set("hand_yield_load_N", h.yield_load)
      .set("hand_steel_yield_Pa", h.steel_yield)
      .set("lever_arm_m", h.lever_arm)
      .set("steel_yielded", r.steel_yielded)
      .set("yield_load_N", r.yield_load)
      .set("yield_error_rel", r.steel_yielded ? rel(r.yield_load, h.yield_load) : 0.0)
      .set("yield_deflection_m", r.yield_deflection)
      .set("hand_shear_capacity_load_N", h.shear_capacity_load)
      .set("hand_ec2_shear_load_N", h.ec2_shear_load).set("hand_zsutty_shear_load_N", h.zsutty_shear_load)
      .set("shear_span_over_depth", o.shear_span / o.effective_depth)
      .set("flexural_cracks", r.flexural_cracks)
      .set("flexural_crack_positions_m", r.flexural_crack_positions)
      .set("mean_crack_spacing_m", r.mean_crack_spacing)
      .set("study_crack_spacing_m", 0.09)
      .set("cracks", static_cast<std::int64_t>(r.final_cracks.size()))
      .set("crack_positions_m", crack_x)
      .set("crack_angles_deg", crack_angle)
      .set("crack_widths_m", crack_width)
      .set("crack_tops_m", crack_top)
      .set("inclined_after_peak_found", p.found)
      .set("inclined_after_peak_x_m", p.x)
      .set("inclined_after_peak_angle_deg", p.angle_deg)
      .set("inclined_after_peak_top_m", p.y_max)
      .set("inclined_after_peak_opening_increase_m", p.opening_increase)
      .set("inclined_after_peak_opening_rate", p.opening_rate)
      .set("inclined_after_peak_window_start_m", p.window_start_deflection)
      .set("inclined_after_peak_window_end_m", p.window_end_deflection)
      .set("inclined_after_peak_load_drop_N", p.load_drop)
      .set("flexural_opening_rate_same_window", p.flexural_opening_rate)
      .set("diagonal_crack_after_peak", p.diagonal)
      .set("boundary_work_J", r.boundary_work)
      .set("contact_dissipated_J", r.contact_dissipated)
      .set("tension_dissipated_J", r.tension_dissipated)
      .set("compression_dissipated_J", r.compression_dissipated)
      .set("damping_dissipated_J", r.damping_dissipated)
      .set("energy_balance_error_rel", r.energy_balance_error)
      .set("quasi_static_index", r.quasi_static_index)
      .set("ramp_s", r.ramp_time)
      .set("dt_s", r.dt)
      .set("added_mass_ratio", r.added_mass_ratio)
      .set("steps", r.steps)
      .set("checkpoint_file", in.loading.checkpoint_file)
      .set("checkpoints_written", r.checkpoints_written)
      .set("resumed_from", in.loading.resume_file)
      .set("resumed_at_step", r.resumed_at_step)
      .set("runtime_before_resume_s", r.runtime_before_resume_s)
      .set("study_runtime_s", o.blocks == 500 ? 990 * 60.0 : 420 * 60.0)
      .set("runtime_s", r.runtime_before_resume_s + timer.seconds());
  tessera::scenes::set_failure_figures(js, r, h);
  js.set("failure_crack", in.failure_crack);
  tessera::scenes::set_shear_figures(js, r);
  if (o.full()) tessera::scenes::set_span_figures(js, r.spans);
  // The phase times are this process's (a resumed run's from its checkpoint on): per its own steps.
  tessera::scenes::set_scheme_figures(js, in.scheme, in.loading.relax_increment, in.loading.relax_tolerance, r);
  tessera::scenes::set_phase_figures(js, r.phases, r.zones, r.subcontacts,
                                     r.resumed_at_step >= 0 ? r.steps - r.resumed_at_step : r.steps);
  tessera::scenes::set_split_figures(js);
  js.write(out / "summary.json");

  char yield_buf[160];
  if (r.steel_yielded)
    std::snprintf(yield_buf, sizeof yield_buf, "yield at %.2f kN (hand A_s f_y z %.2f, f_y %.0f MPa, %+.1f %%)",
                  r.yield_load * 1e-3, h.yield_load * 1e-3, h.steel_yield * 1e-6, 100 * rel(r.yield_load, h.yield_load));
  else
    std::snprintf(yield_buf, sizeof yield_buf, "bars not yielded (hand A_s f_y z %.2f kN, f_y %.0f MPa)",
                  h.yield_load * 1e-3, h.steel_yield * 1e-6);
  const std::string yield_text = yield_buf;
  char after_buf[320] = "none in the shear span";
  if (p.found)
    std::snprintf(after_buf, sizeof after_buf,
                  "x = %.0f mm, %.0f deg, +%.3f mm after the peak, %.2f mm/mm over deflection %.2f-%.2f mm (vertical "
                  "cracks of the moment zone %.2f mm/mm), load drop %.2f kN; diagonal crack after the peak: %s",
                  p.x * 1e3, p.angle_deg, p.opening_increase * 1e3, p.opening_rate, p.window_start_deflection * 1e3,
                  p.window_end_deflection * 1e3, p.flexural_opening_rate, p.load_drop * 1e-3, p.diagonal ? "yes" : "no");
  const std::string after_peak_text = after_buf;
  std::string shear_text = r.shear_at_peak.empty() ? "none" : "";
  for (const auto& sp : r.shear_at_peak) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s%.0f mm: %.1f + %.1f + %.1f + %.1f = %.1f kN (%.1f)", shear_text.empty() ? "" : "; ",
                  sp.x * 1e3, sp.intact * 1e-3, sp.softening * 1e-3, sp.broken_or_slipped * 1e-3, sp.bars * 1e-3,
                  sp.total() * 1e-3, sp.reaction * 1e-3);
    shear_text += buf;
  }
  std::printf(
      "rc_beam (PROVISIONAL geometry): %d blocks%s, %lld sub-contacts (study %d), %.1f contact points over the depth,"
      " %.1f trusses per block\n"
      "  first crack %.2f kN (hand: f_T %.2f, %+.1f %%; flexural strength %.2f, %+.1f %%); h/4 deep %.2f kN at x = %.0f mm,"
      " %.0f deg;"
      " K0 %.1f kN/mm (hand %.1f, %+.1f %%)\n"
      "  %s; %s\n"
      "  %d flexural cracks in the constant-moment zone (whole beam), mean spacing %.0f mm (study 90); failure mode "
      "(the widest crack's): %s (x = %.0f mm, %.0f deg, %.2f mm)\n"
      "  fastest inclined crack after the peak: %s%s\n"
      "  shear at the peak (section x: intact + softening + broken/slipped + bars = total; P/2): %s\n"
      "  energy balance %.2g; dt %.3g s (added mass %.1fx, quasi-static index %.2f), %lld steps, %.1f s; wrote %s\n",
      o.blocks, tessera::scenes::beam_law_label(o, !in.params.empty()).c_str(),
      static_cast<long long>(r.subcontacts), o.blocks == 500 ? 55228 : 27274, r.contact_points_over_depth,
      r.trusses_per_block, r.first_crack_load * 1e-3, h.first_crack_load * 1e-3,
      100 * rel(r.first_crack_load, h.first_crack_load), h.flexural_crack_load * 1e-3,
      100 * rel(r.first_crack_load, h.flexural_crack_load), r.developed_crack_load * 1e-3, r.first_crack_x * 1e3,
      r.first_crack_angle_deg,
      r.initial_stiffness * 1e-6, h.initial_stiffness * 1e-6, 100 * rel(r.initial_stiffness, h.initial_stiffness),
      yield_text.c_str(), tessera::scenes::beam_peak_text(r, h, in.loading.failure_drop, in.loading.failure_confirm).c_str(), r.flexural_cracks, r.mean_crack_spacing * 1e3, r.failure_mode.c_str(),
      r.widest.x * 1e3, r.widest.angle_deg, r.widest.width * 1e3, after_peak_text.c_str(),
      o.full() ? tessera::detail::concat("\n  full beam: failing span ", r.failing_span, "; support reactions at the peak ",
                                         r.spans[0].reaction_at_peak * 1e-3, " / ", r.spans[1].reaction_at_peak * 1e-3,
                                         " kN (left / right)").c_str() : "", shear_text.c_str(), r.energy_balance_error, r.dt, r.added_mass_ratio,
      r.quasi_static_index, static_cast<long long>(r.steps), r.runtime_before_resume_s + timer.seconds(), out.string().c_str());
  tessera::scenes::print_relaxation_counts(r);  // a relaxed run: its dt and added mass above are at 1 s of pseudo-time
}

int run(inputs in) {
  const fs::path out = in.common.out;
  const tessera::cli::wall_timer timer;
  in.beam.seed = in.common.seed;
  in.loading.threads = in.common.threads;
  tessera::scenes::check_scheme_flags({.driver = "rc_beam", .scheme = in.scheme, .explicit_given = in.explicit_given,
                                       .relax_given = in.relax_given, .explicit_load = "loading",
                                       .moves = "the loading plate moves", .increment = in.loading.relax_increment,
                                       .last = in.loading.max_deflection, .last_flag = "--max-deflection"});
  tessera::scenes::check_beam_relaxation(in.beam, in.loading);
  const tessera::scenes::beam_scene scene = tessera::scenes::make_beam(in.beam);
  if (!in.loading.checkpoint_file.empty()) {
    const fs::path parent = fs::path(in.loading.checkpoint_file).parent_path();
    if (!parent.empty()) tessera::io::ensure_directory(parent);
  }
  tessera::scenes::beam_snapshot_writer snaps(out, scene, in.write_vtk);
  const tessera::scenes::beam_result r = tessera::scenes::run_beam(scene, in.loading, snaps);
  tessera::io::ensure_directory(out);
  write_outputs(out, in, scene, r, snaps, timer);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  tessera::scenes::mpi_session mpi(argc, argv);
  inputs in;
  tessera::cli::parser cli(
      "rc_beam",
      "Reinforced-concrete beam without stirrups in four-point bending (Pulatsu et al. 2020, Sec. 4), the half beam with\n"
      "its symmetry face or the whole beam (--span): flexural cracks, yield of the bars, diagonal tension. Default\n"
      "geometry PROVISIONAL (DESIGN.md 6): Walraven's series-A1 beam, b 200, h 150, d 125 mm, shear span 375 mm,\n"
      "constant-moment zone 500 mm, 4 x 8 mm bars.\n"
      "--quick: 60 blocks, 50 mm face zoning, stops at twice the deflection of the first crack h/4 deep (on the default\n"
      "beam short of the failure: summary.json failure_reached false, the peak_over_* ratios null).\n"
      "Under mpirun -np N (builds with MPI): split over N ranks, the same curve.csv to the bit; rank 0 writes --out.\n"
      "--checkpoint FILE saves a long run's state as it goes; --resume FILE continues it, to the same bits.");
  cli.add_standard(in.common);
  bool no_vtk = false;
  auto& b = in.beam;
  auto& l = in.loading;
  l.added_mass_ratio = tessera::scenes::rc_beam_added_mass_ratio;
  cli.option("--blocks", b.blocks, "Voronoi blocks of the half beam: 250 or 500 (the study's), or 8..249 for a coarse run "
             "with the 250-block contacts; with --span full, of ONE half span (the full beam has about 2N, at the half "
             "model's block size and contacts)", "N").within(8, 500);
  cli.option("--span", b.span, "half: the half beam with a symmetry face at mid-span (forces symmetric cracks); full: "
             "the whole beam, both shear spans, supports and loading plates (on a spreader: equal plate loads), no "
             "symmetry condition", "half|full")
      .one_of({"half", "full"});
  tessera::scenes::add_beam_law_flags(cli, b);
  cli.option("--compression", b.compression, "contact law in compression: plastic (cap at f_c = 35 MPa) or elastic",
             "plastic|elastic").one_of({"plastic", "elastic"});
  cli.option("--cohesion", b.cohesion,
             "contact cohesion under tensile softening: decoupled (c_0 until broken, the study) or coupled (softens "
             "with f_t/f_T; with --compression plastic only)", "decoupled|coupled").one_of({"decoupled", "coupled"});
  cli.flag("--slip-breaks-tension", b.slip_breaks_tension,
           "a contact that fails in shear is broken in tension too (3DEC's brittle Coulomb joint; the study keeps its "
           "tension)");
  cli.option("--steel-yield", b.steel_yield, "yield stress of the bars f_y (Pa); 440e6 the study's, 1e12 keeps them "
             "elastic", "F_Y").greater_than(0);
  cli.option("--width", b.width, "beam width b (m)", "M").greater_than(0);
  cli.option("--height", b.height, "beam depth h (m)", "M").greater_than(0);
  cli.option("--depth", b.effective_depth, "effective depth d (m): bars at h - d above the soffit", "M").greater_than(0);
  cli.option("--overhang", b.overhang, "beam end to support axis (m)", "M").greater_than(0);
  cli.option("--shear-span", b.shear_span, "support axis to load axis a (m)", "M").greater_than(0);
  cli.option("--moment-zone", b.moment_zone, "length of the constant-moment zone, whole beam (m)", "M").greater_than(0);
  cli.option("--plate", b.plate, "support and loading plate length along the span (m)", "M").greater_than(0);
  cli.option("--plates", b.plates,
             "contact: steel plates of their own on frictional never-bonded contacts; tied: the gridpoints under "
             "each plate moved as one hinged plate (the study's driven nodes)", "contact|tied")
      .one_of({"contact", "tied"});
  cli.option("--plate-thickness", b.plate_thickness, "steel plate thickness, for its mass (m)", "M").greater_than(0);
  cli.option("--bars", b.bars, "bars across the width", "N").within(1, 100);
  cli.option("--bar-diameter", b.bar_diameter, "bar diameter (m)", "M").greater_than(0);
  cli.option("--end-cover", b.end_cover, "distance from the beam end to the bar ends (m)", "M").at_least(0);
  cli.option("--trusses-per-block", b.trusses_per_block, "truss elements per mean block size along a bar", "K").greater_than(0);
  cli.option("--zone-edge", b.zone_edge, "target edge of the faces' zoning (m): every face gridpoint is a contact point; 0 = h/5", "M").at_least(0);
  cli.option("--regularize", b.regularize, "collapse Voronoi edges shorter than REL x mean cell size (0 = off)", "REL")
      .within(0, tessera::geometry::max_regularization);
  cli.option("--scheme", in.scheme, "explicit: central differences with local damping, the plate moved at --rate (the "
             "study's scheme); relaxation: kinetic dynamic relaxation, the plate moved in increments each relaxed to "
             "static equilibrium (docs/guide.md; the study's law, one process, no checkpoints)", "explicit|relaxation")
      .one_of({"explicit", "relaxation"});
  cli.option("--relax-increment", l.relax_increment, "with --scheme relaxation: plate travel per increment (m)", "M")
      .greater_than(0);
  cli.option("--relax-tolerance", l.relax_tolerance, "with --scheme relaxation: an increment is relaxed once the "
             "largest nodal unbalanced force and block resultant are at most this x P_cr (hand)", "R").greater_than(0).at_most(1);
  cli.option("--rate", l.rate, "loading plate velocity (m/s)", "V").greater_than(0);
  cli.option("--ramp", l.ramp_time, "half-cosine ramp of the plate velocity (s); -1 = the period of the first bending mode", "T").at_least(-1);
  cli.option("--added-mass", l.added_mass_ratio, "mass scaling to the step at which R x the original mass is added", "R").at_least(0);
  cli.option("--dt", l.dt, "instead of --added-mass: mass-scaled time step (s); 0 = use --added-mass", "DT").at_least(0);
  cli.option("--max-deflection", l.max_deflection, "stop at this mid-span deflection (m)", "U").greater_than(0);
  cli.option("--failure-drop", l.failure_drop, "stop once the load has fallen this fraction below its peak: the failure "
             "(summary.json failure_reached; without it the peak_over_* ratios are null, and failure_mode is the "
             "widest crack's classification either way)", "R").within(0.01, 0.99);
  cli.option("--failure-confirm", l.failure_confirm, "the drop of --failure-drop must hold (the load below it at every "
             "sample) over this much further mid-span deflection before the run stops; a load that climbs back above it "
             "was a transient dip and the run goes on, the peak rising if the load passes it (m; 0 = the first sample "
             "below stops; summary.json failure_deflection_m: where the drop began)", "U").within(0, 0.1);
  cli.option("--failure-crack", in.failure_crack, "any: every drop of --failure-drop is the failure; diagonal: only a "
             "drop as a diagonal crack opens (faster than every flexural crack) or a band in a shear span softens since "
             "the peak, any other drop is a dip and the run goes on (summary.json dip_deflections_m)", "any|diagonal").one_of({"any", "diagonal"});
  cli.option("--damping", l.damping_gamma, "local damping constant gamma", "G").within(0, 0.99);
  cli.option("--sample", l.sample, "steps between curve samples", "K").at_least(1);
  cli.option("--params", in.params,
             "calibrated concrete: calibrated.json of calibrate --material beam, its entry for --blocks (the zoning and "
             "the beam's dimensions must match) with its whole set (law, scales, c_0/f_T, phi_0, phi_res, G_II, cap, G_c, "
             "residual cap), instead of the law flags (--law ... --crush-shear); default: the study's parameters verbatim",
             "FILE");
  cli.flag("--no-vtk", no_vtk, "skip the VTK snapshots");
  cli.option("--checkpoint", l.checkpoint_file,
             "save the run's state to FILE (atomically) when it ends and every --checkpoint-every s of wall time, "
             "to continue it with --resume (one process)", "FILE");
  cli.option("--checkpoint-every", l.checkpoint_every, "wall time between checkpoints (s); 0 = at the end only", "S")
      .at_least(0);
  cli.option("--resume", l.resume_file,
             "continue the run saved in FILE by --checkpoint, to the same bits as a run that never stopped; give the "
             "saved run's flags (all but --threads, --out, --no-vtk, --max-deflection, --failure-drop, --failure-confirm, "
             "--checkpoint and --checkpoint-every must be the same)", "FILE");
  cli.parse_or_exit(argc, argv);
  in.write_vtk = !no_vtk;
  l.relaxation = in.scheme == "relaxation";
  l.failure_needs_diagonal = in.failure_crack == "diagonal";
  for (const char* f : {"--rate", "--ramp", "--added-mass", "--dt", "--sample"})
    if (cli.given(f)) in.explicit_given.emplace_back(f);
  for (const char* f : {"--relax-increment", "--relax-tolerance"})
    if (cli.given(f)) in.relax_given.emplace_back(f);
  l.run_key = tessera::scenes::beam_run_key(argc, argv);
  if (in.common.quick) {
    // CTest: a coarse beam to first cracking and a little past it.
    if (!cli.given("--blocks")) b.blocks = 60;
    if (!cli.given("--zone-edge")) b.zone_edge = 0.05;
    if (!cli.given("--max-deflection")) l.max_deflection = 2e-3;
    l.first_crack_only = 2;
  }
  try {
    mpi.require_splittable(!l.relaxation, "rc_beam --scheme relaxation", "kinetic relaxation is not distributed");
    tessera::scenes::check_beam_law_flags(cli, in.params, in.beam.law, in.beam.g_c);
    if (!in.params.empty()) in.model_young = tessera::scenes::load_beam_params(in.beam, in.params, l.rate);
    tessera::scenes::check_beam_law_set(in.beam);
    tessera::scenes::check_beam_checkpoint_flags(cli, in.loading, mpi.ranks());
    tessera::require(!l.failure_needs_diagonal || (l.failure_confirm == 0 && mpi.ranks() <= 1), "rc_beam: --failure-crack "
                     "diagonal runs in one process without --failure-confirm (got ", l.failure_confirm, " m, ", mpi.ranks(), " ranks)");
  } catch (const std::exception& e) {
    if (mpi.rank() == 0) tessera::cli::print_error("rc_beam", e);
    return 2;
  }
  mpi.route_output(in.common.out);  // under mpirun: rank 0 writes --out
  tessera::io::run_record record(in.common.out, "rc_beam", argc, argv);
  try {
    const int status = run(in);
    if (status == 0) record.complete();
    return status;
  } catch (const std::exception& e) {
    tessera::cli::print_error("rc_beam", e);
    return 1;
  }
}
