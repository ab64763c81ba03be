// compression: uniaxial (or triaxial) compression of a concrete cylinder or prism of random Voronoi
// blocks. --material names the concrete, a recipe of examples/calibrate --material: beam (the
// default; rc_beam: study_beam_params, f_c cap 35 MPa, semi-rigid zones of 10 x 25 GPa, faces zoned
// to a 30 mm edge) at the beam's block size, or prism (the study's prism: the 100-block Table 1
// contacts with f_T, c_0 times 0.907 as brazilian, power softening, no contact cap, zones of
// 10 x 28 GPa, one per face triangle) at the 100-block prism's block size, unless told otherwise.
//
// Specimen: a cylinder 150 x 300 mm (a 36-gon prism, axis z; EN 12390-3's cylinder, EC2's f_c) or
// a prism W x W x H. Ends (--ends):
//   fixed         every end gridpoint held in x, y and z: a platen with no slip (bonded);
//   frictionless  the ends held along z only (a platen with perfect lubrication), with one bottom
//                 gridpoint held in x and y and one in y, against rigid-body motion only;
//   friction      a rigid steel platen at each end (contact::rigid_platen) sliding at the Coulomb
//                 limit with --friction mu (0.1-0.2 for steel on concrete, greased to dry).
// The bottom end stays, the top end moves down at --rate (5 mm/s, quasi-static: masses scaled so it
// moves --step-displacement per step). --confinement p (Pa) holds a lateral pressure on the mantle
// (a dead load on every surface triangle of it, ramped in and settled before the axial loading):
// a triaxial test, for the slope of the strength envelope.
//
// Measured (summary.json, curve.csv): the axial stress sigma = P / A (P the top end's reaction)
// against the axial strain eps = u / H and the lateral strain (the mean outward displacement of
// the mantle's gridpoints over the middle half of the height, over the radius or half width);
// f_c the peak stress, counted as a peak only once the stress has fallen to (1 - --drop) f_c after
// it (otherwise "peak": false and f_c null: a plateau or a rising branch is not a strength); E the
// secant modulus between 10 % and 40 % of the peak (of the largest stress without a peak); nu =
// eps_lat / eps at 40 % (expansion over shortening). Cracked area (tensile damage >= 0.5 or slipped) by orientation: "axial"
// cracks have normals within 30 deg of the horizontal plane (splitting), the rest are inclined.
// Contact law (--law, --material beam): study, the beam's (study_beam_law: brittle Coulomb shear onto c_res, phi_res),
// or slip_softening (slip_softening_beam_law, docs/model.md: c_0 and phi_0 soften linearly with the
// plastic slip to c_res and --phi-res-deg, the slip scale set by the mode-II fracture energy --g-ii),
// or crushing (crushing_beam_law: slip_softening whose cap --cap softens linearly with the plastic
// closure to --cap-residual x --cap over the compressive fracture energy --g-c; --crush-shear scales
// the shear limit by the cap's remaining fraction too), or mixed_mode (presets::mixed_mode_beam_law: one
// damage for tension and shear over G_f and --g-ii; law/mixed_mode.hpp).
// --params FILE: the concrete of a calibrated.json entry (calibrate; common/concrete_set.hpp): law,
// strength and fracture-energy scales, c_0/f_T, phi_0, phi_res, G_II, cap (G_c, residual cap), for the recipe named by
// --material, --recipe-blocks and --zone-edge (refused, naming both values, if the file's differs).
// VTK (--no-vtk to skip): zones (displacement, stress) and contacts (every law field) at the end of the
// run (past the peak, or at --max-strain), end_zones.vtu and end_contacts.vtp in compression.pvd.
#include <tessera/analysis/curves.hpp>
#include <tessera/geometry/shapes.hpp>
#include <tessera/geometry/voronoi.hpp>
#include <tessera/geometry/zoning.hpp>
#include <tessera/io/json.hpp>
#include <tessera/io/run_record.hpp>
#include <tessera/presets/pulatsu2020.hpp>
#include <tessera/solver/recorders.hpp>
#include <tessera/solver/solver.hpp>

#include "common/cli.hpp"
#include "common/concrete_set.hpp"
#include "compression/specimen.hpp"

using namespace tessera;

namespace {
template <class Law>
int run_specimen(const scenes::compression_options& in, const scenes::concrete_set& set, const std::string& params,
                 const scenes::concrete_recipe<Law>& recipe, io::run_record& record);
}  // namespace

int main(int argc, char** argv) {
  scenes::compression_options in;
  cli::parser cli("compression", "Uniaxial or triaxial compression of a concrete cylinder or prism of Voronoi blocks "
                                 "(the beam's concrete): f_c, strain at peak, E, Poisson's ratio, softening.");
  cli.add_standard(in.common);
  cli.option("--material", in.material, "the concrete, a recipe of calibrate --material: beam (rc_beam's) or prism (the "
             "study's prism, no contact cap)", "M").one_of({"beam", "prism"});
  cli.option("--shape", in.shape, "cylinder (150 x 300 mm) or prism", "S").one_of({"cylinder", "prism"});
  cli.option("--diameter", in.width, "cylinder diameter or prism side (m)", "M").within(0.02, 2);
  cli.option("--height", in.height, "specimen height (m)", "M").within(0.02, 4);
  cli.option("--blocks", in.blocks, "Voronoi blocks; 0 = the material's block size (the default cylinder: 61 of the "
             "beam's, 190 of the prism's); else at least 2", "N")
      .within(0, 5000);
  cli.option("--ends", in.ends, "fixed, frictionless or friction (rigid steel platens)", "E")
      .one_of({"fixed", "frictionless", "friction"});
  cli.option("--friction", in.friction, "platen friction coefficient with --ends friction", "MU").within(0, 2);
  cli.option("--confinement", in.confinement, "lateral pressure on the mantle (Pa, compression positive)", "P")
      .within(0, 100e6);
  cli.option("--f-t", in.f_t, "contact tensile strength f_T (Pa); 0 = the material's (beam 2.5, prism 0.907 x 2.15 MPa)", "PA").within(0, 1e9);
  scenes::add_cohesion_ratio_flag(cli, in.cohesion_ratio);
  scenes::add_law_flags(cli, in, "--material beam only");  // --law, --g-ii, --phi-deg, --phi-res-deg, --cap
  cli.option("--rate", in.rate, "top end speed (m/s)", "V").within(1e-5, 0.1);
  cli.option("--step-displacement", in.step_displacement, "top end travel per step (m)", "DU").within(1e-10, 1e-7);
  cli.option("--max-strain", in.max_strain, "axial strain at which the run ends without a peak", "EPS")
      .within(1e-4, 0.05);
  cli.option("--drop", in.drop, "post-peak drop that ends the run and marks the peak, as a fraction of f_c", "F")
      .within(0.02, 0.9);
  cli.flag("--no-vtk", in.no_vtk, "write no VTK files");
  std::string params;
  scenes::concrete_set set;
  cli.option("--recipe-blocks", set.recipe_blocks, "the recipe's block count (calibrate --blocks): its contacts and block "
             "size; 0 = prism 100, beam 250; else at least 8", "N").within(0, 750);
  cli.option("--zone-edge", set.zone_edge, "beam: the recipe's face zoning edge (m; calibrate --zone-edge); default 0.03",
             "M").within(0, 1);
  cli.option("--params", params, "calibrate's calibrated.json: the concrete (law, scales, c_0/f_T, phi_0, phi_res, G_II, "
             "cap) of its entry for this recipe, instead of the concrete flags", "FILE");
  cli.parse_or_exit(argc, argv);
  for (const char* flag : {"--f-t", "--cohesion-ratio", "--phi-deg", "--phi-res-deg", "--law", "--g-ii", "--cap", "--g-c",
                           "--cap-residual", "--crush-shear"})
    if (!params.empty() && cli.given(flag)) {
      std::fprintf(stderr, "compression: %s with --params %s: the file sets the concrete (drop the flag)\n", flag, params.c_str());
      return 2;
    }
  if (in.material == "prism" && cli.given("--zone-edge")) {
    std::fprintf(stderr, "compression: --zone-edge %g applies to --material beam only (the prism's recipe has one zone "
                 "per face triangle)\n", set.zone_edge);
    return 2;
  }
  if (in.common.quick) {  // a coarser step and a shorter softening branch: the CTest
    if (!cli.given("--step-displacement")) in.step_displacement = 5e-9;
    if (!cli.given("--drop")) in.drop = 0.1;
  }
  if (in.common.threads > 0) set_threads(in.common.threads);
  if (in.material == "prism" && cli.given("--cap")) {
    std::fprintf(stderr, "compression: --cap %g applies to --material beam only (the prism's contacts have no cap)\n", in.cap);
    return 2;
  }
  if (in.material == "prism" && scenes::concrete_law_named(in.law, "compression").beam_only) {
    std::fprintf(stderr, "compression: --law %s applies to --material beam only (the prism's concrete has the study's law)\n",
                 in.law.c_str());
    return 2;
  }
  try {
    scenes::require_law_flags(cli, "compression", in.law, in.g_c);
    scenes::require_recipe_blocks("compression", set.recipe_blocks);
  } catch (const std::exception& e) {
    cli::print_error("compression", e);
    return 2;
  }
  if (in.blocks == 1) {  // one block has no contact: nothing to crack, crush or slide
    std::fprintf(stderr, "compression: --blocks 1 must be 0 (the material's block size) or >= 2 (one block has no contact)\n");
    return 2;
  }
  set.material = in.material;
  scenes::concrete_set_from(in, set);
  if (!params.empty()) {
    try {
      scenes::load_concrete_params(set, params, in.step_displacement, in.rate, "compression");
    } catch (const std::exception& e) {
      cli::print_error("compression", e);
      return 2;
    }
    scenes::concrete_set_to(set, in);
  }
  io::run_record record(in.common.out, "compression", argc, argv);
  try {
    return scenes::with_concrete(set, [&](const auto& recipe) { return run_specimen(in, set, params, recipe, record); });
  } catch (const std::exception& e) {
    cli::print_error("compression", e);
    return 1;
  }
}

namespace {

template <class Law>
int run_specimen(const scenes::compression_options& in, const scenes::concrete_set& set, const std::string& params,
                 const scenes::concrete_recipe<Law>& recipe, io::run_record& record) {
  {
    scenes::compression_specimen<Law> sp(in, recipe);
    const scenes::compression_result r = sp.run();
    io::summary_json j;
    scenes::write_compression_summary(j, in, sp, r);
    j.set("params", params.empty() ? "flags" : params).set("recipe_blocks", set.blocks())
        .set("strength_scale", set.scale()).set("fracture_energy_scale", set.fracture_energy_scale);
    j.write(std::filesystem::path(in.common.out) / "summary.json");
    record.complete();
    std::printf("compression: %s concrete (%s law), %s, %d blocks, %s ends%s: %s; E %.1f GPa, nu %.3f; %lld steps, %.1f s\n",
                in.material.c_str(), in.law.c_str(), in.shape.c_str(), static_cast<int>(sp.block_count()), in.ends.c_str(),
                in.confinement > 0 ? tessera::detail::concat(", confined at ", in.confinement * 1e-6, " MPa").c_str() : "",
                r.peak ? tessera::detail::concat("f_c ", r.peak_stress * 1e-6, " MPa at strain ", r.peak_strain).c_str()
                       : tessera::detail::concat("no peak up to strain ", r.last_strain, " (largest stress ",
                                                 r.peak_stress * 1e-6, " MPa)").c_str(),
                r.young * 1e-9, r.poisson, static_cast<long long>(r.steps), r.runtime_s);
    return 0;
  }
}

}  // namespace
