#pragma once
// The study's RC beam solvers of tessera::instances (tessera/instances.hpp gathers them with the
// others): deformable blocks on bonded faces with the beam's law (linear tension softening, a
// plastic compressive cap, Coulomb friction with residual values) on the contact set's elastic
// pack path, and steel bars embedded in the zones; the solver examples/rc_beam runs with the
// study's law (presets::study_beam_law, presets::study_beam_params). Link tessera::instances.
#include "../law/compression.hpp"
#include "../law/tension.hpp"
#include "../law/with_elastic_packs.hpp"
#include "tie.hpp"

namespace tessera::instances {

/// The study's beam law (Sec. 4): linear tension softening (f_T, G_f), a plastic compressive cap
/// f_c, Coulomb friction with residual values (c_0, phi_0, then c_res, phi_res); the same type as
/// presets::study_beam_law, whose parameters presets::study_beam_params(blocks) gives (Pa/m, Pa,
/// J/m^2).
using beam_law = law::cohesive_frictional<law::linear_softening, law::plastic_cap, law::coulomb_residual>;
/// The beam's contacts: the tessellation's bonded faces with beam_law on the elastic pack path
/// (law::with_elastic_packs: the same bits as the plain law without FMA contraction), the type
/// presets::bonded_faces<study_beam_law> names and examples/rc_beam builds.
using beam_contacts = contact::face_contacts<law::with_elastic_packs<beam_law>>;
/// The study's RC beam: deformable linear-elastic tetrahedral blocks, beam_contacts, steel bars as
/// embedded trusses with a Coulomb bond (reinforcement::embedded_truss<coulomb_bond>), central
/// differences with local damping: examples/rc_beam's solver with the study's law (its
/// scenes::beam_solver<presets::study_beam_law>). Load it through contact::rigid_platen<beam_law>
/// plates (registered forces) or prescribed velocities.
using beam_solver = solver<blocks::deformable<zones::linear_elastic_tet>, beam_contacts,
                           reinforcement::embedded_truss<reinforcement::coulomb_bond>>;
/// The beam undamped (integrator::no_damping): the reinforced beam's dynamics (free vibration,
/// impact) with the energy kept.
using beam_undamped_solver = solver<blocks::deformable<zones::linear_elastic_tet>, beam_contacts,
                                    reinforcement::embedded_truss<reinforcement::coulomb_bond>,
                                    integrator::central_difference<integrator::no_damping>>;

}  // namespace tessera::instances

TESSERA_SOLVER_INSTANCE(tessera::instances::beam_solver)
TESSERA_SOLVER_INSTANCE(tessera::instances::beam_undamped_solver)
TESSERA_INSTANCE(class tessera::contact::face_contacts<tessera::law::with_elastic_packs<tessera::instances::beam_law>>)
