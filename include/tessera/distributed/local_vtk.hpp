#pragma once
// distributed::write_zones_pvtu: the zones of a run on local models (distributed/local_model.hpp)
// as one parallel VTK dataset, without gathering the model anywhere: each rank writes the zones of
// its own blocks as a piece, `<stem>_<rank>.vtu` beside `<stem>.pvtu`, and rank 0 writes the .pvtu
// that lists the pieces once every rank has written its own. ParaView opens the .pvtu as the whole
// model (docs/guide.md, "Local storage per rank"):
//
//   distributed::write_zones_pvtu("results/split/end_zones.pvtu", lm, s, MPI_COMM_WORLD);
//
// A piece holds the own blocks' gridpoints (reference positions) and zones. Point data:
// `gridpoint` (Int32, the whole model's id) and `displacement` (m); cell data: `block` (Int32, the
// whole model's id) and, for deformable blocks, `stress` (Pa, tension positive, VTK's component
// order). A ghost block is in no piece: each block appears once. Every file is written atomically;
// the .pvtu is written only after every piece, so a killed or failed run leaves no .pvtu that
// names a missing piece. Only where MPI is built in (TESSERA_HAVE_MPI).

#ifdef TESSERA_HAVE_MPI
#include <mpi.h>

#include <bit>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "../core/errors.hpp"
#include "../io/atomic_file.hpp"
#include "../io/vtk.hpp"
#include "local_model.hpp"

namespace tessera::distributed {

/// The piece of rank r of `pvtu` (path/stem.pvtu): path/stem_r.vtu.
[[nodiscard]] inline std::filesystem::path pvtu_piece(const std::filesystem::path& pvtu, int r) {
  return pvtu.parent_path() / (pvtu.stem().string() + "_" + std::to_string(r) + ".vtu");
}

/// Writes the zones of this rank's own blocks of `lm` (solver `s` built on it: its gridpoints'
/// displacements and, for deformable blocks, its zone stresses, current after the last step) as
/// piece pvtu_piece(pvtu, rank), then, on rank 0, `pvtu` (file comment). Every rank of `comm` must
/// call it. The folder must exist (io::ensure_directory on one rank, then a barrier). Throws
/// invalid_input (every rank alike) when `pvtu` does not end in .pvtu, and io_error on every rank,
/// naming the ranks whose files failed, when any rank could not write (a missing folder, a full
/// disk; the .pvtu is then not written). O(own zones and gridpoints); allocates the piece.
template <class Solver>
void write_zones_pvtu(const std::filesystem::path& pvtu, const local_model& lm, const Solver& s, MPI_Comm comm,
                      io::vtk::format fmt = io::vtk::format::binary) {
  require(pvtu.extension() == ".pvtu", "write_zones_pvtu: '", pvtu.string(), "' must end in .pvtu");
  const geometry::block_mesh& mesh = lm.mesh;
  require(s.gridpoints().size() == mesh.gridpoint_count(), "write_zones_pvtu: the solver has ", s.gridpoints().size(),
          " gridpoints, the local model ", mesh.gridpoint_count());
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  const auto& zs = s.blocks().zone_stress();
  const bool stressed = zs.rows() == mesh.zone_count() && mesh.zone_count() > 0;
  const auto at = [](index_t i) { return static_cast<std::size_t>(i); };
  std::string failure;
  try {
    // Own gridpoints, compacted in local (= global) order, and the own zones on them.
    std::vector<index_t> piece_of(at(mesh.gridpoint_count()), invalid_index);
    std::vector<vec3> points;
    std::vector<std::int32_t> gridpoint_id, block_id;
    std::vector<vec3> displacement;
    for (index_t g = 0; g < mesh.gridpoint_count(); ++g) {
      if (!lm.owns_gridpoint(g)) continue;
      piece_of[at(g)] = static_cast<index_t>(points.size());
      points.push_back(mesh.gridpoints[at(g)]);
      gridpoint_id.push_back(static_cast<std::int32_t>(lm.global_gridpoint(g)));
      displacement.emplace_back(s.gridpoints().displacement.row(g).transpose());
    }
    io::vtk::unstructured_grid grid;
    std::vector<io::vtk::sym_tensor> stress;
    for (index_t z = 0; z < mesh.zone_count(); ++z) {
      const index_t b = mesh.zone_block[at(z)];
      if (lm.block_rank(b) != rank) continue;
      const auto& zone = mesh.zones[at(z)];
      grid.add_cell(io::vtk::cell_type::tetra,
                    {piece_of[at(zone[0])], piece_of[at(zone[1])], piece_of[at(zone[2])], piece_of[at(zone[3])]});
      block_id.push_back(static_cast<std::int32_t>(lm.global_block(b)));
      if (stressed) stress.push_back(io::vtk::voigt_row_to_sym_tensor(zs, z));
    }
    grid.set_points(std::move(points));
    grid.point_data.add_scalar("gridpoint", std::span<const std::int32_t>(gridpoint_id));
    grid.point_data.add_vector("displacement", std::span<const vec3>(displacement));
    grid.cell_data.add_scalar("block", std::span<const std::int32_t>(block_id));
    if (stressed) grid.cell_data.add_tensor("stress", stress);
    grid.write(pvtu_piece(pvtu, rank), fmt);
  } catch (const std::exception& e) {
    failure = e.what();
  }
  // Every rank learns whether all pieces exist before rank 0 names them.
  const auto agree = [&](const std::string& what) {
    int mine = failure.empty() ? 0 : 1;
    std::vector<int> all(static_cast<std::size_t>(ranks));
    MPI_Allgather(&mine, 1, MPI_INT, all.data(), 1, MPI_INT, comm);
    std::string failed;
    for (int r = 0; r < ranks; ++r)
      if (all[static_cast<std::size_t>(r)] != 0) failed += (failed.empty() ? "" : ", ") + std::to_string(r);
    if (!failed.empty())
      throw io_error(tessera::detail::concat("write_zones_pvtu: ", what, " failed on rank(s) ", failed,
                                             failure.empty() ? std::string() : "; here: " + failure));
  };
  agree("a piece");
  if (rank == 0) {
    try {
      io::atomic_ofstream file(pvtu);
      std::ostream& os = file.stream();
      os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\""
         << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
         << "\" header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n"
         << "    <PPointData>\n      <PDataArray type=\"Int32\" Name=\"gridpoint\" NumberOfComponents=\"1\"/>\n"
         << "      <PDataArray type=\"Float64\" Name=\"displacement\" NumberOfComponents=\"3\"/>\n    </PPointData>\n"
         << "    <PCellData>\n      <PDataArray type=\"Int32\" Name=\"block\" NumberOfComponents=\"1\"/>\n"
         << (stressed ? "      <PDataArray type=\"Float64\" Name=\"stress\" NumberOfComponents=\"6\"/>\n" : "")
         << "    </PCellData>\n    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
      for (int r = 0; r < ranks; ++r) os << "    <Piece Source=\"" << pvtu_piece(pvtu, r).filename().string() << "\"/>\n";
      os << "  </PUnstructuredGrid>\n</VTKFile>\n";
      file.commit();
    } catch (const std::exception& e) {
      failure = e.what();
    }
  }
  agree("the .pvtu");
}

}  // namespace tessera::distributed

#endif  // TESSERA_HAVE_MPI
