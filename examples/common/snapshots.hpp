#pragma once
// VTK snapshots of a running solver, listed in one ParaView .pvd series: at each tag (drop1,
// yield, end, ...) the sub-contacts with every declared law field (<tag>_contacts.vtp), the bars
// as polylines where the solver has them (<tag>_bar.vtp) and the zones with displacement
// and stress (<tag>_zones.vtu). Used by rc_tie and rc_beam as their on_event callback, and by
// compression. The tag "start" (the run's checks have passed, its first step is next) writes no
// snapshot: it creates the output directory, so run.json says "running" from the run's first minute.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "tessera/geometry/block_mesh.hpp"
#include "tessera/io/atomic_file.hpp"
#include "tessera/io/vtk.hpp"
#include "tessera/io/vtk_contacts.hpp"

namespace tessera::scenes {

class bar_snapshots {
 public:
  /// `mesh` must outlive the writer; `series` is the .pvd file name (e.g. "tie.pvd").
  bar_snapshots(std::filesystem::path dir, const geometry::block_mesh& mesh, std::string series, bool enabled)
      : dir_(std::move(dir)), mesh_(&mesh), series_(std::move(series)), enabled_(enabled) {}

  template <class Solver>
  void operator()(const Solver& s, const std::string& tag) {
    namespace vtk = io::vtk;
    if (tag == "start") {
      io::ensure_directory(dir_);
      return;
    }
    if (!enabled_) return;
    io::ensure_directory(dir_);
    const real t = s.time();
    contacts_.take(s.contacts(), s.gridpoints());
    contacts_.write(dir_ / (tag + "_contacts.vtp"), vtk::format::binary);
    pvd_.add(t, dir_ / (tag + "_contacts.vtp"), 1);
    if constexpr (Solver::reinforcement_type::enabled) {  // a scene without bars writes none
      vtk::write_bar_vtp(dir_ / (tag + "_bar.vtp"), s.reinforcement());
      pvd_.add(t, dir_ / (tag + "_bar.vtp"), 2);
    }
    // Zones with displacement and stress (empty for rigid blocks).
    std::vector<vtk::sym_tensor> stress;
    const auto& zs = s.blocks().zone_stress();
    for (Eigen::Index z = 0; z < zs.rows(); ++z) stress.push_back(vtk::voigt_row_to_sym_tensor(zs, z));
    vtk::zone_fields fields;
    fields.displacement = &s.gridpoints().displacement;
    fields.stress = stress;
    vtk::write_zones_vtu(dir_ / (tag + "_zones.vtu"), *mesh_, fields, vtk::format::binary);
    pvd_.add(t, dir_ / (tag + "_zones.vtu"), 0);
    pvd_.write(dir_ / series_);
    tags_.push_back(tag);
  }
  [[nodiscard]] const std::vector<std::string>& tags() const { return tags_; }

 private:
  std::filesystem::path dir_;
  const geometry::block_mesh* mesh_;
  std::string series_;
  bool enabled_;
  io::vtk::pvd_collection pvd_;
  io::vtk::contact_snapshot contacts_;  ///< reused between snapshots
  std::vector<std::string> tags_;
};

}  // namespace tessera::scenes
