#pragma once
// Module header for io/. Owners add their headers here as they land.
#include "core.hpp"
#include "io/atomic_file.hpp"
#include "io/csv.hpp"
#include "io/json.hpp"
#include "io/json_reader.hpp"
#include "io/plot.hpp"
#include "io/vtk.hpp"
#include "io/neper.hpp"
#include "io/vtk_contacts.hpp"
#include "io/checkpoint.hpp"
