#pragma once
// The cost of a run per entity and per phase, as every driver's summary.json reports it
// (solver::phases(), solver/solver.hpp):
//   ns_per_zone_step        zone time / (zones x steps)            (per core: thread time)
//   ns_per_subcontact_step  contact time / (sub-contacts x steps)
//   phase_<name>_s          time in zones, contacts, bars, integration, recorders (s)
// On one thread these are the per-core costs; on several, the zone and contact times are summed
// over threads, so the per-entity figures stay per-core costs.

#include <cstdint>

#include "tessera/io/json.hpp"
#include "tessera/solver/solver.hpp"

namespace tessera::scenes {

inline void set_phase_figures(io::summary_json& js, const phase_times& p, index_t zones, index_t subcontacts,
                              std::int64_t steps) {
  const auto per = [&](double seconds, index_t entities) {
    return entities > 0 && steps > 0 ? seconds * 1e9 / (static_cast<double>(entities) * static_cast<double>(steps)) : 0.0;
  };
  js.set("ns_per_zone_step", per(p.zones, zones))
      .set("ns_per_subcontact_step", per(p.contacts, subcontacts))
      .set("phase_zones_s", p.zones)
      .set("phase_contacts_s", p.contacts)
      .set("phase_bars_s", p.bars)
      .set("phase_integration_s", p.integration)
      .set("phase_recorders_s", p.recorders);
}

}  // namespace tessera::scenes
