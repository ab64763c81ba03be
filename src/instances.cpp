// The one definition of the solvers include/tessera/instances.hpp declares extern: the
// tessera::instances library (CMakeLists.txt). Nothing else belongs here.
#define TESSERA_INSTANCES_DEFINE
#include "tessera/instances.hpp"
