// tessellate: random Voronoi tessellation of a box into convex polyhedral blocks, each split
// into constant-strain tetrahedral zones: the geometry every tessera scene starts from.
//
// Default specimen: the reference study's prism, 0.068 x 0.068 x 0.6 m, 100 blocks
// (Pulatsu et al. 2020, Sec. 3), raw Voronoi cells as the simulations use them (--regularize 0;
// --regularize 0.2, presets::study_regularization, collapses edges shorter than 0.2 of the mean
// cell size as Neper does, which warps faces: geometry/regularize.hpp).
//
// Outputs in --out DIR:
//   blocks.vtu    polyhedral cells (VTK type 42) with cell data block, volume
//   zones.vtu     tetrahedral zones with cell/point data block
//   summary.json  inputs, tessellation checks (volume_error_rel, unmatched_faces, face warp and
//                 non-convexity after --regularize), zone quality,
//                 runtime_s (tessellation + zoning wall time)
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>

#include "common/cli.hpp"
#include "tessera/core/parallel.hpp"
#include "tessera/geometry/regularize.hpp"
#include "tessera/presets.hpp"
#include "tessera/geometry/tessellation_queries.hpp"
#include "tessera/geometry/voronoi.hpp"
#include "tessera/geometry/zoning.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/run_record.hpp"
#include "tessera/io/json.hpp"
#include "tessera/io/vtk.hpp"

namespace {

struct inputs {
  tessera::cli::standard_options common;
  int blocks = 100;
  std::array<double, 3> size{0.068, 0.068, 0.6};  // m
  int lloyd = 0;
  double min_spacing = 0.0;                        // m
  double target_edge = 0.0;                        // m, 0 = one zone per face triangle
  // collapse edges shorter than this x the mean cell size (geometry/regularize.hpp), 0 = off
  double regularize = 0;  // as the simulations (direct_tension, rc_tie) default
  bool allow_large = false;  // --allow-large: skip the memory estimate
};

namespace geo = tessera::geometry;

/// Size guard, before anything is written (tessellate --edge): throws invalid_input when the
/// zoning would need more than 8 GiB, unless --allow-large.
void check_size(const inputs& in) {
  // a zone edge h over a box of volume V makes about
  // V / (h^3 / (6 sqrt 2)) tetrahedra (regular ones); each costs about 1 KiB across the zoning and
  // the solver's arrays (measured: 3004 zones of the 100-block prism, ~3 MB).
  if (in.target_edge > 0 && !in.allow_large) {
    const double volume = in.size[0] * in.size[1] * in.size[2];
    const double zones = volume / (in.target_edge * in.target_edge * in.target_edge / (6 * std::sqrt(2.0)));
    const double bytes = 1024 * zones;
    const double limit = 8.0 * 1024 * 1024 * 1024;
    tessera::require(bytes <= limit, "tessellate: --edge ", in.target_edge, " m over a ", in.size[0], " x ", in.size[1],
                     " x ", in.size[2], " m box makes about ", zones, " zones, an estimated ", bytes / (1 << 30),
                     " GiB (limit 8 GiB); choose a larger --edge or pass --allow-large");
  }
}

/// What tessellate measures of its tessellation and zoning.
struct measures {
  geo::tessellation_report report;
  geo::zone_quality q;
  std::int64_t boundary_faces = 0, subcontacts = 0;
  double tessellation_s = 0, runtime_s = 0;
};
measures measure(const geo::tessellation& tess, const geo::block_mesh& mesh, double tessellation_s, double runtime_s) {
  const geo::tessellation_report report = geo::check(tess);
  const geo::zone_quality q = geo::quality(mesh);
  std::int64_t boundary_faces = 0;
  for (tessera::index_t f = 0; f < tess.face_count(); ++f) boundary_faces += tess.is_boundary_face(f);
  // One sub-contact per face-node pair of a shared face (the study: 3808 for 100 blocks).
  std::int64_t subcontacts = 0;
  for (const auto& sf : tess.shared_faces)
    subcontacts += mesh.face_node_offsets[static_cast<std::size_t>(sf.face_a) + 1] - mesh.face_node_offsets[static_cast<std::size_t>(sf.face_a)];

  return {report, q, boundary_faces, subcontacts, tessellation_s, runtime_s};
}

/// summary.json (one key per line: the file's schema).
void write_summary(const std::filesystem::path& out, const inputs& in, const geo::tessellation& tess,
                   const geo::block_mesh& mesh, const measures& m) {
  namespace io = tessera::io;
  const geo::tessellation_report& report = m.report;
  const geo::zone_quality& q = m.q;
  const std::int64_t boundary_faces = m.boundary_faces, subcontacts = m.subcontacts;
  const double tessellation_s = m.tessellation_s, runtime_s = m.runtime_s;
  io::summary_json s;
  s.set("example", "tessellate")
      .set("blocks_requested", in.blocks)
      .set("seed", in.common.seed)
      .set("size_m", std::vector<double>{in.size[0], in.size[1], in.size[2]})
      .set("lloyd_iterations", in.lloyd)
      .set("min_spacing_m", in.min_spacing)
      .set("target_edge_length_m", in.target_edge)
      .set("regularize_min_edge_rel", in.regularize)
      .set("quick", in.common.quick)
      .set("threads", tessera::max_threads())
      .set("blocks", tess.cell_count())
      .set("faces", tess.face_count())
      .set("faces_shared", static_cast<std::int64_t>(tess.shared_faces.size()))
      .set("faces_boundary", boundary_faces)
      .set("vertices", tess.vertex_count())
      .set("volume_error_rel", report.volume_error_rel)
      .set("unmatched_faces", report.unmatched_faces)
      .set("open_cells", report.open_cells)
      .set("nonconvex_cells", report.nonconvex_cells)
      .set("min_face_area_m2", report.min_face_area)
      .set("min_edge_length_m", report.min_edge_length)
      .set("max_face_warp_m", report.max_face_warp)
      .set("max_nonconvexity_m", report.max_nonconvexity)
      .set("gridpoints", mesh.gridpoint_count())
      .set("zones", q.zones)
      .set("face_nodes", static_cast<std::int64_t>(mesh.face_nodes.size()))
      .set("subcontacts", subcontacts)
      .set("zones_per_block_min", q.min_zones_per_block)
      .set("zones_per_block_mean", q.mean_zones_per_block)
      .set("zones_per_block_max", q.max_zones_per_block)
      .set("min_zone_volume", q.min_zone_volume)
      .set("min_dihedral_deg", q.min_dihedral_deg)
      .set("max_dihedral_deg", q.max_dihedral_deg)
      .set("min_volume_ratio", q.min_volume_ratio)
      .set("mean_volume_ratio", q.mean_volume_ratio)
      .set("fraction_volume_ratio_below_0_1", q.fraction_below_ratio_0_1)
      .set("max_zone_edge_m", q.max_edge_length)
      .set("tessellation_s", tessellation_s)
      .set("runtime_s", runtime_s);
  s.write(out / "summary.json");
}

void print_report(const std::filesystem::path& out, const inputs& in, const geo::tessellation& tess,
                  const geo::block_mesh& mesh, const measures& m) {
  const geo::tessellation_report& report = m.report;
  const geo::zone_quality& q = m.q;
  const std::int64_t boundary_faces = m.boundary_faces, subcontacts = m.subcontacts;
  const double tessellation_s = m.tessellation_s, runtime_s = m.runtime_s;
  std::printf("tessellate: %d blocks in %.4g x %.4g x %.4g m (seed %llu, Lloyd %d)\n", tess.cell_count(), in.size[0],
              in.size[1], in.size[2], static_cast<unsigned long long>(in.common.seed), in.lloyd);
  std::printf("  faces %d (%zu shared, %lld on the boundary), vertices %d\n", tess.face_count(), tess.shared_faces.size(),
              static_cast<long long>(boundary_faces), tess.vertex_count());
  std::printf("  volume_error_rel %.3e, unmatched_faces %d, open_cells %d\n", report.volume_error_rel,
              report.unmatched_faces, report.open_cells);
  std::printf("  min edge %.3g m, max face warp %.3g m, max non-convexity %.3g m (regularize %g)\n",
              report.min_edge_length, report.max_face_warp, report.max_nonconvexity, in.regularize);
  std::printf("  zones %d (per block min/mean/max %d / %.2f / %d), gridpoints %d, sub-contacts %lld\n", q.zones,
              q.min_zones_per_block, q.mean_zones_per_block, q.max_zones_per_block, mesh.gridpoint_count(),
              static_cast<long long>(subcontacts));
  std::printf("  min zone volume %.3e m^3, min dihedral %.3g deg, volume ratio min %.3g mean %.3f (%.1f%% below 0.1)\n",
              q.min_zone_volume, q.min_dihedral_deg, q.min_volume_ratio, q.mean_volume_ratio,
              100.0 * q.fraction_below_ratio_0_1);
  std::printf("  runtime_s %.4f (tessellation %.4f, zoning %.4f)\n", runtime_s, tessellation_s, runtime_s - tessellation_s);
  std::printf("  wrote %s/{blocks.vtu, zones.vtu, summary.json}\n", out.string().c_str());
}

int run(const inputs& in) {
  namespace io = tessera::io;
  const std::filesystem::path out = in.common.out;
  check_size(in);
  io::ensure_directory(out);
  if (in.common.threads > 0) tessera::set_threads(in.common.threads);

  tessera::aabb box;
  box.lo = tessera::vec3::Zero();
  box.hi = tessera::vec3(in.size[0], in.size[1], in.size[2]);
  geo::tessellation_options topt;
  topt.lloyd_iterations = in.lloyd;
  topt.min_spacing = in.min_spacing;
  topt.min_edge_rel = in.regularize;
  geo::zoning_options zopt;
  zopt.target_edge_length = in.target_edge;

  // ---- geometry ----
  const tessera::cli::wall_timer timer;
  const geo::tessellation tess = geo::random_voronoi(box, in.blocks, in.common.seed, topt);
  const double tessellation_s = timer.seconds();
  const geo::block_mesh mesh = geo::zone_blocks(tess, zopt);
  const double runtime_s = timer.seconds();

  const measures m = measure(tess, mesh, tessellation_s, runtime_s);
  // ---- outputs ----
  io::vtk::write_blocks_vtu(out / "blocks.vtu", tess);
  io::vtk::write_zones_vtu(out / "zones.vtu", mesh);
  write_summary(out, in, tess, mesh, m);

  print_report(out, in, tess, mesh, m);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  inputs in;
  tessera::cli::parser cli("tessellate",
                           "Random Voronoi tessellation of a box into convex blocks, zoned into tetrahedra.\n"
                           "Default: the reference study's 68 x 68 x 600 mm prism with 100 blocks.");
  cli.add_standard(in.common);
  cli.option("--blocks", in.blocks, "number of blocks (Voronoi generators)", "N").within(1, 1000000);
  cli.option("--size", in.size, "box edge lengths (m)", {"LX", "LY", "LZ"}).greater_than(0);
  cli.option("--lloyd", in.lloyd, "Lloyd relaxation iterations (more uniform blocks)", "K").within(0, 1000);
  cli.option("--min-spacing", in.min_spacing, "minimum distance between generators (m), 0 = none", "D").at_least(0);
  cli.option("--edge", in.target_edge, "target zone edge length (m), 0 = no refinement", "H").at_least(0);
  cli.option("--regularize", in.regularize,
             "collapse edges shorter than REL x mean cell size, 0 = off (raw Voronoi)", "REL").within(0, tessera::geometry::max_regularization);
  cli.flag("--allow-large", in.allow_large, "skip the memory estimate that refuses zonings over 8 GiB");
  cli.parse_or_exit(argc, argv);
  if (in.common.quick && !cli.given("--blocks")) in.blocks = 20;  // a given --blocks is kept
  // run.json is written when the output directory is created (after the checks), listing each
  // file as it is written; "complete" after summary.json, "interrupted" on SIGINT/SIGTERM.
  tessera::io::run_record record(in.common.out, "tessellate", argc, argv);
  try {
    const int status = run(in);
    if (status == 0) record.complete();
    return status;
  } catch (const std::exception& e) {
    tessera::cli::print_error("tessellate", e);
    return 1;
  }
}
