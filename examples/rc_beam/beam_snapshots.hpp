#pragma once
// rc_beam's VTK snapshots at its events (common/snapshots.hpp: zones, contacts, bars, beam.pvd) and
// the cracked sub-contacts at the end, which main writes to cracks.csv and cracks.png.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "common/snapshots.hpp"
#include "rc_beam/beam.hpp"
#include "rc_beam/beam_cracks.hpp"
#include "tessera/analysis/cracks.hpp"

namespace tessera::scenes {

/// The beam's VTK snapshots (common/snapshots.hpp), and the cracked sub-contacts at the end.
class beam_snapshot_writer {
 public:
  beam_snapshot_writer(std::filesystem::path dir, const beam_scene& scene, bool enabled)
      : vtk_(std::move(dir), scene.mesh, "beam.pvd", enabled) {}
  template <class Solver>
  void operator()(const Solver& s, const std::string& tag) {
    vtk_(s, tag);
    if (tag == "end") final_contacts(s);
  }
  /// Softened sub-contacts at the end (side view) and their opening (m).
  std::vector<real> crack_x, crack_y, crack_w;

 private:
  template <class Solver>
  void final_contacts(const Solver& s) {
    const auto& c = s.contacts();
    const auto& gp = s.gridpoints();
    for (index_t i = 0; i < c.size(); ++i) {
      const real w = subcontact_opening(c, gp, i);
      if (!analysis::crack_graph::past_peak(c.state(i).flags)) continue;
      const vec3 p = c.position(i, gp);
      crack_x.push_back(p.x()), crack_y.push_back(p.y()), crack_w.push_back(w);
    }
  }
  bar_snapshots vtk_;
};

}  // namespace tessera::scenes
