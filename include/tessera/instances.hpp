#pragma once
// The solvers most scenes use, compiled once into the tessera::instances library (issue #40:
// a small scene compiled in about a minute, most of it instantiating and optimising the
// solver). Opt in by including this header and linking tessera::instances:
//
//   target_link_libraries(my_scene PRIVATE tessera::instances)   # brings tessera::tessera
//   #include <tessera/instances.hpp>
//   tessera::instances::rigid_dry_solver s(tess, mesh, blocks::rigid::params{2400},  // kg/m^3
//       {law::dry_joint(1e10, 1e10, law::friction_angle::from_degrees(30)), 1e-3});  // Pa/m, Pa/m, phi; tolerance m
//
// Each alias below is declared `extern template` here and defined once in the library
// (src/instances.cpp), so a translation unit that includes this header does not emit the
// solver's out-of-line members again; the type is the same as the one spelled out in full, so
// a scene that writes `solver<blocks::rigid, contact::detected_contacts<law::dry_joint_law>, ...>`
// gets the compiled copy too. A solver type not listed here is compiled in the user's
// translation unit as before. The library is built with the flags of the build that makes it
// (one definition per program: link one tessera::instances, built with the compiler and
// -march flags of the rest of the program). A scene of one family may include only its header,
// <tessera/instances/rigid.hpp> or <tessera/instances/prism.hpp>, and parse less. The prism with
// bars (instances/tie.hpp), the study's beam with bars (instances/beam.hpp) and the deformable
// blocks on detected contacts (instances/deformable_detected.hpp) have headers of their own too.
#include "instances/beam.hpp"
#include "instances/deformable_detected.hpp"
#include "instances/prism.hpp"
#include "instances/rigid.hpp"
#include "instances/tie.hpp"
