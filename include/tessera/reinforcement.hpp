#pragma once
// Module header for reinforcement/. Owners add their headers here as they land.
#include "core.hpp"
#include "reinforcement/concepts.hpp"
#include "reinforcement/none.hpp"
#include "reinforcement/bar.hpp"
#include "reinforcement/truss.hpp"
#include "reinforcement/bond.hpp"
#include "reinforcement/embedding.hpp"
#include "reinforcement/embedded_truss.hpp"
