#pragma once
// direct_tension's VTK fields: the contacts and zones at the peak and at the end of the first seed's
// run (tension_snapshot), and a ParaView series of both (direct_tension.pvd).

#include <filesystem>
#include <vector>

#include "common/scenes.hpp"
#include "direct_tension/tension_test.hpp"
#include "tessera/io/vtk.hpp"

namespace tessera::scenes {

/// The zones of `scene` with the displacement and stress of snapshot s.
inline void write_tension_zones_vtu(const std::filesystem::path& path, const prism_scene& scene, const tension_snapshot& s) {
  std::vector<io::vtk::sym_tensor> stress;
  const auto& zs = s.zone_stress;
  stress.reserve(static_cast<std::size_t>(zs.rows()));
  for (Eigen::Index z = 0; z < zs.rows(); ++z) stress.push_back(io::vtk::voigt_row_to_sym_tensor(zs, z));
  io::vtk::zone_fields fields;
  fields.displacement = &s.gridpoint_displacement;
  fields.stress = stress;
  io::vtk::write_zones_vtu(path, scene.mesh, fields);
}

/// Contact and zone snapshots at the peak and at the end, and a ParaView time series of both.
inline void write_tension_fields(const std::filesystem::path& out, const prism_scene& scene, const tension_result& r) {
  namespace io = tessera::io;
  r.at_peak.contacts.write(out / "contacts_peak.vtp");
  r.at_end.contacts.write(out / "contacts_end.vtp");
  write_tension_zones_vtu(out / "zones_peak.vtu", scene, r.at_peak);
  write_tension_zones_vtu(out / "zones_end.vtu", scene, r.at_end);
  io::vtk::pvd_collection pvd;
  pvd.add(r.at_peak.time, out / "zones_peak.vtu", 0);
  pvd.add(r.at_peak.time, out / "contacts_peak.vtp", 1);
  pvd.add(r.at_end.time, out / "zones_end.vtu", 0);
  pvd.add(r.at_end.time, out / "contacts_end.vtp", 1);
  pvd.write(out / "direct_tension.pvd");
}

}  // namespace tessera::scenes
