// verification: the contact-detection verification problems (examples/verification/cases.hpp):
// a block on an incline that sticks or slides, a block that topples or not, a settling stack and
// a dropped block, each against its closed-form answer; a cracked prism that recloses; and a
// bonded cube that fails in shear and slides on its broken face. --deformable runs the first four
// with deformable blocks (elastic zones; cases.hpp).
//
// Outputs in --out (default results/verification):
//   summary.json  case, inputs (block_model; young_Pa, zone_edge_m with --deformable), measured,
//                 reference, error_rel, tolerance, pass, mode (topple),
//                 drift_m (stack), peak_Pa / stress_at_reversal_Pa / max_stress_after_closure_Pa
//                 (reclose), failure_tilt_deg / acceleration / acceleration_reference /
//                 acceleration_error / slide_m / bonded_at_start / kept_last_rebuild (bond),
//                 energy_error_rel, steps, rebuilds, subcontacts, runtime_s
//   curve.csv     t_s, x_m, z_m, tilt_rad of the moving (top) block; reclose: u_m, stress_Pa;
//                 bond: t_s, x_m, force_N (the shear force on the cube)
//   blocks_final.vtu   the blocks at the end (ParaView; not for reclose)
// Exit status 0 when the case ran (pass or not: the summary says), 1 on an error, 2 on bad flags.

#include <cstdio>
#include <filesystem>
#include <string>

#include "common/cli.hpp"
#include "tessera/io/csv.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/run_record.hpp"
#include "tessera/io/vtk.hpp"
#include "verification/cases.hpp"

namespace {

namespace ver = tessera::verification;
namespace io = tessera::io;

struct inputs {
  tessera::cli::standard_options common;
  ver::inputs scene;
};

int run(const inputs& in) {
  const std::filesystem::path out = in.common.out;
  ver::validate(in.scene);  // before anything is written
  io::ensure_directory(out);
  if (in.common.threads > 0) tessera::set_threads(in.common.threads);
  const tessera::cli::wall_timer timer;
  const ver::result r = ver::run(in.scene);
  const double runtime_s = timer.seconds();

  if (r.which == "reclose") {
    io::write_csv(out / "curve.csv", {"u_m", "stress_Pa"}, {r.u, r.stress});
  } else if (r.which == "bond") {
    io::write_csv(out / "curve.csv", {"t_s", "x_m", "force_N"}, {r.t, r.x, r.force});
    io::vtk::write_blocks_vtu(out / "blocks_final.vtu", r.final_blocks);
  } else {
    io::write_csv(out / "curve.csv", {"t_s", "x_m", "z_m", "tilt_rad"}, {r.t, r.x, r.z, r.rotation});
    io::vtk::write_blocks_vtu(out / "blocks_final.vtu", r.final_blocks);
  }
  io::summary_json s;
  s.set("example", "verification").set("case", r.which).set("quick", in.scene.quick);
  if (r.which == "reclose") {
    s.set("prism_blocks", 100);  // the study's prism (examples/common/scenes.hpp)
  } else {
    s.set("angle_deg", in.scene.angle_deg)
        .set("friction_deg", in.scene.friction_deg)
        .set("aspect", in.scene.aspect)
        .set("size_m", in.scene.size)
        .set("blocks", in.scene.blocks)
        .set("k_n_Pa_per_m", in.scene.k_n)
        .set("tolerance_m", in.scene.tolerance);
    if (r.which != "bond") s.set("block_model", in.scene.deformable ? "deformable" : "rigid");
    if (in.scene.deformable)
      s.set("young_Pa", in.scene.young).set("zone_edge_m", in.scene.zone_edge > 0 ? in.scene.zone_edge : in.scene.size);
  }
  s.set("quantity", r.quantity)
      .set("unit", r.unit)
      .set("measured", r.measured)
      .set("reference", r.reference)
      .set("error_rel", r.error_rel)
      .set("tolerance", r.tolerance)
      .set("pass", r.pass);
  if (r.which == "topple") s.set("mode", r.mode).set("expected_mode", r.expected_mode);
  if (r.which == "stack") s.set("drift_m", r.drift_m);
  if (r.which == "bond")
    s.set("cohesion_Pa", in.scene.cohesion)
        .set("failure_tilt_deg", r.stress_at_reversal * 180 / 3.14159265358979323846)
        .set("acceleration", r.acceleration)
        .set("acceleration_reference", r.acceleration_reference)
        .set("acceleration_error", r.acceleration_error)
        .set("slide_m", r.slide_m)
        .set("bonded_at_start", static_cast<std::int64_t>(r.bonded_at_start))
        .set("kept_last_rebuild", static_cast<std::int64_t>(r.kept_last_rebuild));
  if (r.which == "reclose")
    s.set("peak_Pa", r.peak)
        .set("stress_at_reversal_Pa", r.stress_at_reversal)
        .set("max_stress_after_closure_Pa", r.max_stress_after_closure);
  s.set("energy_error_rel", r.energy_error_rel).set("dt_s", r.dt).set("steps", static_cast<std::int64_t>(r.steps))
      .set("damping_in_force", r.damping_in_force);
  if (r.which != "reclose")
    s.set("rebuilds", static_cast<std::int64_t>(r.rebuilds))
        .set("storage_growths", static_cast<std::int64_t>(r.growths))
        .set("subcontacts", static_cast<std::int64_t>(r.subcontacts));
  s.set("threads", tessera::max_threads()).set("runtime_s", runtime_s);
  s.write(out / "summary.json");

  std::printf("verification %s: %s %.6g %s, reference %.6g, error_rel %.3g (tolerance %.3g) -> %s\n", r.which.c_str(),
              r.quantity.c_str(), r.measured, r.unit.c_str(), r.reference, r.error_rel, r.tolerance,
              r.pass ? "pass" : "FAIL");
  if (r.which == "topple") std::printf("  mode %s, expected %s\n", r.mode.c_str(), r.expected_mode.c_str());
  if (r.which == "stack") std::printf("  drift of the top block over the second half %.3g m\n", r.drift_m);
  if (r.which == "bond")
    std::printf("  %lld sub-contacts started bonded, failed at a tilt of %.4g deg; then a = %.6g m/s^2 against %.6g "
                "(error %.3g), slid %.4g m; %lld kept their state at the last rebuild\n",
                static_cast<long long>(r.bonded_at_start), r.stress_at_reversal * 180 / 3.14159265358979323846,
                r.acceleration, r.acceleration_reference, r.acceleration_error, r.slide_m,
                static_cast<long long>(r.kept_last_rebuild));
  if (r.which == "reclose")
    std::printf("  peak %.4g MPa; the push began at %.4g MPa, the re-pull reached %.4g MPa (no tension regained)\n",
                r.peak * 1e-6, r.stress_at_reversal * 1e-6, r.max_stress_after_closure * 1e-6);
  if (r.which == "reclose")
    std::printf("  %lld steps of %.3g s, energy balance %.2g, runtime_s %.3f\n", static_cast<long long>(r.steps), r.dt,
                r.energy_error_rel, runtime_s);
  else
    std::printf("  %lld steps of %.3g s, %lld rebuilds, %lld sub-contacts at the end, energy balance %.2g, runtime_s %.3f\n",
                static_cast<long long>(r.steps), r.dt, static_cast<long long>(r.rebuilds),
                static_cast<long long>(r.subcontacts), r.energy_error_rel, runtime_s);
  std::printf("  wrote %s/{summary.json, curve.csv%s}\n", out.string().c_str(),
              r.which == "reclose" ? "" : ", blocks_final.vtu");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  inputs in;
  tessera::cli::parser cli("verification",
                           "Verification problems of contacts that open, slide and meet again (rigid blocks under gravity\n"
                           "with detected contacts, or deformable ones with --deformable; reclose: the deformable prism on\n"
                           "its own faces):\n"
                           "  incline  a cube on a plane at --angle-deg with --friction-deg, undamped: sticks\n"
                           "           (slip < 1e-6 m) or slides with a = g (sin t - cos t tan phi) within 1 %\n"
                           "  topple   a block of width/height --aspect on the incline: topples iff tan t > b/h\n"
                           "  stack    --blocks cubes settling on a base: base reaction = total weight within 1e-6\n"
                           "  drop     a cube dropped --drop-height on a base: overlap at rest = W/(k_n A) within 1 %\n"
                           "  reclose  the study's 100-block prism cracked in tension, pushed back into compression\n"
                           "           and pulled again: compression at the intact stiffness within 2 %, no tension\n"
                           "           regained (the crack closes on its own faces; the other flags do not apply)\n"
                           "  bond     a cube bonded to the base (shear strength --cohesion c_0), tilted to --angle-deg:\n"
                           "           the bond fails at c_0 A within 1 %, then the broken face is an incline with\n"
                           "           --friction-deg (no cohesion regained): a within 1 % (or sticks)");
  cli.add_standard(in.common);
  cli.option("--case", in.scene.which, "verification problem", "NAME").one_of({"incline", "topple", "stack", "drop", "reclose", "bond"});
  cli.option("--angle-deg", in.scene.angle_deg, "incline angle theta (deg)", "DEG").within(0, 89.9);
  cli.option("--friction-deg", in.scene.friction_deg, "joint friction angle phi (deg)", "DEG").within(0, 89.9);
  cli.option("--aspect", in.scene.aspect, "topple: block width / height b/h", "R").greater_than(0).at_most(20);
  cli.option("--size", in.scene.size, "block edge (m); topple: the height h", "M").greater_than(0).at_most(100);
  cli.option("--blocks", in.scene.blocks, "stack: number of blocks in the column", "N").within(1, 200);
  cli.option("--damping", in.scene.damping,
             "local damping gamma in [0, 1]; -1 = the case's default (0 incline/topple; 0.8 stack/drop and the\n"
             "                      deformable incline below the friction angle)", "G")
      .within(-1, 1);
  cli.option("--duration", in.scene.duration, "simulated time (s); -1 = the case's default (deformable incline/topple: 0.4 s, at most 2)", "S").within(-1, 100);
  cli.option("--drop-height", in.scene.drop_height, "drop: initial gap under the cube (m)", "M").at_least(0);
  cli.option("--kn", in.scene.k_n, "joint normal stiffness k_n = k_s (Pa/m)", "K").greater_than(0).at_most(1e14);
  cli.option("--tolerance", in.scene.tolerance, "contact tolerance (m)", "M").greater_than(0);
  cli.flag("--deformable", in.scene.deformable,
           "incline, topple, stack, drop: deformable blocks (elastic tetrahedral zones) instead of rigid ones");
  cli.option("--young", in.scene.young, "deformable: Young's modulus of the blocks (Pa; Poisson's ratio 0.2)", "PA")
      .greater_than(0)
      .at_most(1e13);
  cli.option("--zone-edge", in.scene.zone_edge, "deformable: target zone edge (m); -1 = the block edge", "M");
  cli.option("--cohesion", in.scene.cohesion, "bond: cohesion c_0 of the bonded face (Pa)", "PA")
      .greater_than(0)
      .at_most(1e8);
  cli.parse_or_exit(argc, argv);
  in.scene.quick = in.common.quick;
  try {
    ver::validate(in.scene);  // before run.json or anything else is written
  } catch (const std::exception& e) {
    tessera::cli::print_error("verification", e);
    return 1;
  }
  tessera::io::run_record record(in.common.out, "verification", argc, argv);
  try {
    const int status = run(in);
    if (status == 0) record.complete();
    return status;
  } catch (const std::exception& e) {
    tessera::cli::print_error("verification", e);
    return 1;
  }
}
