#pragma once
// Module header for law/. Owners add their headers here as they land.
#include "core.hpp"
#include "law/concepts.hpp"
#include "law/tension.hpp"
#include "law/compression.hpp"
#include "law/shear.hpp"
#include "law/slip_softening.hpp"
#include "law/mixed_mode.hpp"
#include "law/cohesive_frictional.hpp"
#include "law/with_elastic_packs.hpp"
#include "law/joints.hpp"
