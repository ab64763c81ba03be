#pragma once
// Module header for blocks/. Owners add their headers here as they land.
#include "core.hpp"
#include "blocks/concepts.hpp"
#include "blocks/linear_elastic_tet.hpp"
#include "blocks/deformable.hpp"
#include "blocks/rigid.hpp"
